#include "graftnav/eval/evaluation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "graftnav/nav/earth.h"
#include "graftnav/nav/nav_interp.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {
namespace {

struct RmsAccumulator {
  double h2 = 0, v2 = 0, r2 = 0, p2 = 0, y2 = 0;
  long n = 0;
  void add(double h, double v, double r, double p, double y) {
    h2 += h * h;
    v2 += v * v;
    r2 += r * r;
    p2 += p * p;
    y2 += y * y;
    ++n;
  }
  DriftStats rms() const {
    DriftStats s;
    if (n == 0) return s;
    s.horizontal_m = std::sqrt(h2 / n);
    s.vertical_m = std::sqrt(v2 / n);
    s.roll_rad = std::sqrt(r2 / n);
    s.pitch_rad = std::sqrt(p2 / n);
    s.heading_rad = std::sqrt(y2 / n);
    return s;
  }
};

}  // namespace

void EvaluationOptions::validate() const {
  if (!(nees_interval_s >= 0.0)) {
    throw std::invalid_argument("EvaluationOptions: nees_interval_s must be >= 0, got " +
                                std::to_string(nees_interval_s));
  }
  if (!(nees_band_probability > 0.0 && nees_band_probability < 1.0)) {
    throw std::invalid_argument("EvaluationOptions: nees_band_probability must be in (0,1), got " +
                                std::to_string(nees_band_probability));
  }
}

namespace {

// The error of a solution state against the reference state at the same time.
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

// Epoch errors in time order, summed into the statistics of an Evaluation: overall and outage
// RMS, per-outage maxima, NEES at most every nees_interval_s.
class EvaluationAccumulator {
 public:
  EvaluationAccumulator(const std::vector<TimeWindow>& windows, const EvaluationOptions& options,
                        Evaluation* ev)
      : windows_(windows), options_(options), ev_(ev), drift_(windows.size()) {
    for (size_t k = 0; k < windows_.size(); ++k) {
      drift_[k].window = windows_[k];
      drift_[k].max = DriftStats{0, 0, 0, 0, 0};
    }
  }

  void add(const NavState& s, const PvaSigma* sg, const NavState& ref) {
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
    ev_->epochs.push_back(e);
  }

  void finish() {
    Evaluation& ev = *ev_;
    ev.overall_rms = all_.rms();
    ev.outage_rms = in_outage_.rms();
    ev.outage_epochs = static_cast<int>(in_outage_.n);
    RmsAccumulator maxima;
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

 private:
  void addNees(EpochError& e, const PvaSigma& sg, double t_s) {
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

  const std::vector<TimeWindow>& windows_;
  const EvaluationOptions& options_;
  Evaluation* ev_;
  std::vector<OutageDrift> drift_;
  RmsAccumulator all_, in_outage_;
  size_t w_ = 0;
  double nees_sum_ = 0.0, last_nees_t_ = -std::numeric_limits<double>::infinity();
};

}  // namespace

Evaluation evaluateSolution(const NavSolution& solution, const NavSeries& reference,
                            const std::vector<TimeWindow>& outages,
                            const EvaluationOptions& options) {
  options.validate();
  if (solution.states.empty() || reference.empty() ||
      solution.states.back().t_s < reference.front().t_s ||
      solution.states.front().t_s > reference.back().t_s) {
    throw std::invalid_argument("evaluateSolution: solution '" + solution.estimator +
                                "' and the reference do not overlap in time");
  }
  std::vector<TimeWindow> windows = outages;
  std::sort(windows.begin(), windows.end(),
            [](const TimeWindow& a, const TimeWindow& b) { return a.start_s < b.start_s; });

  Evaluation ev;
  ev.epochs.reserve(solution.states.size());
  const bool has_sigma = solution.sigma.size() == solution.states.size();
  EvaluationAccumulator acc(windows, options, &ev);
  const NavSeries& sol = solution.states;
  const double sol_rate =
      sol.size() > 1 ? (sol.size() - 1) / std::max(1e-9, sol.back().t_s - sol.front().t_s) : 0.0;
  const double ref_rate =
      reference.size() > 1
          ? (reference.size() - 1) / std::max(1e-9, reference.back().t_s - reference.front().t_s)
          : 0.0;
  const bool at_reference = options.epochs == EvaluationEpochs::kReference ||
                            (options.epochs == EvaluationEpochs::kAuto && ref_rate < sol_rate);
  if (!at_reference) {
    NavInterpolator ref_at(reference);
    for (size_t i = 0; i < sol.size(); ++i) {
      const auto ref = ref_at.at(sol[i].t_s);
      if (!ref) continue;
      acc.add(sol[i], has_sigma ? &solution.sigma[i] : nullptr, *ref);
    }
  } else {
    NavInterpolator sol_at(sol);
    size_t k = 0;  // sigma bracket
    for (const NavState& ref : reference) {
      const auto s = sol_at.at(ref.t_s);
      if (!s) continue;
      PvaSigma sg;
      if (has_sigma) {
        while (k + 1 < sol.size() && sol[k + 1].t_s <= ref.t_s) ++k;
        const size_t k1 = std::min(k + 1, sol.size() - 1);
        const double span = sol[k1].t_s - sol[k].t_s;
        const double u = span > 0 ? std::clamp((ref.t_s - sol[k].t_s) / span, 0.0, 1.0) : 0.0;
        sg = (1.0 - u) * solution.sigma[k] + u * solution.sigma[k1];
      }
      acc.add(*s, has_sigma ? &sg : nullptr, ref);
    }
  }
  if (ev.epochs.empty()) {
    throw std::invalid_argument("evaluateSolution: no solution epoch of '" + solution.estimator +
                                "' lies inside the reference span");
  }
  acc.finish();
  return ev;
}

}  // namespace graftnav
