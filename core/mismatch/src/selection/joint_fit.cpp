#include "graftnav/mismatch/joint_fit.h"

#include <ceres/ceres.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "joint_fit_cost.h"

namespace graftnav {

void JointFitOptions::validate() const {
  if (max_iterations < 1)
    throw std::invalid_argument(
        "JointFitOptions: max_iterations = " + std::to_string(max_iterations) + " must be >= 1");
  if (chunk_bins < 2)
    throw std::invalid_argument("JointFitOptions: chunk_bins = " + std::to_string(chunk_bins) +
                                " must be >= 2");
  if (!(min_reciprocal_condition > 0.0 && min_reciprocal_condition < 1.0))
    throw std::invalid_argument("JointFitOptions: min_reciprocal_condition must be in (0, 1)");
}

namespace {

// Central difference per bin of a column (one-sided at the ends), per second.
Eigen::VectorXd binDerivative(const Eigen::VectorXd& u, double bin_s) {
  const int n = static_cast<int>(u.size());
  Eigen::VectorXd d(n);
  for (int i = 0; i < n; ++i) {
    const int a = std::max(0, i - 1), b = std::min(n - 1, i + 1);
    d(i) = (u(b) - u(a)) / ((b - a) * bin_s);
  }
  return d;
}

using joint_fit_detail::ChunkCost;
using joint_fit_detail::JointData;

void checkJointInputs(const Eigen::MatrixXd& residual, const GridSpec& grid,
                      const std::vector<CandidateTerm>& terms, const SelectionResult& linear,
                      int time_offset_term) {
  const int n = grid.count;
  if (residual.rows() != n || residual.cols() != kMismatchChannels)
    throw std::invalid_argument(
        fmt::format("jointFitWithTimeOffset: residual is {} x {}, expected {} x 6 (grid bins)",
                    residual.rows(), residual.cols(), n));
  if (time_offset_term < 0 || time_offset_term >= static_cast<int>(terms.size()))
    throw std::invalid_argument("jointFitWithTimeOffset: time_offset_term out of range");
  if (linear.nuisance.term < 0 && linear.nuisance.theta.size() == 0)
    throw std::invalid_argument("jointFitWithTimeOffset: the linear fit has no nuisance term");
}

// The residual, the reference's bin means X and the noise weights of the cost.
void initJointData(const Eigen::MatrixXd& residual, const CumulativeImu& cum, const GridSpec& grid,
                   double pivot_s, const SelectionResult& linear, JointData* d) {
  const int n = grid.count;
  d->r = &residual;
  d->cum = &cum;
  d->grid = grid;
  d->pivot = pivot_s;
  d->rho = linear.rho;
  for (int c = 0; c < kMismatchChannels; ++c) d->w(c) = 1.0 / linear.sigma(c);
  d->X.resize(n, kMismatchChannels);
  for (int i = 0; i < n; ++i)
    d->X.row(i) =
        ((cum.at(grid.binStart(i + 1)) - cum.at(grid.binStart(i))) / grid.bin_s).transpose();
  d->K = Eigen::MatrixXd::Zero(n, kMismatchChannels);
}

// Model terms in the order nuisance, selected (time offset excluded), and where the parameters
// of the free ones sit in theta (start -1: a fixed term, summed into JointData::K).
struct JointLayout {
  std::vector<const TermFit*> fits;
  std::vector<int> start;
  std::vector<double> theta;
};

JointLayout layoutParameters(const std::vector<CandidateTerm>& terms, const SelectionResult& linear,
                             int time_offset_term, JointData* d) {
  const int n = d->grid.count;
  const double bin_s = d->grid.bin_s;
  JointLayout L;
  L.fits = {&linear.nuisance};
  for (const TermFit& tf : linear.selected)
    if (tf.term != time_offset_term) L.fits.push_back(&tf);
  L.start.assign(L.fits.size(), -1);
  for (std::size_t f = 0; f < L.fits.size(); ++f) {
    const int t = L.fits[f]->term < 0 ? 0 : L.fits[f]->term;
    const CandidateTerm& term = terms[t];
    if (term.fixed()) {
      d->K += termContribution(term, Eigen::VectorXd::Ones(term.columns.size()), n);
      continue;
    }
    L.start[f] = static_cast<int>(L.theta.size());
    for (std::size_t j = 0; j < term.columns.size(); ++j) {
      const int k = static_cast<int>(L.theta.size());
      L.theta.push_back(L.fits[f]->theta(static_cast<Eigen::Index>(j)));
      for (int c = 0; c < kMismatchChannels; ++c)
        if (term.columns[j].actsOn(c)) {
          const RegressorColumn& col = term.columns[j];
          Eigen::VectorXd whole = col.grid_rows > 0 ? col.dense(c) : Eigen::VectorXd();
          const Eigen::VectorXd& u = col.grid_rows > 0 ? whole : col.channel[c];
          // A moved Eigen vector keeps its buffer, so u stays valid in u_whole.
          d->cols[c].push_back({k, u.data(), binDerivative(u, bin_s), std::move(whole)});
        }
    }
  }
  d->P = static_cast<int>(L.theta.size());
  d->dK.resize(n, kMismatchChannels);
  for (int c = 0; c < kMismatchChannels; ++c) d->dK.col(c) = binDerivative(d->K.col(c), bin_s);
  return L;
}

ceres::Solver::Options jointSolverOptions(const JointFitOptions& options) {
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  so.max_num_iterations = options.max_iterations;
  so.function_tolerance = 1e-12;
  so.parameter_tolerance = 1e-12;
  so.gradient_tolerance = 1e-14;
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  return so;
}

// Covariance of (theta, tau) at the solution; NaN (and *ok false) when Ceres cannot compute it.
Eigen::MatrixXd jointCovariance(ceres::Problem* problem, double* theta, double* tau, int P,
                                const JointFitOptions& options, bool* ok) {
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::DENSE_SVD;
  co.null_space_rank = -1;
  co.min_reciprocal_condition_number = options.min_reciprocal_condition;
  co.num_threads = 1;
  ceres::Covariance covariance(co);
  const std::vector<const double*> blocks = {theta, tau};
  std::vector<std::pair<const double*, const double*>> pairs;
  for (const double* a : blocks)
    for (const double* b : blocks) pairs.emplace_back(a, b);
  Eigen::MatrixXd cov =
      Eigen::MatrixXd::Constant(P + 1, P + 1, std::numeric_limits<double>::quiet_NaN());
  *ok = covariance.Compute(pairs, problem);
  if (*ok) {
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> full(P + 1, P + 1);
    *ok = covariance.GetCovarianceMatrix(blocks, full.data());
    if (*ok) cov = full;
  }
  return cov;
}

// Inflation as in the linear covariance: c for all, each term's slow-noise factor on its block
// (sqrt(f_a f_b) on cross blocks).
void inflateAsLinear(const JointLayout& L, const SelectionResult& linear, int to_pos, int P,
                     Eigen::MatrixXd* cov) {
  std::vector<double> factor(P + 1, 1.0);
  for (std::size_t f = 0; f < L.fits.size(); ++f)
    if (L.start[f] >= 0)
      for (Eigen::Index j = 0; j < L.fits[f]->theta.size(); ++j)
        factor[L.start[f] + j] = L.fits[f]->inflation_factor;
  factor[P] = linear.selected[to_pos].inflation_factor;
  for (int a = 0; a <= P; ++a)
    for (int b = 0; b <= P; ++b)
      (*cov)(a, b) *= linear.inflation * std::sqrt(factor[a] * factor[b]);
}

// A term's fit at the joint solution (its block of theta and of the covariance).
TermFit jointTermFit(const TermFit& lin, int s0, const std::vector<double>& theta,
                     const Eigen::MatrixXd& cov) {
  TermFit tf = lin;
  if (s0 < 0) return tf;  // fixed term
  const int k = static_cast<int>(lin.theta.size());
  for (int j = 0; j < k; ++j) tf.theta(j) = theta[s0 + j];
  tf.covariance = cov.block(s0, s0, k, k);
  tf.sigma = tf.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  for (int j = 0; j < k; ++j)  // what the linear fit found unobservable stays so
    if (!std::isfinite(lin.sigma(j))) tf.sigma(j) = lin.sigma(j);
  return tf;
}

// The model at the solution (r - e) without the nuisance, and every term's fit in the order of
// the linear selection (the time offset's from tau).
void jointResults(const JointData& d, const JointLayout& L, const Eigen::MatrixXd& residual,
                  const std::vector<CandidateTerm>& terms, const SelectionResult& linear,
                  int time_offset_term, double tau, const Eigen::MatrixXd& cov,
                  JointFitResult* out) {
  const int n = d.grid.count;
  out->model.resize(n, kMismatchChannels);
  double e[6];
  for (int i = 0; i < n; ++i) {
    d.error(i, L.theta.data(), tau, e, nullptr, nullptr);
    for (int c = 0; c < kMismatchChannels; ++c) out->model(i, c) = residual(i, c) - e[c];
  }
  out->nuisance = jointTermFit(linear.nuisance, L.start[0], L.theta, cov);
  const int t0 = linear.nuisance.term < 0 ? 0 : linear.nuisance.term;
  out->model -= termContribution(terms[t0], out->nuisance.theta, n);
  std::size_t f = 1;
  for (const TermFit& lin : linear.selected) {
    TermFit tf;
    if (lin.term == time_offset_term) {
      tf = lin;
      tf.theta = Eigen::VectorXd::Constant(1, tau);
      tf.covariance = Eigen::MatrixXd::Constant(1, 1, cov(d.P, d.P));
      tf.sigma = Eigen::VectorXd::Constant(1, std::sqrt(std::max(0.0, cov(d.P, d.P))));
      out->tau_sigma_s = tf.sigma(0);
    } else {
      tf = jointTermFit(lin, L.start[f], L.theta, cov);
      ++f;
    }
    out->terms.push_back(tf);
  }
}

}  // namespace

JointFitResult jointFitWithTimeOffset(const Eigen::MatrixXd& residual, const ImuSeries& reference,
                                      const GridSpec& grid, const std::vector<CandidateTerm>& terms,
                                      const SelectionResult& linear, int time_offset_term,
                                      double regressor_pivot_s, const JointFitOptions& options,
                                      const ImuSampleMap& response) {
  options.validate();
  checkJointInputs(residual, grid, terms, linear, time_offset_term);
  int to_pos = -1;
  for (std::size_t k = 0; k < linear.selected.size(); ++k)
    if (linear.selected[k].term == time_offset_term) to_pos = static_cast<int>(k);
  if (to_pos < 0)
    throw std::invalid_argument("jointFitWithTimeOffset: the time_offset term is not selected");
  const int n = grid.count;
  const CumulativeImu cum(reference, response);
  JointData d;
  initJointData(residual, cum, grid, regressor_pivot_s, linear, &d);
  JointLayout L = layoutParameters(terms, linear, time_offset_term, &d);
  double tau = linear.selected[to_pos].theta(0);
  const double tau_linear = tau;

  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  for (int i0 = 0; i0 < n; i0 += options.chunk_bins) {
    const int i1 = std::min(n, i0 + options.chunk_bins);
    problem.AddResidualBlock(new ChunkCost(&d, i0, i1), nullptr, L.theta.data(), &tau);
  }
  ceres::Solver::Summary summary;
  ceres::Solve(jointSolverOptions(options), &problem, &summary);

  JointFitResult out;
  out.iterations = static_cast<int>(summary.iterations.size());
  out.initial_cost = summary.initial_cost;
  out.final_cost = summary.final_cost;
  out.tau_s = tau;
  bool cov_ok = false;
  Eigen::MatrixXd cov = jointCovariance(&problem, L.theta.data(), &tau, d.P, options, &cov_ok);
  out.converged = summary.IsSolutionUsable() && cov_ok;
  inflateAsLinear(L, linear, to_pos, d.P, &cov);
  jointResults(d, L, residual, terms, linear, time_offset_term, tau, cov, &out);
  out.summary = fmt::format(
      "Ceres joint fit ({} parameters + tau, {} iterations, {}): cost {:.6g} -> {:.6g}, tau "
      "{:.6f} s (linear pivot fit) -> {:.6f} +- {:.6f} s",
      d.P, out.iterations, out.converged ? "converged" : "NOT usable", out.initial_cost,
      out.final_cost, tau_linear, tau, out.tau_sigma_s);
  return out;
}

}  // namespace graftnav
