#include "graftnav/estimation/vehicle_aiding.h"

#include "graftnav/estimation/nav_solution.h"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>
#include <string>

namespace graftnav {
namespace {

class SeriesOdometerSource final : public OdometerSource {
 public:
  explicit SeriesOdometerSource(const OdometerSeries& samples) : samples_(samples) {}
  bool next(OdometerSample* sample) override {
    if (i_ >= samples_.size()) return false;
    *sample = samples_[i_++];
    return true;
  }

 private:
  const OdometerSeries& samples_;
  std::size_t i_ = 0;
};

void require(bool ok, const std::string& field, double value, const char* rule) {
  if (!ok) {
    throw std::invalid_argument(field + " = " + std::to_string(value) + ": " + rule);
  }
}

bool finiteNonNegative(double x) { return std::isfinite(x) && x >= 0.0; }
bool finitePositive(double x) { return std::isfinite(x) && x > 0.0; }

}  // namespace

std::unique_ptr<OdometerSource> seriesOdometerSource(const OdometerSeries& samples) {
  return std::make_unique<SeriesOdometerSource>(samples);
}

Eigen::Matrix3d VehicleAidingOptions::C_vb() const {
  const Eigen::Vector3d& e = odometer.mounting_rad;  // roll, pitch, yaw of b in v (ZYX)
  return (Eigen::AngleAxisd(e.z(), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(e.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(e.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

double VehicleAidingOptions::rateHz() const {
  double r = 0.0;
  if (odometer.enabled) r = std::max(r, odometer.rate_hz);
  if (nhc.enabled) r = std::max(r, nhc.rate_hz);
  return r;
}

Eigen::Vector3d VehicleAidingOptions::rowStd_m_s() const {
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  if (odometer.enabled) s = odometer.std_m_s.cwiseMax(0.0);
  if (nhc.enabled) s.tail<2>() = nhc.std_m_s;
  return s;
}

void VehicleAidingOptions::validate() const {
  const OdometerOptions& o = odometer;
  require(finitePositive(o.std_m_s.x()), "odometer.std_m_s (forward)", o.std_m_s.x(),
          "must be > 0");
  for (int i = 1; i < 3; ++i)
    require(std::isfinite(o.std_m_s(i)), "odometer.std_m_s", o.std_m_s(i), "must be finite");
  require(finiteNonNegative(o.scale_std), "odometer.scale_std", o.scale_std, "must be >= 0");
  require(o.scale_std < 0.5, "odometer.scale_std", o.scale_std,
          "must be < 0.5 (a fraction of the speed, not ppm)");
  require(finiteNonNegative(o.scale_random_walk_per_sqrt_s), "odometer.scale_random_walk",
          o.scale_random_walk_per_sqrt_s, "must be >= 0");
  require(o.lever_arm_b_m.allFinite() && o.lever_arm_b_m.cwiseAbs().maxCoeff() < 100.0,
          "odometer.lever_arm_m", o.lever_arm_b_m.cwiseAbs().maxCoeff(),
          "must be finite and within 100 m");
  require(o.mounting_rad.allFinite() && o.mounting_rad.cwiseAbs().maxCoeff() <= 2.0 * M_PI,
          "odometer.mounting_deg", o.mounting_rad.cwiseAbs().maxCoeff() * 180.0 / M_PI,
          "must be finite and within 360 deg");
  require(finitePositive(o.rate_hz), "odometer.rate_hz", o.rate_hz, "must be > 0");
  require(finitePositive(o.max_gap_s), "odometer.max_gap_s", o.max_gap_s, "must be > 0");
  for (int i = 0; i < 2; ++i)
    require(finitePositive(nhc.std_m_s(i)), "nhc.std_m_s", nhc.std_m_s(i), "must be > 0");
  require(finitePositive(nhc.rate_hz), "nhc.rate_hz", nhc.rate_hz, "must be > 0");
}

OdometerInterpolator::OdometerInterpolator(std::unique_ptr<OdometerSource> source, double max_gap_s)
    : source_(std::move(source)), max_gap_s_(max_gap_s) {
  if (!source_) throw std::invalid_argument("OdometerInterpolator: no odometer source");
}

bool OdometerInterpolator::advance() {
  OdometerSample s;
  if (ended_ || !source_->next(&s)) {
    ended_ = true;
    return false;
  }
  if (has_b_ && s.t_s < b_.t_s) {
    throw std::invalid_argument("odometer samples out of time order: t=" + std::to_string(s.t_s) +
                                " after t=" + std::to_string(b_.t_s));
  }
  a_ = b_;
  has_a_ = has_b_;
  b_ = s;
  has_b_ = true;
  return true;
}

bool OdometerInterpolator::at(double t_s, double* speed_m_s) {
  while (!ended_ && (!has_b_ || b_.t_s < t_s)) advance();
  if (!has_b_ || b_.t_s < t_s) return false;  // after the last sample
  if (b_.t_s == t_s) {
    *speed_m_s = b_.speed_m_s;
    return true;
  }
  if (!has_a_ || a_.t_s > t_s || b_.t_s - a_.t_s > max_gap_s_) return false;
  const double w = (t_s - a_.t_s) / (b_.t_s - a_.t_s);
  *speed_m_s = a_.speed_m_s + w * (b_.speed_m_s - a_.speed_m_s);
  return true;
}

std::unique_ptr<OdometerSource> EstimationProblem::openOdometer() const {
  return odometer_stream ? odometer_stream() : seriesOdometerSource(odometer);
}

}  // namespace graftnav
