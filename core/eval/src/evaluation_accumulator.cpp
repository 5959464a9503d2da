#include "evaluation_accumulator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "graftnav/nav/distributions.h"
#include "graftnav/nav/earth.h"
#include "graftnav/nav/rotation.h"

namespace graftnav::eval_detail {

EpochError epochError(const NavState& s, const NavState& ref) {
  EpochError e;
  e.t_s = s.t_s;
  e.pos_ned_m = positionErrorNed(s.pos, ref.pos);
  e.vel_ned_m_s = s.v_n - ref.v_n;
  const Eigen::Vector3d eu_s = eulerFromQuat(s.q_nb), eu_r = eulerFromQuat(ref.q_nb);
  for (int j = 0; j < 3; ++j) e.euler_rad[j] = wrapAngle(eu_s[j] - eu_r[j]);
  e.att_n_rad = rotationVectorFromQuat(s.q_nb * ref.q_nb.conjugate());
  return e;
}

void EvaluationAccumulator::RmsSum::add(double h, double v, double r, double p, double y) {
  h2 += h * h;
  v2 += v * v;
  r2 += r * r;
  p2 += p * p;
  y2 += y * y;
  ++n;
}

DriftStats EvaluationAccumulator::RmsSum::rms() const {
  DriftStats s;
  if (n == 0) return s;
  s.horizontal_m = std::sqrt(h2 / n);
  s.vertical_m = std::sqrt(v2 / n);
  s.roll_rad = std::sqrt(r2 / n);
  s.pitch_rad = std::sqrt(p2 / n);
  s.heading_rad = std::sqrt(y2 / n);
  return s;
}

EvaluationAccumulator::EvaluationAccumulator(const std::vector<TimeWindow>& windows,
                                             const EvaluationOptions& options, Evaluation* ev,
                                             EpochFn on_epoch)
    : windows_(windows),
      options_(options),
      ev_(ev),
      on_epoch_(std::move(on_epoch)),
      drift_(windows.size()),
      last_nees_t_(-std::numeric_limits<double>::infinity()) {
  for (size_t k = 0; k < windows_.size(); ++k) {
    drift_[k].window = windows_[k];
    drift_[k].max = DriftStats{0, 0, 0, 0, 0};
  }
}

void EvaluationAccumulator::add(const NavState& s, const PvaSigma* sg, const NavState& ref) {
  EpochError e = epochError(s, ref);
  while (w_ < windows_.size() && windows_[w_].end_s < s.t_s) ++w_;
  if (w_ < windows_.size() && windows_[w_].contains(s.t_s)) e.outage = static_cast<int>(w_);

  const double hz = e.pos_ned_m.head<2>().norm(), vt = std::abs(e.pos_ned_m.z());
  const double r = std::abs(e.euler_rad.x()), p = std::abs(e.euler_rad.y()),
               y = std::abs(e.euler_rad.z());
  all_.add(hz, vt, r, p, y);
  if (e.outage >= 0) {
    in_outage_.add(hz, vt, r, p, y);
    OutageDrift& d = drift_[static_cast<size_t>(e.outage)];
    ++d.epochs;
    d.max.horizontal_m = std::max(d.max.horizontal_m, hz);
    d.max.vertical_m = std::max(d.max.vertical_m, vt);
    d.max.roll_rad = std::max(d.max.roll_rad, r);
    d.max.pitch_rad = std::max(d.max.pitch_rad, p);
    d.max.heading_rad = std::max(d.max.heading_rad, y);
  }
  if (sg) addNees(e, *sg, s.t_s);
  ++ev_->epoch_count;
  on_epoch_(e);
}

void EvaluationAccumulator::finish() {
  Evaluation& ev = *ev_;
  ev.overall_rms = all_.rms();
  ev.outage_rms = in_outage_.rms();
  ev.outage_epochs = static_cast<int>(in_outage_.n);
  RmsSum maxima;
  for (const OutageDrift& d : drift_) {
    if (d.epochs == 0) continue;
    ev.outages.push_back(d);
    maxima.add(d.max.horizontal_m, d.max.vertical_m, d.max.roll_rad, d.max.pitch_rad,
               d.max.heading_rad);
  }
  ev.outage_max_rms = maxima.rms();
  if (ev.nees_samples > 0) {
    const double n = ev.nees_samples;
    ev.nees_mean = nees_sum_ / n;
    const double tail = 0.5 * (1.0 - options_.nees_band_probability);
    ev.nees_band_low = chiSquareQuantile(tail, ev.nees_dof * n) / n;
    ev.nees_band_high = chiSquareQuantile(1.0 - tail, ev.nees_dof * n) / n;
  }
}

void EvaluationAccumulator::addNees(EpochError& e, const PvaSigma& sg, double t_s) {
  Eigen::Matrix<double, 9, 1> err;
  err << e.pos_ned_m, e.vel_ned_m_s, e.att_n_rad;
  if (!((sg.array() > 0.0).all() && sg.allFinite())) return;
  e.nees = (err.array() / sg.array()).square().sum();
  if (t_s - last_nees_t_ >= options_.nees_interval_s - 1e-9) {
    nees_sum_ += e.nees;
    ++ev_->nees_samples;
    last_nees_t_ = t_s;
  }
}

std::vector<TimeWindow> sortedWindows(std::vector<TimeWindow> windows) {
  std::sort(windows.begin(), windows.end(),
            [](const TimeWindow& a, const TimeWindow& b) { return a.start_s < b.start_s; });
  return windows;
}

double seriesRate(std::size_t count, double t_first_s, double t_last_s) {
  return count > 1 ? (count - 1) / std::max(1e-9, t_last_s - t_first_s) : 0.0;
}

}  // namespace graftnav::eval_detail
