#include "graftnav/filters/ekf.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "graftnav/filters/kalman_update.h"
#include "graftnav/nav/distributions.h"

namespace graftnav {

using namespace ekf;

namespace {
constexpr double kTimeTol_s = 1e-6;
}  // namespace

ImuSample sliceImuSample(const ImuSample& s, double t_from, double t_to) {
  const double start = s.t_s - s.dt_s;
  const double a = std::max(t_from, start), b = std::min(t_to, s.t_s);
  if (a <= start + kTimeTol_s * 1e-3 && b >= s.t_s - kTimeTol_s * 1e-3) return s;
  ImuSample out = s;
  out.t_s = b;
  out.dt_s = std::max(0.0, b - a);
  const double frac = s.dt_s > 0.0 ? out.dt_s / s.dt_s : 0.0;
  out.dtheta_rad = s.dtheta_rad * frac;
  out.dvel_m_s = s.dvel_m_s * frac;
  return out;
}

ErrorCov initialCovariance(const EstimationProblem& problem, const EkfOptions& o) {
  ErrorState sd = ErrorState::Zero();
  const ImuProfile& p = problem.imu_profile;
  if ((problem.initial_sigma.array() >= 0.0).all() && problem.initial_sigma.allFinite()) {
    sd.head<9>() = problem.initial_sigma;
  } else {
    sd.segment<3>(kPos).setConstant(o.init_pos_std_m);
    sd.segment<3>(kVel).setConstant(o.init_vel_std_m_s);
    sd.segment<3>(kAtt) << o.init_roll_pitch_std_rad, o.init_roll_pitch_std_rad,
        o.init_heading_std_rad;
  }
  const double bg = p.gyro_bias_initial_std_rad_s > 0 ? p.gyro_bias_initial_std_rad_s
                                                      : p.gyro_bias_instability_rad_s;
  const double ba = p.accel_bias_initial_std_m_s2 > 0 ? p.accel_bias_initial_std_m_s2
                                                      : p.accel_bias_instability_m_s2;
  // Floors keep P invertible for the smoother when a profile gives zero (far below any IMU).
  sd.segment<3>(kGyroBias).setConstant(std::max(bg, 1e-10));
  sd.segment<3>(kAccelBias).setConstant(std::max(ba, 1e-8));
  sd.segment<3>(kGyroScale).setConstant(std::max(p.gyro_scale_std, 1e-9));
  sd.segment<3>(kAccelScale).setConstant(std::max(p.accel_scale_std, 1e-9));
  for (int i = 0; i < 9; ++i) sd[i] = std::max(sd[i], 1e-9);
  return sd.array().square().matrix().asDiagonal();
}

GnssInsEkf::GnssInsEkf(const NavState& initial, const ErrorCov& P0, const ImuProfile& profile,
                       const EkfOptions& options)
    : opt_(options),
      profile_(profile),
      qc_(continuousNoiseDensity(profile)),
      mech_(initial),
      nav_(initial),
      P_(P0),
      last_record_t_(initial.t_s) {
  opt_.validate();
  const bool gate = opt_.gate_probability > 0.0 && opt_.gate_probability < 1.0;
  for (int m = 1; m <= 3; ++m) {
    const double t = gate ? chiSquareQuantile(opt_.gate_probability, static_cast<double>(m))
                          : std::numeric_limits<double>::infinity();
    gnss_gate_.threshold[m] = vehicle_gate_.threshold[m] = t;
  }
}

void GnssInsEkf::enableOdometerScale(double sigma0, double random_walk_per_sqrt_s) {
  if (!(sigma0 > 0.0) || !(random_walk_per_sqrt_s >= 0.0)) {
    throw std::invalid_argument(
        "GnssInsEkf::enableOdometerScale: sigma0 must be > 0 and the "
        "random walk >= 0");
  }
  has_scale_ = true;
  scale_ = OdometerScaleState{};
  scale_.P_kk = sigma0 * sigma0;
  scale_.q_per_s = random_walk_per_sqrt_s * random_walk_per_sqrt_s;
}

void GnssInsEkf::enableRecording(bool on) {
  recording_ = on;
  records_.clear();
  Phi_since_record_.setIdentity();
  if (on) {
    flushCovariance();
    pushRecord(ErrorState::Zero(), P_);
  }
}

void GnssInsEkf::propagate(const ImuSample& raw) {
  if (!(raw.dt_s > 0.0)) return;  // an empty slice
  const ImuSample s = correctImuSample(raw, sensors_);
  mech_.step(s);
  nav_ = mech_.state();
  sum_dtheta_ += s.dtheta_rad;
  sum_dvel_ += s.dvel_m_s;
  acc_dt_ += s.dt_s;
  last_omega_b_ = s.dtheta_rad / s.dt_s;
  if (acc_dt_ >= opt_.covariance_interval_s - 1e-9) {
    flushCovariance();
    if (recording_ && nav_.t_s - last_record_t_ >= opt_.record_interval_s - 1e-9) {
      pushRecord(ErrorState::Zero(), P_);
    }
  }
}

void GnssInsEkf::flushCovariance() {
  if (acc_dt_ <= 0.0) return;
  const ErrorCov F = errorDynamics(nav_, sum_dtheta_ / acc_dt_, sum_dvel_ / acc_dt_, profile_);
  ErrorCov Phi, Qd;
  discretize(F, qc_, acc_dt_, &Phi, &Qd);
  propagateCovariance(Phi, Qd, &P_);
  symmetrizeCovariance<kStateDim>(P_);
  if (has_scale_) {
    scale_.P_xk = (Phi * scale_.P_xk).eval();
    scale_.P_kk += scale_.q_per_s * acc_dt_;
  }
  if (recording_) Phi_since_record_ = (Phi * Phi_since_record_).eval();
  sum_dtheta_.setZero();
  sum_dvel_.setZero();
  acc_dt_ = 0.0;
  sigma_valid_ = false;
}

bool GnssInsEkf::accept(Gate& gate, int rows, double d2) {
  if (d2 > gate.threshold[rows] && gate.consecutive < opt_.max_consecutive_rejections) {
    ++gate.rejected;
    ++gate.consecutive;
    return false;
  }
  gate.consecutive = 0;
  ++gate.used;
  return true;
}

void GnssInsEkf::applyCorrection(const ErrorState& dx) {
  nav_ = correctNavState(nav_, dx);
  mech_.setState(nav_);
  sensors_.gyro_bias_rad_s += dx.segment<3>(kGyroBias);
  sensors_.accel_bias_m_s2 += dx.segment<3>(kAccelBias);
  sensors_.gyro_scale += dx.segment<3>(kGyroScale);
  sensors_.accel_scale += dx.segment<3>(kAccelScale);
  sigma_valid_ = false;
}

// Without the scale state: the 21-state update. With it: the same on the 22 states, assembled
// from P, P_xk and P_kk and split back; H_k is the measurement's derivative by the scale.
template <int M>
bool GnssInsEkf::update(const Eigen::Matrix<double, M, 1>& z,
                        const Eigen::Matrix<double, M, kStateDim>& H,
                        const Eigen::Matrix<double, M, 1>& r_diag,
                        const Eigen::Matrix<double, M, 1>& H_k, Gate& gate) {
  flushCovariance();
  if (!has_scale_) {
    ErrorCov P_prior;
    ErrorState dx;
    const bool ok = josephUpdate<kStateDim, M>(
        P_, z, H, r_diag, nav_.t_s,
        [&](double d2) {
          P_prior = P_;
          return accept(gate, M, d2);
        },
        &dx);
    if (!ok) return false;
    applyCorrection(dx);
    if (recording_) pushRecord(dx, P_prior);
    return true;
  }
  constexpr int N = kStateDim + 1;
  Eigen::Matrix<double, N, N> P;
  P.topLeftCorner<kStateDim, kStateDim>() = P_;
  P.topRightCorner<kStateDim, 1>() = scale_.P_xk;
  P.bottomLeftCorner<1, kStateDim>() = scale_.P_xk.transpose();
  P(kStateDim, kStateDim) = scale_.P_kk;
  Eigen::Matrix<double, M, N> Ha;
  Ha << H, H_k;
  ErrorCov P_prior;
  const OdometerScaleState scale_prior = scale_;
  Eigen::Matrix<double, N, 1> dx;
  const bool ok = josephUpdate<N, M>(
      P, z, Ha, r_diag, nav_.t_s,
      [&](double d2) {
        P_prior = P_;
        return accept(gate, M, d2);
      },
      &dx);
  if (!ok) return false;
  P_ = P.template topLeftCorner<kStateDim, kStateDim>();
  scale_.P_xk = P.template topRightCorner<kStateDim, 1>();
  scale_.P_kk = P(kStateDim, kStateDim);
  scale_.k += dx(kStateDim);
  applyCorrection(dx.template head<kStateDim>());
  if (recording_) pushRecord(dx.template head<kStateDim>(), P_prior, dx(kStateDim), &scale_prior);
  return true;
}

bool GnssInsEkf::updatePosition(const GnssFix& fix, const Eigen::Vector3d& lever_arm_b_m) {
  Eigen::Vector3d r;
  for (int i = 0; i < 3; ++i) {
    double sd = fix.std_ned_m[i];
    if (!(sd > 0.0) || !std::isfinite(sd)) sd = opt_.gnss_default_std_m;
    sd = std::max(sd * opt_.gnss_std_scale, opt_.gnss_std_floor_m);
    r[i] = sd * sd;
  }
  return update<3>(gnssPositionInnovation(nav_, lever_arm_b_m, fix.pos),
                   gnssPositionJacobian(nav_, lever_arm_b_m), r, Eigen::Vector3d::Zero(),
                   gnss_gate_);
}

bool GnssInsEkf::updateVelocity(const Eigen::Vector3d& v_ned_m_s, const Eigen::Vector3d& std_m_s,
                                const Eigen::Vector3d& lever_arm_b_m) {
  const Eigen::Vector3d z = antennaVelocity(nav_, last_omega_b_, lever_arm_b_m) - v_ned_m_s;
  return update<3>(z, gnssVelocityJacobian(nav_, last_omega_b_, lever_arm_b_m),
                   std_m_s.array().square().matrix(), Eigen::Vector3d::Zero(), gnss_gate_);
}

template <int M>
bool GnssInsEkf::updateRows(const Eigen::Vector3d& z, const Eigen::Matrix<double, 3, kStateDim>& H,
                            const Eigen::Vector3d& r, const Eigen::Vector3d& H_k, const int* rows) {
  Eigen::Matrix<double, M, 1> zm, rm, hm;
  Eigen::Matrix<double, M, kStateDim> Hm;
  for (int i = 0; i < M; ++i) {
    zm(i) = z(rows[i]);
    rm(i) = r(rows[i]);
    hm(i) = H_k(rows[i]);
    Hm.row(i) = H.row(rows[i]);
  }
  return update<M>(zm, Hm, rm, hm, vehicle_gate_);
}

bool GnssInsEkf::updateVehicleVelocity(const VehicleGeometry& g, const Eigen::Vector3d& row_std_m_s,
                                       const double* speed_m_s) {
  const Eigen::Vector3d v_v = vehicleVelocity(nav_, last_omega_b_, g);
  Eigen::Matrix<double, 3, kStateDim> H = vehicleVelocityJacobian(nav_, last_omega_b_, g);
  Eigen::Vector3d z = v_v, H_k = Eigen::Vector3d::Zero();
  int rows[3], m = 0;
  if (speed_m_s && row_std_m_s.x() > 0.0) {
    // s = (1 + k) v_v.x: the computed reading minus the measured one.
    const double gain = has_scale_ ? 1.0 + scale_.k : 1.0;
    z.x() = gain * v_v.x() - *speed_m_s;
    H.row(0) *= gain;
    H_k.x() = -v_v.x();
    rows[m++] = 0;
  }
  for (int i = 1; i < 3; ++i)
    if (row_std_m_s(i) > 0.0) rows[m++] = i;
  const Eigen::Vector3d r = row_std_m_s.cwiseAbs2();
  switch (m) {
    case 1:
      return updateRows<1>(z, H, r, H_k, rows);
    case 2:
      return updateRows<2>(z, H, r, H_k, rows);
    case 3:
      return updateRows<3>(z, H, r, H_k, rows);
    default:
      return false;
  }
}

const PvaSigma& GnssInsEkf::pvaSigma() {
  if (!sigma_valid_) {
    const Eigen::Matrix<double, 9, 9> J = psiToPhiJacobian(nav_);
    const Eigen::Matrix<double, 9, 9> C = J * P_.topLeftCorner<9, 9>() * J.transpose();
    sigma_ = C.diagonal().cwiseMax(0.0).cwiseSqrt();
    sigma_valid_ = true;
  }
  return sigma_;
}

void GnssInsEkf::recordNow() {
  flushCovariance();
  if (recording_ && (records_.empty() || nav_.t_s > records_.back().t_s)) {
    pushRecord(ErrorState::Zero(), P_);
  }
}

void GnssInsEkf::pushRecord(const ErrorState& dx, const ErrorCov& P_prior, double dk,
                            const OdometerScaleState* scale_prior) {
  if (!records_.empty() && std::abs(records_.back().t_s - nav_.t_s) < 1e-9) {
    // A second record at the same epoch (an interval record, then an update; or two updates):
    // merge them, keeping the first prior and transition and summing the corrections.
    SmootherRecord& b = records_.back();
    b.nav = nav_;
    b.sensors = sensors_;
    b.dx += dx;
    b.P_post = P_;
    b.dk += dk;
    b.scale_post = scale_;
    Phi_since_record_.setIdentity();
    return;
  }
  SmootherRecord r;
  r.t_s = nav_.t_s;
  r.nav = nav_;
  r.sensors = sensors_;
  r.dx = dx;
  r.P_prior = P_prior;
  r.P_post = P_;
  r.Phi = Phi_since_record_;
  r.has_scale = has_scale_;
  r.scale_prior = scale_prior ? *scale_prior : scale_;
  r.scale_post = scale_;
  r.dk = dk;
  records_.push_back(r);
  Phi_since_record_.setIdentity();
  last_record_t_ = nav_.t_s;
}

EkfPass::EkfPass(const EstimationProblem& problem, const EkfOptions& options, bool record)
    : options_(options),
      gnss_(problem),
      lever_arm_b_m_(problem.lever_arm_b_m),
      gnss_week_(problem.initial.gnss_week),
      filter_(problem.initial, initialCovariance(problem, options), problem.imu_profile, options),
      t_cur_(problem.initial.t_s),
      aiding_(problem.aiding),
      t0_(problem.initial.t_s) {
  bookkeeping_.estimator = "ekf";
  if (aiding_.any()) {
    aiding_.validate();
    vehicle_.C_vb = aiding_.C_vb();
    vehicle_.lever_arm_b_m = aiding_.odometer.lever_arm_b_m;
    if (aiding_.odometer.enabled) {
      odometer_ = std::make_unique<OdometerInterpolator>(problem.openOdometer(),
                                                         aiding_.odometer.max_gap_s);
    }
    if (aiding_.odometer.estimatesScale()) {
      filter_.enableOdometerScale(aiding_.odometer.scale_std,
                                  aiding_.odometer.scale_random_walk_per_sqrt_s);
    }
  }
  filter_.enableRecording(record);
  for (const GnssFix* f; (f = gnss_.peek()) && f->t_s < t_cur_ - kTimeTol_s;)
    gnss_.pop();  // before the start
  for (const GnssFix* f; (f = gnss_.peek()) && f->t_s <= t_cur_ + kTimeTol_s;)
    applyNextFix();  // at it
}

void EkfPass::applyNextFix() {
  if (filter_.updatePosition(*gnss_.peek(), lever_arm_b_m_)) ++bookkeeping_.gnss_used;
  gnss_.pop();
}

void EkfPass::add(const ImuSample& s, SolutionSink* sink) {
  if (s.t_s <= t_cur_ + kTimeTol_s) return;
  double piece_start = std::max(s.t_s - s.dt_s, t_cur_);
  for (const GnssFix* f; (f = gnss_.peek()) && f->t_s < s.t_s - kTimeTol_s;) {
    const double tg = f->t_s;
    if (tg > piece_start + kTimeTol_s) {
      filter_.propagate(sliceImuSample(s, piece_start, tg));
      piece_start = tg;
    }
    applyNextFix();
  }
  filter_.propagate(sliceImuSample(s, piece_start, s.t_s));
  for (const GnssFix* f; (f = gnss_.peek()) && f->t_s <= s.t_s + kTimeTol_s;) applyNextFix();
  if (aiding_.any()) aidVehicle(s.t_s);
  t_cur_ = s.t_s;
  if (++processed_ % static_cast<size_t>(options_.output_decimation) == 0 && sink) {
    NavState st = filter_.state();
    st.t_s = s.t_s;
    st.gnss_week = gnss_week_;
    if (filter_.estimatesOdometerScale()) {
      const OdometerScaleState& k = filter_.odometerScale();
      sink->addOdometerScale({k.k, std::sqrt(std::max(k.P_kk, 0.0))});
    }
    sink->add(st, &filter_.pvaSigma(), filter_.sensors());
  }
}

void EkfPass::aidVehicle(double t_s) {
  const double period = 1.0 / aiding_.rateHz();
  if (t_s < t0_ + static_cast<double>(next_aid_) * period - kTimeTol_s) return;
  while (t0_ + static_cast<double>(next_aid_) * period <= t_s + kTimeTol_s) ++next_aid_;
  double speed = 0.0;
  const bool has_speed = odometer_ && odometer_->at(t_s, &speed);
  filter_.updateVehicleVelocity(vehicle_, aiding_.rowStd_m_s(), has_speed ? &speed : nullptr);
}

NavSolution EkfPass::finish(SmootherRecords* records) {
  if (processed_ == 0) {
    throw std::invalid_argument("runEkf: no IMU sample after the initial time " +
                                std::to_string(t_cur_));
  }
  filter_.recordNow();
  gnss_.skipRest();
  bookkeeping_.gnss_withheld = gnss_.withheld();
  bookkeeping_.gnss_rejected = filter_.rejected();
  bookkeeping_.vehicle_used = filter_.vehicleUsed();
  bookkeeping_.vehicle_rejected = filter_.vehicleRejected();
  if (records) *records = std::move(filter_.records());
  return bookkeeping_;
}

NavSolution runEkfStreaming(const EstimationProblem& problem, const EkfOptions& options,
                            const ImuPassFn& imu, SolutionSink& sink) {
  options.validate();
  EkfPass pass(problem, options, false);
  imu([&](const ImuSeries& block) {
    for (const ImuSample& s : block) pass.add(s, &sink);
  });
  return pass.finish();
}

NavSolution runEkf(const EstimationProblem& problem, const EkfOptions& options,
                   SmootherRecords* records, const ProgressFn& progress, bool keep_states) {
  options.validate();
  if (problem.imu.empty()) throw std::invalid_argument("runEkf: the IMU series is empty");
  EkfPass pass(problem, options, records != nullptr);
  NavSolution sol;
  NavSolutionSink sink(&sol);
  const size_t n = problem.imu.size();
  if (keep_states) sink.reserve(n / static_cast<size_t>(options.output_decimation) + 1);
  const size_t progress_step = std::max<size_t>(1, n / 100);
  for (size_t j = 0; j < n; ++j) {
    if (progress && j % progress_step == 0) progress(static_cast<double>(j) / n);
    pass.add(problem.imu[j], keep_states ? &sink : nullptr);
  }
  const NavSolution book = pass.finish(records);
  sol.copyBookkeeping(book);
  if (progress) progress(1.0);
  return sol;
}

}  // namespace graftnav
