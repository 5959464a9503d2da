// Helpers around the finder: the static-bias simulation of a case without lab data, the value
// lattice of raw increments, and SG#3 from a per-bin contribution.
#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "graftnav/mismatch/diagnosis.h"
#include "graftnav/mismatch/locate.h"

namespace graftnav {

StaticBiasSimulation simulateFromReferenceAndStaticBias(const ImuSeries& reference,
                                                        const ImuSeries& tested,
                                                        double min_static_s, double max_static_s) {
  const double bin = 0.1;
  const GridSpec g = commonGrid(reference, tested, bin);
  const BinnedImu x = binImu(reference, g), y = binImu(tested, g);
  const std::vector<std::string> reg = labelRegimes(x, Eigen::VectorXd());
  const int need = static_cast<int>(std::ceil(min_static_s / bin));
  const int most = static_cast<int>(std::floor(max_static_s / bin));
  int start = -1, len = 0;
  for (int i = 0; i < g.count; ++i) {
    if (reg[i] == "stopped") {
      if (len == 0) start = i;
      ++len;
      if (len >= most) break;
    } else {
      if (len >= need) break;
      len = 0;
    }
  }
  if (len < need)
    throw std::runtime_error("simulateFromReferenceAndStaticBias: no static span of " +
                             std::to_string(min_static_s) + " s in the field recording");
  // Skip the span's edges (motion may start within a bin).
  const int a = start + std::min(5, len / 4), b = start + len - std::min(5, len / 4);
  StaticBiasSimulation out;
  out.t_start_s = g.binStart(a);
  out.t_end_s = g.binStart(b);
  out.gyro_bias_rad_s = (y.omega_rad_s.middleRows(a, b - a) - x.omega_rad_s.middleRows(a, b - a))
                            .colwise()
                            .mean()
                            .transpose();
  out.accel_bias_m_s2 =
      (y.f_m_s2.middleRows(a, b - a) - x.f_m_s2.middleRows(a, b - a)).colwise().mean().transpose();
  // The temperature behind this bias is the tested IMU's over the span (NaN without one), not
  // the reference IMU's: temperature_bias is regressed on the tested minus this temperature.
  const Eigen::VectorXd span_degC = y.temperature_degC.segment(a, b - a);
  out.temperature_degC = span_degC.allFinite() ? span_degC.mean() : std::nan("");
  out.simulated =
      withStaticBias(reference, out.gyro_bias_rad_s, out.accel_bias_m_s2, out.temperature_degC);
  return out;
}

ImuSeries withStaticBias(const ImuSeries& reference, const Eigen::Vector3d& gyro_bias_rad_s,
                         const Eigen::Vector3d& accel_bias_m_s2, double temperature_degC) {
  ImuSeries out = reference;
  for (ImuSample& smp : out) {
    smp.dtheta_rad += gyro_bias_rad_s * smp.dt_s;
    smp.dvel_m_s += accel_bias_m_s2 * smp.dt_s;
    smp.temperature_degC = temperature_degC;
  }
  return out;
}

namespace {

// The distinct values of one axis, sorted, gathered from a pass in pieces (a buffer sorted and
// merged in), given up once they are more than `most`: then the values do not repeat enough to
// lie on a lattice.
class DistinctValues {
 public:
  explicit DistinctValues(std::size_t most) : most_(most) {}
  void add(double v) {
    if (too_many_) return;
    buffer_.push_back(v);
    if (buffer_.size() >= kBuffer) merge();
  }
  // The sorted distinct values; empty when there were more than `most`.
  std::vector<double> finish() {
    merge();
    return too_many_ ? std::vector<double>() : std::move(distinct_);
  }

