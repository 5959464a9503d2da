#include "graftnav/filters/rts_smoother.h"

#include <Eigen/Cholesky>
#include <stdexcept>

#include "graftnav/nav/mechanization.h"

namespace graftnav {

using namespace ekf;

namespace {
constexpr double kTimeTol_s = 1e-6;

ImuErrorEstimate correctSensors(ImuErrorEstimate s, const ErrorState& e) {
  s.gyro_bias_rad_s += e.segment<3>(kGyroBias);
  s.accel_bias_m_s2 += e.segment<3>(kAccelBias);
  s.gyro_scale += e.segment<3>(kGyroScale);
  s.accel_scale += e.segment<3>(kAccelScale);
  return s;
}

PvaSigma sigmaOf(const SmoothedRecord& r) {
  const Eigen::Matrix<double, 9, 9> J = psiToPhiJacobian(r.nav);
  const Eigen::Matrix<double, 9, 9> C = J * r.P.topLeftCorner<9, 9>() * J.transpose();
  return C.diagonal().cwiseMax(0.0).cwiseSqrt();
}
}  // namespace

std::vector<SmoothedRecord> smoothRecords(const std::vector<SmootherRecord>& rec) {
  const size_t N = rec.size();
  std::vector<SmoothedRecord> out(N);
  if (N == 0) return out;
  ErrorState e_next = ErrorState::Zero();
  ErrorCov Ps_next = rec[N - 1].P_post;
  out[N - 1] = {rec[N - 1].t_s, rec[N - 1].nav, rec[N - 1].sensors, Ps_next};
  for (size_t k = N - 1; k-- > 0;) {
    const SmootherRecord& a = rec[k];
    const SmootherRecord& b = rec[k + 1];
    // G^T = (P^-)^-1 Phi P^+, solved on the diagonally scaled P^- (states span ~20 decades).
    const ErrorState d = b.P_prior.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    const ErrorCov A = d.asDiagonal() * b.P_prior * d.asDiagonal();
    const ErrorCov rhs = d.asDiagonal() * (b.Phi * a.P_post);
    const Eigen::LDLT<ErrorCov> ldlt(A);
    if (ldlt.info() != Eigen::Success) {
      throw std::runtime_error("smoothRecords: predicted covariance not invertible at t=" +
                               std::to_string(b.t_s));
    }
    const ErrorCov Gt = d.asDiagonal() * ldlt.solve(rhs);
    const ErrorState e = Gt.transpose() * (e_next + b.dx);
    ErrorCov Ps = a.P_post + Gt.transpose() * (Ps_next - b.P_prior) * Gt;
    Ps = 0.5 * (Ps + Ps.transpose()).eval();
    SmoothedRecord& s = out[k];
    s.t_s = a.t_s;
    s.nav = correctNavState(a.nav, e);
    s.sensors = correctSensors(a.sensors, e);
    s.P = Ps;
    e_next = e;
    Ps_next = Ps;
  }
  return out;
}

NavSolution runRts(const EstimationProblem& problem, const EkfOptions& options, NavSolution* forward,
                   RtsStats* stats, const ProgressFn& progress) {
  std::vector<SmootherRecord> records;
  ProgressFn fwd_progress;
  if (progress) fwd_progress = [&](double f) { progress(0.6 * f); };
  NavSolution fwd = runEkf(problem, options, &records, fwd_progress, forward != nullptr);
  if (stats) {
    stats->records = records.size();
    stats->record_bytes = records.size() * sizeof(SmootherRecord);
  }
  const std::vector<SmoothedRecord> sm = smoothRecords(records);
  records.clear();
  records.shrink_to_fit();
  if (progress) progress(0.7);

  NavSolution sol;
  sol.estimator = "rts";
  sol.gnss_used = fwd.gnss_used;
  sol.gnss_rejected = fwd.gnss_rejected;
  sol.gnss_withheld = fwd.gnss_withheld;
  const size_t reserve =
      problem.imu.size() / static_cast<size_t>(options.output_decimation) + 1;
  sol.states.reserve(reserve);
  sol.sigma.reserve(reserve);
  sol.gyro_bias_rad_s.reserve(reserve);
  sol.accel_bias_m_s2.reserve(reserve);
  sol.gyro_scale.reserve(reserve);
  sol.accel_scale.reserve(reserve);
  if (forward) *forward = std::move(fwd);

  const ImuSeries& imu = problem.imu;
  size_t j = 0;
  while (j < imu.size() && imu[j].t_s <= sm.front().t_s + kTimeTol_s) ++j;
  std::vector<NavState> buffer;
  size_t processed = 0;
  const auto decim = static_cast<size_t>(options.output_decimation);
  for (size_t k = 0; k + 1 < sm.size(); ++k) {
    const double t0 = sm[k].t_s, t1 = sm[k + 1].t_s;
    if (!(t1 > t0 + kTimeTol_s)) continue;
    Strapdown sd(sm[k].nav);
    buffer.clear();
    while (j < imu.size() && imu[j].t_s - imu[j].dt_s < t1 - kTimeTol_s) {
      const ImuSample piece = sliceImuSample(imu[j], t0, t1);
      if (piece.dt_s > 0.0) sd.step(correctImuSample(piece, sm[k].sensors));
      if (imu[j].t_s <= t1 + kTimeTol_s) {
        NavState st = sd.state();
        st.t_s = imu[j].t_s;
        buffer.push_back(st);
        ++j;
      } else {
        break;  // the sample straddles t1: its remainder belongs to the next interval
      }
    }
    if (buffer.empty()) continue;
    ErrorState mismatch = ErrorState::Zero();
    mismatch.head<9>() = navErrorPsi(sd.state(), sm[k + 1].nav);
    const PvaSigma s0 = sigmaOf(sm[k]), s1 = sigmaOf(sm[k + 1]);
    for (const NavState& st : buffer) {
      if (++processed % decim != 0) continue;  // keep the N-th, 2N-th, ... epoch
      const double u = std::clamp((st.t_s - t0) / (t1 - t0), 0.0, 1.0);
      NavState out = correctNavState(st, u * mismatch);
      out.t_s = st.t_s;
      out.gnss_week = problem.initial.gnss_week;
      sol.states.push_back(out);
      sol.sigma.push_back((1.0 - u) * s0 + u * s1);
      const ImuErrorEstimate& a = sm[k].sensors;
      const ImuErrorEstimate& b = sm[k + 1].sensors;
      sol.gyro_bias_rad_s.push_back((1.0 - u) * a.gyro_bias_rad_s + u * b.gyro_bias_rad_s);
      sol.accel_bias_m_s2.push_back((1.0 - u) * a.accel_bias_m_s2 + u * b.accel_bias_m_s2);
      sol.gyro_scale.push_back((1.0 - u) * a.gyro_scale + u * b.gyro_scale);
      sol.accel_scale.push_back((1.0 - u) * a.accel_scale + u * b.accel_scale);
    }
  }
  if (progress) progress(1.0);
  return sol;
}

}  // namespace graftnav
