#include "graftnav/sim/track_trajectory.h"

#include <Eigen/Sparse>
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "graftnav/nav/rotation.h"
#include "graftnav/nav/units.h"

namespace graftnav {
namespace {

constexpr int kDegree = 5;
constexpr int kOrder = kDegree + 1;

// Pieces of the cardinal quintic B-spline N(x), x in [0, 6): piece s is a polynomial in u = x - s,
// coefficients of u^0..u^5, from the Cox-de Boor recursion on integer knots.
using Poly = std::array<double, kOrder>;
std::array<Poly, kOrder> cardinalPieces() {
  std::array<std::array<Poly, kOrder>, kOrder> P{};  // P[d][s]
  P[0][0] = {1, 0, 0, 0, 0, 0};
  for (int d = 1; d <= kDegree; ++d) {
    for (int s = 0; s <= d; ++s) {
      Poly q{};
      if (s <= d - 1) {  // (s + u)/d * P[d-1][s]
        for (int k = 0; k < kOrder; ++k) {
          const double a = P[d - 1][s][k] / d;
          q[k] += s * a;
          if (k + 1 < kOrder) q[k + 1] += a;
        }
      }
      if (s >= 1) {  // (d + 1 - s - u)/d * P[d-1][s-1]
        for (int k = 0; k < kOrder; ++k) {
          const double a = P[d - 1][s - 1][k] / d;
          q[k] += (d + 1 - s) * a;
          if (k + 1 < kOrder) q[k + 1] -= a;
        }
      }
      P[d][s] = q;
    }
  }
  return P[kDegree];
}

const std::array<Poly, kOrder>& pieces() {
  static const std::array<Poly, kOrder> p = cardinalPieces();
  return p;
}

// r-th derivative of polynomial c at u.
double polyDerivative(const Poly& c, double u, int r) {
  double v = 0.0;
  for (int k = kDegree; k >= r; --k) {
    double f = 1.0;
    for (int i = 0; i < r; ++i) f *= (k - i);
    v = v * u + f * c[k];
  }
  return v;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const std::size_t m = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + m, v.end());
  return v[m];
}

}  // namespace

// Uniform quintic B-spline f(t) = sum_j c_j N((t - t0)/dt - j + 5), fitted by penalized weighted
// least squares: min sum_i w_i (y_i - f(t_i))^2 + lambda sum_r (third difference of c)_r^2.
class TrackTrajectory::Spline {
 public:
  Spline(double t0, double dt, int nseg) : t0_(t0), dt_(dt), nseg_(std::max(1, nseg)) {}