 private:
  static constexpr std::size_t kBuffer = std::size_t{1} << 18;
  void merge() {
    if (too_many_) return;
    std::sort(buffer_.begin(), buffer_.end());
    buffer_.erase(std::unique(buffer_.begin(), buffer_.end()), buffer_.end());
    std::vector<double> merged;
    merged.reserve(distinct_.size() + buffer_.size());
    std::set_union(distinct_.begin(), distinct_.end(), buffer_.begin(), buffer_.end(),
                   std::back_inserter(merged));
    buffer_.clear();
    distinct_ = std::move(merged);
    if (distinct_.size() > most_) {
      too_many_ = true;
      std::vector<double>().swap(distinct_);
      std::vector<double>().swap(buffer_);
    }
  }
  std::size_t most_;
  bool too_many_ = false;
  std::vector<double> buffer_, distinct_;
};

// The lattice step of an axis from its sorted distinct values, 0 when they are not on one.
double latticeStep(const std::vector<double>& u) {
  if (u.size() < 2) return 0.0;
  double q = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < u.size(); ++i) q = std::min(q, u[i] - u[i - 1]);
  if (!(q > 0.0)) return 0.0;
  // Refine with the median of gap / round(gap / q) and check every value is on the lattice.
  std::vector<double> est;
  for (std::size_t i = 1; i < u.size(); ++i) {
    const double m = std::round((u[i] - u[i - 1]) / q);
    if (m >= 1.0 && m <= 1000.0) est.push_back((u[i] - u[i - 1]) / m);
  }
  std::nth_element(est.begin(), est.begin() + est.size() / 2, est.end());
  q = est[est.size() / 2];
  for (double val : u) {
    const double f = val / q;
    if (std::abs(f - std::round(f)) > 1e-3 && std::abs(f) < 1e12) return 0.0;
  }
  return q;
}

}  // namespace

Eigen::Vector3d detectQuantizationStep(const ImuSeries& imu, Sensor sensor) {
  if (imu.size() < 100) return Eigen::Vector3d::Zero();
  return detectQuantizationStep(viewedRecording(imu), sensor);
}

// One pass per axis: the distinct values of one axis are held at a time (values must repeat:
// at most half as many as samples).
Eigen::Vector3d detectQuantizationStep(const ImuRecording& imu, Sensor sensor) {
  Eigen::Vector3d step = Eigen::Vector3d::Zero();
  if (imu.samples < 100) return step;
  for (int a = 0; a < 3; ++a) {
    DistinctValues values(imu.samples / 2);
    imu.pass([&](const ImuSeries& block) {
      for (const ImuSample& s : block)
        values.add(sensor == Sensor::gyro ? s.dtheta_rad(a) : s.dvel_m_s(a));
    });
    step(a) = latticeStep(values.finish());
  }
  return step;
}

ImuSeries addBinnedContribution(const ImuSeries& simulated, const GridSpec& grid,
                                const Eigen::MatrixXd& c) {
  ImuSeries out = simulated;
  addBinnedContributionInPlace(grid, c, &out);
  return out;
}

ImuRecording withBinnedContribution(ImuRecording simulated, const GridSpec& grid,
                                    Eigen::MatrixXd contribution) {
  if (contribution.rows() != grid.count || contribution.cols() != kMismatchChannels)
    throw std::invalid_argument("withBinnedContribution: contribution is not grid.count x 6");
  auto c = std::make_shared<const Eigen::MatrixXd>(std::move(contribution));
  ImuSeries ends{simulated.first, simulated.last};
  addBinnedContributionInPlace(grid, *c, &ends);
  ImuRecording out = simulated;
  out.first = ends.front();
  out.last = ends.back();
  out.pass = [source = std::move(simulated.pass), grid, c](const ImuBlockFn& block) {
    ImuSeries added;
    source([&](const ImuSeries& b) {
      added = b;
      addBinnedContributionInPlace(grid, *c, &added);
      block(added);
    });
  };
  return out;
}

void addBinnedContributionInPlace(const GridSpec& grid, const Eigen::MatrixXd& c,
                                  ImuSeries* series) {
  if (c.rows() != grid.count || c.cols() != kMismatchChannels)
    throw std::invalid_argument("addBinnedContribution: contribution is not grid.count x 6");
  for (ImuSample& s : *series) {
    const double mid = s.t_s - 0.5 * s.dt_s;
    const int i = std::clamp(static_cast<int>(std::floor((mid - grid.t_begin_s) / grid.bin_s)), 0,
                             grid.count - 1);
    s.dtheta_rad += c.row(i).head<3>().transpose() * s.dt_s;
    s.dvel_m_s += c.row(i).tail<3>().transpose() * s.dt_s;
  }
}

}  // namespace graftnav
