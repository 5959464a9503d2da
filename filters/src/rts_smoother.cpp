#include "graftnav/filters/rts_smoother.h"

#include <Eigen/Cholesky>
#include <algorithm>
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

namespace {

// One backward step on N states (21, or 22 with the odometer scale): from the smoothed error
// and covariance at record k+1 (e_next, Ps_next) to those at k, given P^+_k, and P^-_{k+1},
// Phi_{k+1} and the correction dx_{k+1} fed back at k+1. Throws naming t_next when P^- is not
// invertible.
template <int N>
void smoothStep(const Eigen::Matrix<double, N, N>& P_post,
                const Eigen::Matrix<double, N, N>& P_prior_next,
                const Eigen::Matrix<double, N, N>& Phi_next,
                const Eigen::Matrix<double, N, 1>& dx_next, double t_next,
                Eigen::Matrix<double, N, 1>* e, Eigen::Matrix<double, N, N>* Ps) {
  using Vec = Eigen::Matrix<double, N, 1>;
  using Mat = Eigen::Matrix<double, N, N>;
  // G^T = (P^-)^-1 Phi P^+, solved on the diagonally scaled P^- (states span ~20 decades).
  const Vec d = P_prior_next.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const Mat A = d.asDiagonal() * P_prior_next * d.asDiagonal();
  const Mat rhs = d.asDiagonal() * (Phi_next * P_post);
  const Eigen::LDLT<Mat> ldlt(A);
  if (ldlt.info() != Eigen::Success) {
    throw std::runtime_error("smoothRecords: predicted covariance not invertible at t=" +
                             std::to_string(t_next));
  }
  const Mat Gt = d.asDiagonal() * ldlt.solve(rhs);
  const Vec e_k = Gt.transpose() * (*e + dx_next);
  Mat Ps_k = P_post + Gt.transpose() * (*Ps - P_prior_next) * Gt;
  Ps_k = 0.5 * (Ps_k + Ps_k.transpose()).eval();
  *e = e_k;
  *Ps = Ps_k;
}

using Cov22 = Eigen::Matrix<double, kStateDim + 1, kStateDim + 1>;
using State22 = Eigen::Matrix<double, kStateDim + 1, 1>;

Cov22 withScale(const ErrorCov& P, const OdometerScaleState& k) {
  Cov22 out;
  out.topLeftCorner<kStateDim, kStateDim>() = P;
  out.topRightCorner<kStateDim, 1>() = k.P_xk;
  out.bottomLeftCorner<1, kStateDim>() = k.P_xk.transpose();
  out(kStateDim, kStateDim) = k.P_kk;
  return out;
}

// The record's nominal corrected by the smoothed error e (its first 21 states).
void setSmoothed(const SmootherRecord& a, const ErrorState& e, const ErrorCov& P,
                 SmoothedRecord* s) {
  s->t_s = a.t_s;
  s->nav = correctNavState(a.nav, e);
  s->sensors = correctSensors(a.sensors, e);
  s->P = P;
}

// The records carry the odometer scale: the same recursion on the 22 states (the scale's
// transition is 1, so Phi is extended by a unit diagonal).
std::vector<SmoothedRecord> smoothRecordsWithScale(const SmootherRecords& rec) {
  const size_t N = rec.size();
  std::vector<SmoothedRecord> out(N);
  State22 e_next = State22::Zero();
  Cov22 Ps_next = withScale(rec[N - 1].P_post, rec[N - 1].scale_post);
  for (size_t k = N; k-- > 0;) {
    const SmootherRecord& a = rec[k];
    if (k + 1 < N) {
      const SmootherRecord& b = rec[k + 1];
      Cov22 Phi = Cov22::Zero();
      Phi.topLeftCorner<kStateDim, kStateDim>() = b.Phi;
      Phi(kStateDim, kStateDim) = 1.0;
      State22 dx;
      dx << b.dx, b.dk;
      smoothStep<kStateDim + 1>(withScale(a.P_post, a.scale_post),
                                withScale(b.P_prior, b.scale_prior), Phi, dx, b.t_s, &e_next,
                                &Ps_next);
    }
    setSmoothed(a, e_next.head<kStateDim>(), Ps_next.topLeftCorner<kStateDim, kStateDim>(),
                &out[k]);
    out[k].has_scale = true;
    out[k].scale = a.scale_post.k + e_next(kStateDim);
    out[k].scale_std = std::sqrt(std::max(Ps_next(kStateDim, kStateDim), 0.0));
  }
  return out;
}

}  // namespace

std::vector<SmoothedRecord> smoothRecords(const SmootherRecords& rec) {
  const size_t N = rec.size();
  if (N == 0) return {};
  if (rec.front().has_scale) return smoothRecordsWithScale(rec);
  std::vector<SmoothedRecord> out(N);
  ErrorState e_next = ErrorState::Zero();
  ErrorCov Ps_next = rec[N - 1].P_post;
  out[N - 1] = {rec[N - 1].t_s, rec[N - 1].nav, rec[N - 1].sensors, Ps_next};
  for (size_t k = N - 1; k-- > 0;) {
    const SmootherRecord& a = rec[k];
    const SmootherRecord& b = rec[k + 1];
    smoothStep<kStateDim>(a.P_post, b.P_prior, b.Phi, b.dx, b.t_s, &e_next, &Ps_next);
    setSmoothed(a, e_next, Ps_next, &out[k]);
  }
  return out;
}

RtsOutputPass::RtsOutputPass(std::vector<SmoothedRecord> smoothed, int output_decimation,
                             int gnss_week)
    : sm_(std::move(smoothed)),
      decimation_(static_cast<std::size_t>(std::max(output_decimation, 1))),
      gnss_week_(gnss_week),
      strapdown_(sm_.empty() ? NavState{} : sm_.front().nav) {
  buffer_.reserve(1024);
}