  // lambda chosen so that a sinusoid at cutoff_hz is attenuated by about half:
  // lambda (2 sin(pi f dt))^6 ~= mean weight per knot interval.
  void fit(const std::vector<double>& t, const std::vector<double>& y, const std::vector<double>& w,
           double cutoff_hz) {
    const int K = nseg_ + kDegree;
    std::vector<Eigen::Triplet<double>> trip;
    trip.reserve(t.size() * kOrder * kOrder + 7 * K);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(K);
    double wsum = 0.0;
    for (std::size_t i = 0; i < t.size(); ++i) {
      if (!(w[i] > 0.0)) continue;
      int m;
      double u;
      locate(t[i], m, u);
      double b[kOrder];
      for (int s = 0; s < kOrder; ++s) b[s] = polyDerivative(pieces()[s], u, 0);
      for (int s1 = 0; s1 < kOrder; ++s1) {
        const int j1 = m + kDegree - s1;
        rhs[j1] += w[i] * b[s1] * y[i];
        for (int s2 = 0; s2 < kOrder; ++s2) {
          trip.emplace_back(j1, m + kDegree - s2, w[i] * b[s1] * b[s2]);
        }
      }
      wsum += w[i];
    }
    const double x = 2.0 * std::sin(units::kPi * std::min(cutoff_hz * dt_, 0.5));
    const double lambda = (wsum / nseg_) / std::pow(x, 6);
    const double d3[4] = {1.0, -3.0, 3.0, -1.0};
    for (int r = 0; r + 3 < K; ++r) {
      for (int a = 0; a < 4; ++a) {
        for (int b = 0; b < 4; ++b) trip.emplace_back(r + a, r + b, lambda * d3[a] * d3[b]);
      }
    }
    Eigen::SparseMatrix<double> N(K, K);
    N.setFromTriplets(trip.begin(), trip.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(N);
    if (ldlt.info() != Eigen::Success) {
      throw std::runtime_error("TrackTrajectory: smoothing spline system is singular");
    }
    c_ = ldlt.solve(rhs);
  }

  // d[r] = r-th time derivative at t, r = 0..nder.
  void eval(double t, double* d, int nder) const {
    int m;
    double u;
    locate(t, m, u);
    double scale = 1.0;
    for (int r = 0; r <= nder; ++r) {
      double v = 0.0;
      for (int s = 0; s < kOrder; ++s) v += c_[m + kDegree - s] * polyDerivative(pieces()[s], u, r);
      d[r] = v * scale;
      scale /= dt_;
    }
  }

 private:
  void locate(double t, int& m, double& u) const {
    const double x = (t - t0_) / dt_;
    m = std::clamp(static_cast<int>(std::floor(x)), 0, nseg_ - 1);
    u = x - m;
  }
  double t0_, dt_;
  int nseg_;
  Eigen::VectorXd c_;
};

std::vector<AttitudeOscillation> TrackSmoothingOptions::defaultOscillations() {
  const double d = units::kDegToRad;
  return {{0, 0.20 * d, 1.7, 0.0},
          {0, 0.08 * d, 3.1, 1.0},
          {1, 0.15 * d, 1.3, 0.5},
          {1, 0.06 * d, 2.6, 2.0},
          {2, 0.03 * d, 2.3, 0.3}};
}

void TrackSmoothingOptions::validate() const {
  auto need = [](bool ok, const char* key, double v) {
    if (!ok) {
      throw std::invalid_argument(std::string("TrackSmoothingOptions: bad ") + key + " = " +
                                  std::to_string(v));
    }
  };
  need(position_cutoff_hz > 0.0, "position_cutoff_hz", position_cutoff_hz);
  need(attitude_cutoff_hz > 0.0, "attitude_cutoff_hz", attitude_cutoff_hz);
  need(knot_spacing_s > 0.0, "knot_spacing_s", knot_spacing_s);
  need(outlier_sigma > 0.0, "outlier_sigma", outlier_sigma);
  need(stop_speed_m_s >= 0.0, "stop_speed_m_s", stop_speed_m_s);
  need(stop_min_epochs >= 2, "stop_min_epochs", stop_min_epochs);
  need(heading_hold_speed_m_s > 0.0, "heading_hold_speed_m_s", heading_hold_speed_m_s);
  need(lateral_speed_floor_m_s > 0.0, "lateral_speed_floor_m_s", lateral_speed_floor_m_s);
  need(oscillation_speed_m_s > 0.0, "oscillation_speed_m_s", oscillation_speed_m_s);
  vibration.validate();
  for (const auto& o : oscillations) {
    need(o.euler_index >= 0 && o.euler_index <= 2, "oscillation euler_index", o.euler_index);
    need(o.frequency_hz >= 0.0, "oscillation frequency_hz", o.frequency_hz);
  }
}

namespace {

// Uniform in [0, 1) from the 53 high bits (std::uniform_real_distribution is not specified
// bit-for-bit by the standard; mt19937_64 is).
double uniform01(std::mt19937_64& g) { return static_cast<double>(g() >> 11) * 0x1.0p-53; }

// Sinusoids of total vector rms `rms` (of the amplitude's `order`-th derivative, order 2 for a
// displacement giving acceleration, 1 for an angle giving a rate), axis k % 3 with mean-square
// shares `share`, frequencies and phases from g.
std::vector<VibrationComponent> drawVibration(double rms, const double (&share)[3], int order,
                                              const RoadVibrationOptions& o, std::mt19937_64& g) {
  std::vector<VibrationComponent> out;
  if (!(rms > 0.0)) return out;
  int per_axis[3] = {0, 0, 0};
  for (int k = 0; k < o.components; ++k) ++per_axis[k % 3];
  for (int k = 0; k < o.components; ++k) {
    VibrationComponent c;
    c.axis = k % 3;
    c.frequency_hz = o.band_low_hz + (o.band_high_hz - o.band_low_hz) * uniform01(g);
    c.phase_rad = 2.0 * units::kPi * uniform01(g);
    const double ms = rms * rms * share[c.axis] / per_axis[c.axis];
    c.amplitude = std::sqrt(2.0 * ms) / std::pow(2.0 * units::kPi * c.frequency_hz, order);
    out.push_back(c);
  }
  return out;
}

constexpr double kLinearShare[3] = {0.15, 0.25, 0.60};   // forward, right, down
constexpr double kAngularShare[3] = {0.40, 0.45, 0.15};  // roll, pitch, yaw

// Speed fade of road motion, m = s / (s + c) with s = v_h^2 and c = v_half^2, and its time
// derivatives; the second needs the horizontal jerk (N, E) and is 0 without it.
struct SpeedFade {
  double m = 0.0, dm = 0.0, ddm = 0.0;
};

SpeedFade speedFade(const Eigen::Vector3d& v_n, const Eigen::Vector3d& a_n, double v_half_m_s,
                    const double* jerk_ne = nullptr) {
  const double c = v_half_m_s * v_half_m_s;
  const double s = v_n.x() * v_n.x() + v_n.y() * v_n.y();
  const double ds = 2.0 * (v_n.x() * a_n.x() + v_n.y() * a_n.y());
  const double sc = s + c;
  SpeedFade f;
  f.m = s / sc;
  f.dm = c * ds / (sc * sc);
  if (jerk_ne) {
    const double dds =
        2.0 * (a_n.x() * a_n.x() + a_n.y() * a_n.y() + v_n.x() * jerk_ne[0] + v_n.y() * jerk_ne[1]);
    f.ddm = c * dds / (sc * sc) - 2.0 * c * ds * ds / (sc * sc * sc);
  }
  return f;
}

// Adds amplitude m(t) sin(2 pi f tau + phase) to an Euler angle and its time derivative to the
// angle's rate.
void addFadedSinusoid(double amplitude, double frequency_hz, double phase_rad, double tau,
                      const SpeedFade& fade, double* angle, double* rate) {
  const double w = 2.0 * units::kPi * frequency_hz;
  const double S = std::sin(w * tau + phase_rad), C = std::cos(w * tau + phase_rad);
  *angle += amplitude * fade.m * S;
  *rate += amplitude * (fade.dm * S + fade.m * w * C);
}

}  // namespace

std::vector<VibrationComponent> RoadVibrationOptions::linearComponents() const {
  std::mt19937_64 g(seed);
  return drawVibration(accel_rms_m_s2, kLinearShare, 2, *this, g);
}

std::vector<VibrationComponent> RoadVibrationOptions::angularComponents() const {
  std::mt19937_64 g(seed ^ 0x9e3779b97f4a7c15ULL);  // a stream independent of the linear one
  return drawVibration(gyro_rms_rad_s, kAngularShare, 1, *this, g);
}

void RoadVibrationOptions::validate() const {
  auto need = [](bool ok, const char* key, double v) {
    if (!ok) {
      throw std::invalid_argument(std::string("RoadVibrationOptions: bad ") + key + " = " +
                                  std::to_string(v));
    }
  };
  need(accel_rms_m_s2 >= 0.0 && std::isfinite(accel_rms_m_s2), "accel_rms_m_s2", accel_rms_m_s2);
  need(gyro_rms_rad_s >= 0.0 && std::isfinite(gyro_rms_rad_s), "gyro_rms_rad_s", gyro_rms_rad_s);
  if (!enabled()) return;
  need(band_low_hz > 0.0 && std::isfinite(band_low_hz), "band_low_hz", band_low_hz);
  need(band_high_hz >= band_low_hz && std::isfinite(band_high_hz), "band_high_hz", band_high_hz);
  need(components >= 3, "components (>= 3, one per axis)", components);
  need(half_amplitude_speed_m_s > 0.0, "half_amplitude_speed_m_s", half_amplitude_speed_m_s);
}

TrackTrajectory::~TrackTrajectory() = default;

namespace {

using Spline = TrackTrajectory::Spline;
using SplineAxes = std::unique_ptr<Spline>[3];

// The fixes in the tangent plane at `origin` and their relative weights (inverse variance).
struct TrackObservations {
  std::vector<double> t;
  std::vector<double> y[3], w0[3];
  std::vector<char> rejected;  // jumps the robust fit left out
};

TrackObservations trackObservations(const GnssSeries& track, const Geodetic& origin) {
  const std::size_t n = track.size();
  TrackObservations o;
  o.t.resize(n);
  o.rejected.assign(n, 0);
  for (int a = 0; a < 3; ++a) {
    o.y[a].resize(n);
    o.w0[a].resize(n);
  }
  std::vector<double> sig[3];
  for (std::size_t i = 0; i < n; ++i) {
    o.t[i] = track[i].t_s;
    const Eigen::Vector3d p = earth::nedFromGeodetic(origin, track[i].pos);
    for (int a = 0; a < 3; ++a) {
      o.y[a][i] = p[a];
      sig[a].push_back(track[i].std_ned_m[a]);
    }
  }
  for (int a = 0; a < 3; ++a) {
    double s_ref = median(sig[a]);
    if (!(s_ref > 0.0)) s_ref = 0.01;
    for (std::size_t i = 0; i < n; ++i) {
      const double s = sig[a][i] > 0.0 ? sig[a][i] : s_ref;
      o.w0[a][i] = (s_ref / s) * (s_ref / s);
    }
  }
  return o;
}

// P-splines of the three axes through yy with weights ww, rejected fixes weighted 0.
void fitPositions(SplineAxes& pos, double t_begin, double dt, int nseg, const TrackObservations& o,
                  const std::vector<double>* yy, const std::vector<double>* ww, double cutoff_hz) {
  for (int a = 0; a < 3; ++a) {
    pos[a] = std::make_unique<Spline>(t_begin, dt, nseg);
    std::vector<double> wa = ww[a];
    for (std::size_t i = 0; i < o.t.size(); ++i)
      if (o.rejected[i]) wa[i] = 0.0;
    pos[a]->fit(o.t, yy[a], wa, cutoff_hz);
  }
}

// One pass of the robust fit: marks fixes whose residual is far beyond the robust spread (jumps);
// returns whether any was newly marked.
bool rejectJumps(const SplineAxes& pos, TrackObservations& o, double outlier_sigma) {
  const std::size_t n = o.t.size();
  bool changed = false;
  for (int a = 0; a < 3; ++a) {
    std::vector<double> r(n), absr;
    for (std::size_t i = 0; i < n; ++i) {
      double d[1];
      pos[a]->eval(o.t[i], d, 0);
      r[i] = o.y[a][i] - d[0];
      if (!o.rejected[i]) absr.push_back(std::abs(r[i]));
    }
    const double s = 1.4826 * median(absr);
    const double thr = std::max(outlier_sigma * s, 0.2);
    for (std::size_t i = 0; i < n; ++i) {
      if (!o.rejected[i] && std::abs(r[i]) > thr) {
        o.rejected[i] = 1;
        changed = true;
      }
    }
  }
  return changed;
}

// Stops: runs of fixes with fitted speed below stop_speed are pinned to their mean position
// (y2, w2: the observations and weights of the final fit). Returns the number of stops.
int pinStops(const SplineAxes& pos, const TrackObservations& o, const TrackSmoothingOptions& opt,
             std::vector<double>* y2, std::vector<double>* w2) {
  const std::size_t n = o.t.size();
  auto slow = [&](std::size_t k) {
    double v2 = 0.0;
    for (int a = 0; a < 3; ++a) {
      double d[2];
      pos[a]->eval(o.t[k], d, 1);
      v2 += d[1] * d[1];
    }
    return std::sqrt(v2) < opt.stop_speed_m_s;
  };
  int stops = 0;
  std::size_t i = 0;
  while (i < n) {
    if (!slow(i)) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < n && slow(j)) ++j;
    if (static_cast<int>(j - i) >= opt.stop_min_epochs) {
      ++stops;
      for (int a = 0; a < 3; ++a) {
        double sum = 0.0;
        int cnt = 0;
        for (std::size_t k = i; k < j; ++k)
          if (!o.rejected[k]) {
            sum += o.y[a][k];
            ++cnt;
          }
        if (cnt == 0) continue;
        for (std::size_t k = i; k < j; ++k) {
          y2[a][k] = sum / cnt;
          w2[a][k] = 100.0 * o.w0[a][k];
        }
      }
    }
    i = j;
  }
  return stops;
}

void residualReport(const SplineAxes& pos, const TrackObservations& o, TrackFitReport* report) {
  for (std::size_t k = 0; k < o.t.size(); ++k) {
    if (o.rejected[k]) {
      ++report->fixes_rejected;
      continue;
    }
    ++report->fixes_used;
    for (int a = 0; a < 3; ++a) {
      double d[1];
      pos[a]->eval(o.t[k], d, 0);
      report->rms_residual_m[a] += (o.y[a][k] - d[0]) * (o.y[a][k] - d[0]);
    }
  }
  for (double& r : report->rms_residual_m) r = std::sqrt(r / std::max(1, report->fixes_used));
}

// Roll, pitch and yaw samples at 4 Hz from the smoothed motion: roll from the lateral
// acceleration, pitch and yaw along the velocity, held (and yaw unwrapped) below the hold speed.
void attitudeSamples(const SplineAxes& pos, double t_begin, double t_end,
                     const TrackSmoothingOptions& opt, std::vector<double>* ts,
                     std::vector<double>* ang) {
  const double g0 = units::kStandardGravity_m_s2;
  const int ns = static_cast<int>(std::floor((t_end - t_begin) * 4.0)) + 1;
  ts->resize(ns);
  std::vector<char> valid(ns, 0);
  for (int a = 0; a < 3; ++a) ang[a].resize(ns);
  for (int k = 0; k < ns; ++k) {
    (*ts)[k] = std::min(t_begin + 0.25 * k, t_end);
    Eigen::Vector3d v, acc;
    for (int a = 0; a < 3; ++a) {
      double d[3];
      pos[a]->eval((*ts)[k], d, 2);
      v[a] = d[1];
      acc[a] = d[2];
    }
    const double vh = std::hypot(v.x(), v.y());
    const double alat =
        (v.x() * acc.y() - v.y() * acc.x()) /
        std::sqrt(vh * vh + opt.lateral_speed_floor_m_s * opt.lateral_speed_floor_m_s);
    ang[0][k] = -opt.roll_per_lateral_g_rad * alat / g0;
    if (vh > opt.heading_hold_speed_m_s) {
      valid[k] = 1;
      ang[1][k] = std::atan2(-v.z(), vh);
      ang[2][k] = std::atan2(v.y(), v.x());
    }
  }
  int first = -1;
  for (int k = 0; k < ns && first < 0; ++k)
    if (valid[k]) first = k;
  double held_pitch = first >= 0 ? ang[1][first] : 0.0;
  double held_yaw = first >= 0 ? ang[2][first] : 0.0;
  for (int k = 0; k < ns; ++k) {
    if (valid[k]) {
      // Unwrap yaw against the previous sample.
      ang[2][k] = held_yaw + wrapAngle(ang[2][k] - held_yaw);
      held_pitch = ang[1][k];
      held_yaw = ang[2][k];
    } else {
      ang[1][k] = held_pitch;
      ang[2][k] = held_yaw;
    }
  }
}

void requireIncreasingFixes(const GnssSeries& track) {
  const std::size_t n = track.size();
  if (n < 10) {
    throw std::invalid_argument("TrackTrajectory: need at least 10 fixes, got " +
                                std::to_string(n));
  }
  for (std::size_t i = 1; i < n; ++i) {
    if (!(track[i].t_s > track[i - 1].t_s)) {
      throw std::invalid_argument("TrackTrajectory: time not increasing at fix " +
                                  std::to_string(i) + " (t=" + std::to_string(track[i].t_s) + ")");
    }
  }
}

}  // namespace

