#include "graftnav/eval/gnss_latency.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "graftnav/eval/evaluation.h"
#include "graftnav/nav/nav_interp.h"

namespace graftnav {

FixResidual fixResidual(const GnssFix& f, const NavState& s, const Eigen::Vector3d& lever_arm_b_m) {
  FixResidual r;
  r.t_s = f.t_s;
  r.fix_type = f.fix_type;
  // Fix minus antenna: (fix - IMU) - C_nb l.
  r.r_ned_m = positionErrorNed(f.pos, s.pos) - s.q_nb.toRotationMatrix() * lever_arm_b_m;
  r.v_ned_m_s = s.v_n;
  return r;
}

std::vector<FixResidual> fixResiduals(const NavSeries& track, const GnssSeries& fixes,
                                      double shift_s, const Eigen::Vector3d& lever_arm_b_m) {
  std::vector<FixResidual> out;
  if (track.size() < 2) return out;
  out.reserve(fixes.size());
  NavInterpolator interp(track);
  for (const GnssFix& f : fixes) {
    const auto s = interp.at(f.t_s - shift_s);
    if (s) out.push_back(fixResidual(f, *s, lever_arm_b_m));
  }
  return out;
}

void LatencyScanOptions::validate() const {
  if (!(max_shift_s > min_shift_s))
    throw std::invalid_argument("LatencyScanOptions: max_shift_s must be > min_shift_s");
  if (!(step_s > 0.0)) throw std::invalid_argument("LatencyScanOptions.step_s must be > 0");
  if (!(min_speed_m_s >= 0.0))
    throw std::invalid_argument("LatencyScanOptions.min_speed_m_s must be >= 0");
  if (!(outlier_m > 0.0)) throw std::invalid_argument("LatencyScanOptions.outlier_m must be > 0");
}

namespace {

// Horizontal RMS of the residuals of `fixes` at `shift`; fixes lacking a track state are skipped.
double rmsH(const NavSeries& track, const GnssSeries& fixes, double shift,
            const Eigen::Vector3d& lever) {
  const auto res = fixResiduals(track, fixes, shift, lever);
  if (res.empty()) return std::nan("");
  double s = 0.0;
  for (const auto& r : res) s += r.r_ned_m.head<2>().squaredNorm();
  return std::sqrt(s / static_cast<double>(res.size()));
}

}  // namespace

LatencyEstimate estimateGnssLatency(const NavSeries& track, const GnssSeries& fixes,
                                    const Eigen::Vector3d& lever, const LatencyScanOptions& o) {
  o.validate();
  LatencyEstimate e;
  // Keep fixes with a moving track over the whole scan range (the same set for every shift).
  GnssSeries moving;
  {
    NavInterpolator interp(track);
    for (const GnssFix& f : fixes) {
      const auto a = interp.at(f.t_s - o.max_shift_s);
      const auto b = interp.at(f.t_s - o.min_shift_s);
      const auto c = interp.at(f.t_s);
      if (!a || !b || !c) continue;
      if (c->v_n.head<2>().norm() < o.min_speed_m_s) {
        ++e.fixes_slow;
        continue;
      }
      moving.push_back(f);
    }
  }
  auto scan = [&](const GnssSeries& set) {
    e.shift_s.clear();
    e.rms_h_m.clear();
    const int n =
        static_cast<int>(std::floor((o.max_shift_s - o.min_shift_s) / o.step_s + 1e-9)) + 1;
    for (int i = 0; i < n; ++i) {
      const double s = o.min_shift_s + i * o.step_s;
      e.shift_s.push_back(s);
      e.rms_h_m.push_back(rmsH(track, set, s, lever));
    }
    std::size_t k = 0;
    for (std::size_t i = 1; i < e.rms_h_m.size(); ++i)
      if (e.rms_h_m[i] < e.rms_h_m[k]) k = i;
    e.grid_s = e.shift_s[k];
    e.grid_rms_h_m = e.rms_h_m[k];
    if (k > 0 && k + 1 < e.rms_h_m.size()) {
      // Parabola through the squared RMS (quadratic in the shift for a linear model).
      const double y0 = e.rms_h_m[k - 1] * e.rms_h_m[k - 1], y1 = e.rms_h_m[k] * e.rms_h_m[k],
                   y2 = e.rms_h_m[k + 1] * e.rms_h_m[k + 1];
      const double den = y0 - 2.0 * y1 + y2;
      if (den > 0.0) e.grid_s += 0.5 * o.step_s * (y0 - y2) / den;
    }
    std::size_t z = 0;
    for (std::size_t i = 1; i < e.shift_s.size(); ++i)
      if (std::abs(e.shift_s[i]) < std::abs(e.shift_s[z])) z = i;
    e.rms_h_at_zero_m = e.rms_h_m[z];
  };
  if (moving.size() < 3) {
    throw std::invalid_argument("estimateGnssLatency: " + std::to_string(moving.size()) +
                                " fixes with the track moving faster than " +
                                std::to_string(o.min_speed_m_s) + " m/s (need 3)");
  }
  scan(moving);
  // Drop outliers at the best shift, then repeat.
  GnssSeries clean;
  {
    const auto res = fixResiduals(track, moving, e.grid_s, lever);
    for (std::size_t i = 0; i < res.size(); ++i) {
      if (res[i].r_ned_m.head<2>().norm() > o.outlier_m) {
        ++e.fixes_outliers;
      } else {
        clean.push_back(moving[i]);
      }
    }
  }
  if (clean.size() < 3) {
    throw std::invalid_argument("estimateGnssLatency: fewer than 3 fixes left after dropping " +
                                std::to_string(e.fixes_outliers) + " outliers");
  }
  scan(clean);
  e.fixes_used = static_cast<int>(clean.size());
  // Along-track least squares at shift 0: r(0) = -v tau.
  double num = 0.0, den = 0.0;
  for (const auto& r : fixResiduals(track, clean, 0.0, lever)) {
    num += r.v_ned_m_s.head<2>().dot(r.r_ned_m.head<2>());
    den += r.v_ned_m_s.head<2>().squaredNorm();
  }
  e.slope_s = den > 0.0 ? -num / den : 0.0;
  return e;
}

void CheckpointWindowSums::add(const FixResidual& r) {
  const double h = r.r_ned_m.head<2>().norm(), v = std::abs(r.r_ned_m.z());
  sum_h2_m2 += h * h;
  sum_v2_m2 += v * v;
  stats.max_h_m = std::max(stats.max_h_m, h);
  stats.max_v_m = std::max(stats.max_v_m, v);
  stats.last_h_m = h;
  ++stats.n;
}

CheckpointEvaluation checkpointEvaluation(const std::vector<CheckpointWindowSums>& windows) {
  CheckpointEvaluation ev;
  double sh = 0.0, sv = 0.0, smh = 0.0, smv = 0.0, mh = 0.0;
  for (const CheckpointWindowSums& w : windows) {
    if (w.stats.n == 0) continue;
    CheckpointWindowStats st = w.stats;
    st.rms_h_m = std::sqrt(w.sum_h2_m2 / st.n);
    st.rms_v_m = std::sqrt(w.sum_v2_m2 / st.n);
    sh += w.sum_h2_m2;
    sv += w.sum_v2_m2;
    smh += st.max_h_m * st.max_h_m;
    smv += st.max_v_m * st.max_v_m;
    mh += st.max_h_m;
    ev.n += st.n;
    ev.windows.push_back(st);
  }
  if (ev.n > 0) {
    const double nw = static_cast<double>(ev.windows.size());
    ev.rms_h_m = std::sqrt(sh / ev.n);
    ev.rms_v_m = std::sqrt(sv / ev.n);
    ev.rms_of_max_h_m = std::sqrt(smh / nw);
    ev.rms_of_max_v_m = std::sqrt(smv / nw);
    ev.mean_of_max_h_m = mh / nw;
  }
  return ev;
}

CheckpointEvaluation evaluateAtCheckpoints(const NavSeries& solution, const GnssSeries& checkpoints,
                                           const std::vector<TimeWindow>& windows,
                                           const Eigen::Vector3d& lever) {
  std::vector<CheckpointWindowSums> sums;
  for (const TimeWindow& w : windows) {
    GnssSeries inside;
    for (const GnssFix& f : checkpoints)
      if (f.t_s >= w.start_s && f.t_s <= w.end_s) inside.push_back(f);
    CheckpointWindowSums s;
    s.stats.window = w;
    for (const FixResidual& r : fixResiduals(solution, inside, 0.0, lever)) s.add(r);
    sums.push_back(s);
  }
  return checkpointEvaluation(sums);
}

}  // namespace graftnav