bool RtsOutputPass::openInterval(std::size_t k) {
  while (k + 1 < sm_.size() && !(sm_[k + 1].t_s > sm_[k].t_s + kTimeTol_s)) ++k;
  k_ = k;
  open_ = k + 1 < sm_.size();
  if (open_) strapdown_ = Strapdown(sm_[k].nav);
  buffer_.clear();
  return open_;
}

void RtsOutputPass::closeInterval(SolutionSink& sink) {
  if (!open_ || buffer_.empty()) return;
  const SmoothedRecord& a = sm_[k_];
  const SmoothedRecord& b = sm_[k_ + 1];
  const double t0 = a.t_s, t1 = b.t_s;
  ErrorState mismatch = ErrorState::Zero();
  mismatch.head<9>() = navErrorPsi(strapdown_.state(), b.nav);
  const PvaSigma s0 = sigmaOf(a), s1 = sigmaOf(b);
  for (const NavState& st : buffer_) {
    if (++processed_ % decimation_ != 0) continue;  // keep the N-th, 2N-th, ... epoch
    const double u = std::clamp((st.t_s - t0) / (t1 - t0), 0.0, 1.0);
    NavState out = correctNavState(st, u * mismatch);
    out.t_s = st.t_s;
    out.gnss_week = gnss_week_;
    ImuErrorEstimate sensors;
    sensors.gyro_bias_rad_s = (1.0 - u) * a.sensors.gyro_bias_rad_s + u * b.sensors.gyro_bias_rad_s;
    sensors.accel_bias_m_s2 = (1.0 - u) * a.sensors.accel_bias_m_s2 + u * b.sensors.accel_bias_m_s2;
    sensors.gyro_scale = (1.0 - u) * a.sensors.gyro_scale + u * b.sensors.gyro_scale;
    sensors.accel_scale = (1.0 - u) * a.sensors.accel_scale + u * b.sensors.accel_scale;
    const PvaSigma sigma = (1.0 - u) * s0 + u * s1;
    if (a.has_scale) {
      sink.addOdometerScale(
          {(1.0 - u) * a.scale + u * b.scale, (1.0 - u) * a.scale_std + u * b.scale_std});
    }
    sink.add(out, &sigma, sensors);
  }
  buffer_.clear();
}

void RtsOutputPass::add(const ImuSample& s, SolutionSink& sink) {
  if (sm_.empty()) return;
  if (!started_) {
    if (s.t_s <= sm_.front().t_s + kTimeTol_s) return;
    started_ = true;
    openInterval(0);
  }
  // From each smoothed record the IMU (corrected with that record's sensor errors) is
  // re-mechanized to the next; a sample straddling a record has its remainder in the next interval.
  while (open_) {
    const double t0 = sm_[k_].t_s, t1 = sm_[k_ + 1].t_s;
    if (s.t_s - s.dt_s < t1 - kTimeTol_s) {
      const ImuSample piece = sliceImuSample(s, t0, t1);
      if (piece.dt_s > 0.0) strapdown_.step(correctImuSample(piece, sm_[k_].sensors));
      if (s.t_s <= t1 + kTimeTol_s) {
        NavState st = strapdown_.state();
        st.t_s = s.t_s;
        buffer_.push_back(st);
        return;
      }
    }
    closeInterval(sink);
    openInterval(k_ + 1);
  }
}

void RtsOutputPass::finish(SolutionSink& sink) { closeInterval(sink); }

NavSolution runRtsStreaming(const EstimationProblem& problem, const EkfOptions& options,
                            const ImuPassFn& imu, SolutionSink& sink) {
  options.validate();
  EkfPass forward(problem, options, true);
  imu([&](const ImuSeries& block) {
    for (const ImuSample& s : block) forward.add(s, nullptr);
  });
  SmootherRecords records;
  NavSolution sol = forward.finish(&records);
  sol.estimator = "rts";
  std::vector<SmoothedRecord> smoothed = smoothRecords(records);
  SmootherRecords().swap(records);  // frees them before the output pass
  RtsOutputPass output(std::move(smoothed), options.output_decimation, problem.initial.gnss_week);
  imu([&](const ImuSeries& block) {
    for (const ImuSample& s : block) output.add(s, sink);
  });
  output.finish(sink);
  return sol;
}

NavSolution runRts(const EstimationProblem& problem, const EkfOptions& options,
                   NavSolution* forward, RtsStats* stats, const ProgressFn& progress) {
  SmootherRecords records;
  ProgressFn fwd_progress;
  if (progress) fwd_progress = [&](double f) { progress(0.6 * f); };
  NavSolution fwd = runEkf(problem, options, &records, fwd_progress, forward != nullptr);
  if (stats) {
    stats->records = records.size();
    stats->record_bytes = records.size() * sizeof(SmootherRecord);
  }
  std::vector<SmoothedRecord> sm = smoothRecords(records);
  SmootherRecords().swap(records);  // frees them before the output pass
  if (progress) progress(0.7);

  NavSolution sol;
  sol.copyBookkeeping(fwd);
  sol.estimator = "rts";
  NavSolutionSink sink(&sol);
  sink.reserve(problem.imu.size() / static_cast<size_t>(options.output_decimation) + 1);
  if (forward) *forward = std::move(fwd);

  RtsOutputPass output(std::move(sm), options.output_decimation, problem.initial.gnss_week);
  for (const ImuSample& s : problem.imu) output.add(s, sink);
  output.finish(sink);
  if (progress) progress(1.0);
  return sol;
}

}  // namespace graftnav
