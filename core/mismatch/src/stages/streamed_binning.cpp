#include "graftnav/mismatch/streamed_binning.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "cumulative_nodes.h"

namespace graftnav {

// The window's nodes as cumulative_nodes.h reads them; count is the nodes read so far (the
// record's count once finished).
struct StreamedBinning::NodeView {
  const StreamedBinning& b;
  const std::size_t count;
  std::size_t size() const { return count; }
  double t(std::size_t k) const { return b.nodeAt(k).t_s; }
  const Vector6d& cum(std::size_t k) const { return b.nodeAt(k).cum; }
  double cumTemp(std::size_t k) const { return b.nodeAt(k).cum_temp; }
  int irregular(std::size_t k) const { return b.nodeAt(k).irregular; }
  std::size_t upperBound(double t_s) const { return b.upperBound(t_s); }
};
StreamedBinning::StreamedBinning(const GridSpec& grid, double time_shift_s, ImuSampleMap map,
                                 BinnedColumns columns)
    : grid_(grid),
      shift_s_(time_shift_s),
      map_(std::move(map)),
      rates_only_(columns == BinnedColumns::rates_only) {
  const int n = grid_.count;
  out_.grid = grid_;
  out_.omega_rad_s.resize(n, 3);
  if (rates_only_) return;
  out_.f_m_s2.resize(n, 3);
  out_.temperature_degC.setConstant(n, std::numeric_limits<double>::quiet_NaN());
  out_.f_within_rms_m_s2.setZero(n);
  sum_sq_.setZero(n);
  count_.setZero(n);
}

const StreamedBinning::Node& StreamedBinning::nodeAt(std::size_t k) const {
  if (k < base_) return first_[k];  // only nodes 0 and 1 are asked for below the window
  return nodes_[k - base_];
}

std::size_t StreamedBinning::upperBound(double t_s) const {
  const auto it = std::upper_bound(nodes_.begin(), nodes_.end(), t_s,
                                   [](double t, const Node& nd) { return t < nd.t_s; });
  if (it == nodes_.begin() && base_ > 0)
    throw std::logic_error("StreamedBinning: a bin edge before the nodes still held");
  return base_ + static_cast<std::size_t>(it - nodes_.begin());
}

void StreamedBinning::add(const ImuSample& raw) {
  if (finished_) throw std::logic_error("StreamedBinning: sample added after finish()");
  const std::size_t k = added_;
  const ImuSample s = map_ ? map_(raw) : raw;
  if (!(s.dt_s > 0.0))
    throw std::invalid_argument("CumulativeImu: sample " + std::to_string(k) +
                                " has dt_s = " + std::to_string(s.dt_s) + " (must be > 0)");
  all_temperature_ &= raw.hasTemperature();
  if (nodes_.empty() && base_ == 0) {
    Node first;
    first.t_s = raw.t_s - raw.dt_s;
    nodes_.push_back(first);
    first_[0] = first;
  }
  const Node& last = nodes_.back();
  // Boundaries follow the time tags (CumulativeImu): the tag ends the sample, the previous end
  // starts it.
  if (!(s.t_s > last.t_s))
    throw std::invalid_argument("CumulativeImu: sample " + std::to_string(k) + " at t = " +
                                std::to_string(s.t_s) + " is not after the previous sample");
  Vector6d inc;
  inc << s.dtheta_rad, s.dvel_m_s;
  Node nd;
  nd.t_s = s.t_s;
  nd.cum = last.cum + inc;
  nd.cum_temp = last.cum_temp + s.temperature_degC * (s.t_s - last.t_s);
  nd.irregular = last.irregular;
  if (nodeCount() >= 2) {
    const double d = s.t_s - last.t_s, d0 = last.t_s - nodeAt(nodeCount() - 2).t_s;
    nd.irregular += std::abs(d - d0) > 1e-6 * d0 ? 1 : 0;
  }
  nodes_.push_back(nd);
  if (nodeCount() == 2) first_[1] = nd;
  ++added_;
  // Within-bin vibration: samples whose end tag falls inside a (shifted) bin.
  const int i = static_cast<int>(std::floor((raw.t_s - shift_s_ - grid_.t_begin_s) / grid_.bin_s));
  if (i >= 0 && i < grid_.count && !rates_only_) pending_.push_back({i, s.dvel_m_s / raw.dt_s});
  closeBins();
}

// The integral at t_s where every node it reads is held and its tests on the node count come
// out as they will on the whole record: at least kSincHalfWidth + 2 nodes after its segment.
bool StreamedBinning::integralAt(double t_s, Vector6d* value, double* temp) const {
  const std::size_t N = nodeCount();
  if (!finished_) {
    if (N < 2) return false;
    if (!(t_s <= first_[0].t_s)) {
      if (!(t_s < nodes_.back().t_s)) return false;
      const std::size_t k = upperBound(t_s) - 1;
      if (k + grid_detail::kSincHalfWidth + 3 > N) return false;
    }
  }
  const NodeView view{*this, N};
  *value = grid_detail::integralAt(view, t_s);
  *temp = grid_detail::temperatureIntegralAt(view, t_s);
  return true;
}

void StreamedBinning::closeBins() {
  const int n = grid_.count;
  while (next_bin_ < n) {
    Vector6d value;
    double temp = 0.0;
    const double t_edge = grid_.binStart(next_bin_ + 1) + shift_s_;
    if (!integralAt(t_edge, &value, &temp)) break;
    if (next_bin_ >= 0) closeBin(next_bin_, value, temp);
    prev_ = value;
    prev_temp_ = temp;
    ++next_bin_;
  }
  // Nodes no later edge reads: those more than the sinc's half width (and the slopes' two)
  // before the segment of the next edge.
  if (next_bin_ >= n || nodes_.size() < 4096) return;
  const double t_next = grid_.binStart(next_bin_ + 1) + shift_s_;
  const std::size_t k = upperBound(std::max(t_next, nodes_.front().t_s));
  const std::size_t keep_from =
      k > 2 * grid_detail::kSincHalfWidth + 8 ? k - 2 * grid_detail::kSincHalfWidth - 8 : 0;
  while (base_ < keep_from && nodes_.size() > 2) {
    nodes_.pop_front();
    ++base_;
  }
}

void StreamedBinning::closeBin(int i, const Vector6d& next, double next_temp) {
  const Vector6d mean = (next - prev_) / grid_.bin_s;
  out_.omega_rad_s.row(i) = mean.head<3>().transpose();
  if (rates_only_) return;
  out_.f_m_s2.row(i) = mean.tail<3>().transpose();
  out_.temperature_degC(i) = (next_temp - prev_temp_) / grid_.bin_s;
  while (!pending_.empty() && pending_.front().bin <= i) {
    const PendingSample& p = pending_.front();
    sum_sq_(p.bin) += (p.f_m_s2 - out_.f_m_s2.row(p.bin).transpose()).squaredNorm();
    ++count_(p.bin);
    pending_.pop_front();
  }
}

BinnedImu StreamedBinning::finish() {
  if (added_ == 0) throw std::invalid_argument("CumulativeImu: empty IMU series");
  finished_ = true;
  closeBins();
  const int n = grid_.count;
  if (rates_only_) return std::move(out_);
  if (!all_temperature_)
    out_.temperature_degC.setConstant(n, std::numeric_limits<double>::quiet_NaN());
  for (int i = 0; i < n; ++i)
    out_.f_within_rms_m_s2(i) = count_(i) > 0 ? std::sqrt(sum_sq_(i) / count_(i)) : 0.0;
  return std::move(out_);
}

}  // namespace graftnav
