#include "graftnav/filters/ekf.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "graftnav/nav/distributions.h"

namespace graftnav {

using namespace ekf;

namespace {
constexpr double kTimeTol_s = 1e-6;

void symmetrize(ErrorCov& P) {
  P = 0.5 * (P + P.transpose()).eval();
  for (int i = 0; i < kStateDim; ++i) P(i, i) = std::max(P(i, i), 1e-300);
}

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
  gate_threshold_ = gate ? chiSquareQuantile(opt_.gate_probability, 3.0)
                         : std::numeric_limits<double>::infinity();
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
  symmetrize(P_);
  if (recording_) Phi_since_record_ = (Phi * Phi_since_record_).eval();
  sum_dtheta_.setZero();
  sum_dvel_.setZero();
  acc_dt_ = 0.0;
  sigma_valid_ = false;
}

bool GnssInsEkf::update(const Eigen::Vector3d& z, const Eigen::Matrix<double, 3, kStateDim>& H,
                        const Eigen::Vector3d& r_diag) {
  flushCovariance();
  const Eigen::Matrix<double, kStateDim, 3> PHt = P_ * H.transpose();
  Eigen::Matrix3d S = H * PHt;
  S.diagonal() += r_diag;
  const Eigen::LLT<Eigen::Matrix3d> llt(S);
  if (llt.info() != Eigen::Success) {
    throw std::runtime_error("GnssInsEkf::update: innovation covariance not positive at t=" +
                             std::to_string(nav_.t_s));
  }
  const double d2 = z.dot(llt.solve(z));
  if (d2 > gate_threshold_ && consecutive_rejected_ < opt_.max_consecutive_rejections) {
    ++rejected_;
    ++consecutive_rejected_;
    return false;
  }
  consecutive_rejected_ = 0;
  const ErrorCov P_prior = P_;
  const Eigen::Matrix<double, kStateDim, 3> K = llt.solve(PHt.transpose()).transpose();
  const ErrorState dx = K * z;
  ErrorCov IKH = ErrorCov::Identity();
  IKH.noalias() -= K * H;
  const ErrorCov tmp = IKH * P_;
  P_.noalias() = tmp * IKH.transpose();
  P_.noalias() += K * r_diag.asDiagonal() * K.transpose();
  symmetrize(P_);

  nav_ = correctNavState(nav_, dx);
  mech_.setState(nav_);
  sensors_.gyro_bias_rad_s += dx.segment<3>(kGyroBias);
  sensors_.accel_bias_m_s2 += dx.segment<3>(kAccelBias);
  sensors_.gyro_scale += dx.segment<3>(kGyroScale);
  sensors_.accel_scale += dx.segment<3>(kAccelScale);
  sigma_valid_ = false;
  if (recording_) pushRecord(dx, P_prior);
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
  return update(gnssPositionInnovation(nav_, lever_arm_b_m, fix.pos),
                gnssPositionJacobian(nav_, lever_arm_b_m), r);
}

bool GnssInsEkf::updateVelocity(const Eigen::Vector3d& v_ned_m_s, const Eigen::Vector3d& std_m_s,
                                const Eigen::Vector3d& lever_arm_b_m) {
  const Eigen::Vector3d z = antennaVelocity(nav_, last_omega_b_, lever_arm_b_m) - v_ned_m_s;
  return update(z, gnssVelocityJacobian(nav_, last_omega_b_, lever_arm_b_m),
                std_m_s.array().square().matrix());
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

void GnssInsEkf::pushRecord(const ErrorState& dx, const ErrorCov& P_prior) {
  if (!records_.empty() && std::abs(records_.back().t_s - nav_.t_s) < 1e-9) {
    // A second record at the same epoch (an interval record, then an update; or two updates):
    // merge them, keeping the first prior and transition and summing the corrections.
    SmootherRecord& b = records_.back();
    b.nav = nav_;
    b.sensors = sensors_;
    b.dx += dx;
    b.P_post = P_;
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
      t_cur_(problem.initial.t_s) {
  bookkeeping_.estimator = "ekf";
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
  t_cur_ = s.t_s;
  if (++processed_ % static_cast<size_t>(options_.output_decimation) == 0 && sink) {
    NavState st = filter_.state();
    st.t_s = s.t_s;
    st.gnss_week = gnss_week_;
    sink->add(st, &filter_.pvaSigma(), filter_.sensors());
  }
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
  sol.estimator = book.estimator;
  sol.gnss_used = book.gnss_used;
  sol.gnss_rejected = book.gnss_rejected;
  sol.gnss_withheld = book.gnss_withheld;
  if (progress) progress(1.0);
  return sol;
}

}  // namespace graftnav