TrackTrajectory::TrackTrajectory(const GnssSeries& track, const TrackSmoothingOptions& opt)
    : TangentPlaneTrajectory(track.empty() ? Geodetic{} : track.front().pos), opt_(opt) {
  opt.validate();
  requireIncreasingFixes(track);
  t_begin_ = track.front().t_s;
  t_end_ = track.back().t_s;
  const double dt = opt.knot_spacing_s;
  const int nseg = static_cast<int>(std::ceil((t_end_ - t_begin_) / dt - 1e-9));

  TrackObservations o = trackObservations(track, origin());
  // Robust fit: reject fixes whose residual is far beyond the robust spread (jumps).
  fitPositions(pos_, t_begin_, dt, nseg, o, o.y, o.w0, opt.position_cutoff_hz);
  for (int iter = 0; iter < 3; ++iter) {
    if (!rejectJumps(pos_, o, opt.outlier_sigma)) break;
    fitPositions(pos_, t_begin_, dt, nseg, o, o.y, o.w0, opt.position_cutoff_hz);
  }
  std::vector<double> y2[3] = {o.y[0], o.y[1], o.y[2]};
  std::vector<double> w2[3] = {o.w0[0], o.w0[1], o.w0[2]};
  report_.stops += pinStops(pos_, o, opt, y2, w2);
  fitPositions(pos_, t_begin_, dt, nseg, o, y2, w2, opt.position_cutoff_hz);
  residualReport(pos_, o, &report_);

  // Attitude samples at 4 Hz from the smoothed motion, then fitted by their own P-splines.
  std::vector<double> ts, ang[3];
  attitudeSamples(pos_, t_begin_, t_end_, opt, &ts, ang);
  const std::vector<double> ws(ts.size(), 1.0);
  for (int a = 0; a < 3; ++a) {
    att_[a] = std::make_unique<Spline>(t_begin_, dt, nseg);
    att_[a]->fit(ts, ang[a], ws, opt.attitude_cutoff_hz);
  }
  if (opt.vibration.enabled()) {
    vib_linear_ = opt.vibration.linearComponents();
    vib_angular_ = opt.vibration.angularComponents();
  }
}

// Adds the vibration to the smoothed motion in k (k still without oscillations in v_n0, a_n0).
// With u(t) = m(t) A sin(w tau + phase):  u' = m' S + m A w C,  u'' = m'' S + 2 m' A w C - m A w^2 S.
// The horizontal displacement h = (forward, right) is rotated by the path yaw psi:
//   d = R(psi) h,  d' = R (h' + psi' J h),  d'' = R (h'' + 2 psi' J h' + psi'' J h - psi'^2 h),
// J = [[0, -1], [1, 0]]; the down displacement adds directly.
void TrackTrajectory::addVibration(double t_s, LocalKinematics& k) const {
  // The fade and its first two derivatives (the jerk is exact from the quintic position spline).
  double j[2];
  for (int a = 0; a < 2; ++a) {
    double d[4];
    pos_[a]->eval(t_s, d, 3);
    j[a] = d[3];
  }
  const SpeedFade fade = speedFade(k.v_n0, k.a_n0, opt_.vibration.half_amplitude_speed_m_s, j);
  const double m = fade.m, dm = fade.dm, ddm = fade.ddm;
  const double tau = t_s - t_begin_;

  Eigen::Vector3d h[3] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                          Eigen::Vector3d::Zero()};  // derivative order 0..2, axes fwd/right/down
  for (const auto& o : vib_linear_) {
    const double w = 2.0 * units::kPi * o.frequency_hz;
    const double S = o.amplitude * std::sin(w * tau + o.phase_rad);
    const double C = o.amplitude * std::cos(w * tau + o.phase_rad);
    h[0][o.axis] += m * S;
    h[1][o.axis] += dm * S + m * w * C;
    h[2][o.axis] += ddm * S + 2.0 * dm * w * C - m * w * w * S;
  }
  if (!vib_linear_.empty()) {
    double psi[3];
    att_[2]->eval(t_s, psi, 2);
    const double cp = std::cos(psi[0]), sp = std::sin(psi[0]);
    auto J = [](const Eigen::Vector3d& x) { return Eigen::Vector2d(-x.y(), x.x()); };
    const Eigen::Vector2d h1 = h[1].head<2>() + psi[1] * J(h[0]);
    const Eigen::Vector2d h2 = h[2].head<2>() + 2.0 * psi[1] * J(h[1]) + psi[2] * J(h[0]) -
                               psi[1] * psi[1] * h[0].head<2>();
    const Eigen::Vector2d hs[3] = {h[0].head<2>(), h1, h2};
    Eigen::Vector3d* out[3] = {&k.p_n0, &k.v_n0, &k.a_n0};
    for (int r = 0; r < 3; ++r) {
      (*out[r])[0] += cp * hs[r].x() - sp * hs[r].y();
      (*out[r])[1] += sp * hs[r].x() + cp * hs[r].y();
      (*out[r])[2] += h[r].z();
    }
  }
  for (const auto& o : vib_angular_)
    addFadedSinusoid(o.amplitude, o.frequency_hz, o.phase_rad, tau, fade, &k.euler_rad[o.axis],
                     &k.euler_rate_rad_s[o.axis]);
}

TangentPlaneTrajectory::LocalKinematics TrackTrajectory::local(double t_s) const {
  LocalKinematics k;
  for (int a = 0; a < 3; ++a) {
    double d[3];
    pos_[a]->eval(t_s, d, 2);
    k.p_n0[a] = d[0];
    k.v_n0[a] = d[1];
    k.a_n0[a] = d[2];
    double e[2];
    att_[a]->eval(t_s, e, 1);
    k.euler_rad[a] = e[0];
    k.euler_rate_rad_s[a] = e[1];
  }
  if (!opt_.oscillations.empty()) {
    const SpeedFade fade = speedFade(k.v_n0, k.a_n0, opt_.oscillation_speed_m_s);
    for (const auto& o : opt_.oscillations)
      addFadedSinusoid(o.amplitude_rad, o.frequency_hz, o.phase_rad, t_s - t_begin_, fade,
                       &k.euler_rad[o.euler_index], &k.euler_rate_rad_s[o.euler_index]);
  }
  if (!vib_linear_.empty() || !vib_angular_.empty()) addVibration(t_s, k);
  return k;
}

}  // namespace graftnav
