#pragma once
// Choosing which candidate terms explain a residual, with evidence that accounts for the
// residual's autocorrelation.
//
// 1. Noise model. The largest model (all candidates) is fitted per channel; its residual e_c gives
//    the lag-1 autocorrelation rho_c and the innovation scale sigma_c of an AR(1) noise. Every
//    channel's residual and regressors are then prewhitened, z_t - rho_c z_{t-1}, and divided by
//    sigma_c, so the whitened errors are close to independent N(0, 1). What AR(1) leaves behind
//    is measured on the whitened full-model residual (lag-1 autocorrelation rho_w) and turned into
//    a variance inflation c = (1 + rho_w) / (1 - rho_w) >= 1 (effective sample size n / c).
// 2. Evidence: twice the log Bayes factor (Laplace form) of the model with a term over the model
//    without it. With A the whitened normal matrix of the term's columns after projecting out the
//    model it is tested against, r their whitened score there, and a Gaussian prior on the
//    term's parameters, isotropic (a term's parameters share units) with variance
//    tau^2 = (N / c) p / trace(D) (N = rows, bins x channels; D the normal matrix of the term's
//    columns net of the nuisance only; p its columns with signal): the prior under which the
//    term's average column carries the information of N / c observations ("unit information"):
//      delta_bic = sum_i [ (v_i' tau r)^2 / (c (1 + s_i)) - ln(1 + s_i) ],
//    s_i, v_i the eigenvalues / vectors of tau^2 A. Each direction costs ln(1 + s_i): ln(N / c)
//    when it is as well determined as an average column, and little when the base model nearly
//    spans it (e.g. G f_z with f_z ~ -g next to the constant bias: s ~ 2e-3 N), whose RSS drop
//    is shrunk by s / (1 + s) alike. For a term with equally informative columns orthogonal to
//    the base this is BIC's RSS_w / c drop minus p ln(N / c). The term's RSS drop is further
//    divided by its slow-noise inflation (below). In forward selection a term that replaces
//    another (excludes) is compared on the terms the two models share; in backward elimination
//    and in the reported evidence a term is measured against the model without it (the
//    alternative it replaced is not restored: forward selection offers it again after a drop).
// 3. Time-blocked cross-validation. K contiguous folds of bins; each fold is predicted by the
//    fit on the others; CV = sum of squared prediction errors in the metric the term is tested
//    in (below: a fast term's GLS, each fold's rows Haar transformed on their own and level j
//    weighted by 1 / c_j; a slow term's white rows); cv_gain = (CV_without - CV_with) / CV_without.
//    In the AR(1) metric alone a fold's error is dominated by the bias wander of its minutes, and
//    a speed-driven vibration level at 3 x its detection limit (delta_bic 414) failed CV.
//    Slow noise: AR(1) misses noise correlated over minutes (a bias random process whose field
//    and lab realizations differ). Per channel, the whitened residual of the full model without
//    the slow candidates is split into Haar levels and its variance per level is smoothed by
//    the law c_j = 1 + a 2^j + b 4^j (white, flicker, random walk; scale_noise.h), fitted on
//    the levels up to twice the block length. A fast term is then fitted and tested by
//    generalized least squares: each channel's whitened rows are Haar transformed and level j
//    weighted by 1 / c_j (regressors and residual alike), so a slow regressor meets the noise of
//    its own time scales and a term on several channels keeps the information of its quiet
//    ones. The slow terms already in the model a fast term is tested against stay in that
//    residual (claimed physics is not noise). A slow term (temperature, bias wander,
//    Earth/gravity) cannot be told from a wander on the coarse scales it shares with it: it is
//    fitted by white least squares, and its RSS drop is divided, and its covariance multiplied,
//    by the larger of two factors: 1 + sum_c s_c (c_slow_c - 1), c_slow_c = block length x
//    variance of the block means of the whitened residual without any slow term (1 for white
//    noise), s_c the share of its regressor energy in block means on channel c; and the factor
//    of a random walk of the block means (block_random_walk.h): one intensity q per sensor
//    triad, estimated by REML on the residual of the fast model fitted with the term, the
//    term's block-mean regressors as fixed effects, K the field walk's block covariance plus,
//    for SG#2, that of the lab record's replay (replay_period_s):
//    1 + sum m^2 q u_b' K u_b / u'u over its columns u (block means u_b, m bins per block).
//    The first treats the blocks as independent and understated a bias wander's projection
//    onto a warm-up about 8 x; the second follows the wander onto the regressor's time scales.
// 4. Forward selection adds, while any exists, the term with the largest delta_bic among those
//    with delta_bic > min_delta_bic and cv_gain > min_cv_gain; backward elimination then drops
//    terms that no longer pass; after a drop, forward and backward run again (a term the dropped
//    one masked may now pass) until nothing is dropped or a model repeats. Gauge: a final model
//    with both full non_orthogonality terms (whose antisymmetric parts span a rotation common
//    to both triads, as mounting_misalignment does) is re-expressed as mounting_misalignment +
//    the gyro's N + the accelerometer's symmetric N (gauge_only; same fit). A term is claimed
//    only if it passes both tests in the final model.
// 5. Names. Terms with declared shape alternatives (shape_alternatives: the even functions |x|
//    of scale_asymmetry and x^2 of scale_nonlinearity, about 95 % correlated on car inputs once
//    the gain is out) can pass both on one even signal. A selected term is named only when the
//    final model's evidence over the same model with the term swapped for its best alternative
//    is at least min_name_margin (the margin a term needs over its absence); otherwise the name
//    is ambiguous (TermFit::name_ambiguous): kept in the model, not claimed. In this comparison
//    each column of the two shapes has the unit-information prior of that column alone
//    (n_eff / its information net of the nuisance), so both pay about ln(n_eff) for every axis
//    the rest of the model leaves informative. The term-isotropic prior of step 2 let a term whose columns differ in scale
//    (x^2 with gyro z or f_z ~ -g dominant) pay little for its small columns: about 8 units in
//    favour of x^2 on car motion (docs/mismatch-method.md, step 3 (h)).
// Everything works on Gram matrices accumulated once per fold, so each trial fit costs a small
// dense solve, independent of the record length.

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "graftnav/mismatch/candidate_terms.h"

namespace graftnav {

struct SelectionOptions {
  int folds = 5;                 // contiguous CV folds, >= 2
  double min_delta_bic = 6.0;    // margin over the evidence penalty (step 2; see
                                 //   docs/mismatch.md for the false-alarm rate this gives)
  double min_cv_gain = 0.0;      // relative CV improvement required
  double min_name_margin = 6.0;  // evidence a name needs over its shape alternative (step 5;
      // also gain vs curvature on a one-signed axis, gain_or_curvature.h)
  int max_terms = 12;     // forward steps at most
  double max_rho = 0.98;  // AR(1) coefficient clamp
  // Block length (bins) of the slow-noise check (see below); 0 = off. diagnose sets 60 s.
  int slow_block_bins = 0;
  // The SG#2 replay of the lab's static record (block_random_walk.h), for the slow terms' random
  // walk: the record length (0: no replay, e.g. reference + static bias), the tiling time at the
  // start of residual row 0, and the residual's bin length.
  double replay_period_s = 0.0;
  double replay_start_s = 0.0;
  double bin_s = 0.0;
  // A fast term's variances at least those of the sandwich A^-1 X'W Sigma W X A^-1
  // (atLeastTheVariances; default on): the level-diagonal Haar GLS treats a random walk's
  // wavelet coefficients as independent across levels, which they are not, and states a
  // regressor on the wander's scales too certain; the sandwich trusts the law's 4^j part to be
  // a random walk, which a quiet residual's slow misfit is not, and can state a direction far
  // too certain (docs/mismatch.md, Known limits). Sigma = white + the random walk whose Haar
  // variances the law's 4^j part fits (step variance 12 b) + the 2^j part on the diagonal.
  // Needs slow_block_bins.
  bool random_walk_sandwich = true;
  void validate() const;
};

struct TermFit {
  int term = -1;               // index into the candidate list
  Eigen::VectorXd theta;       // one value per column (SI)
  Eigen::VectorXd sigma;       // 1-sigma, inflated for autocorrelation
  Eigen::MatrixXd covariance;  // of theta
  double delta_bic = 0.0;      // evidence of step 2 (2 ln Bayes factor; diagnosis.json name)
  double cv_gain = 0.0;
  // A slow term's block-mean factor (1 + sum_c s_c (c_slow_c - 1)); 1 for a fast term, whose
  // slow noise is in its GLS weights. The covariance above already carries it and c.
  double inflation_factor = 1.0;
  // False for a term kept only because a claimed term requires it (requires_terms) while it
  // fails its own test: it stays in the model but is not claimed.
  bool claimed = true;
  // Step 5: the best shape alternative (index into the candidate list; -1: none) and the
  // evidence of this term over it (2 ln Bayes factor of the final model over the model with the
  // alternative in its place, each column of the two under its own unit-information prior).
  // Below min_name_margin the name is ambiguous: the term stays in the model, not claimed.
  int shape_alternative = -1;
  double name_margin = std::numeric_limits<double>::infinity();
  bool name_ambiguous = false;
};

// Detection limit of a candidate left out of the final model: per column, the value that column
// alone would need for its expected (noise-free) evidence over that model to reach
// min_delta_bic (about a 50 % detection probability; infinite without information).
struct TermLimit {
  int term = -1;
  Eigen::VectorXd theta_limit;  // SI, one per column
};

struct SelectionResult {
  std::vector<TermFit> selected;      // claimed terms (nuisance excluded)
  TermFit nuisance;                   // the constant bias per channel
  Eigen::Matrix<double, 6, 1> rho;    // AR(1) coefficient per channel
  Eigen::Matrix<double, 6, 1> sigma;  // AR(1) innovation scale per channel (SI)
  double inflation = 1.0;             // c of the header
  // Slow noise per channel: the GLS law's c_j at the block length (1 for white noise).
  Eigen::Matrix<double, 6, 1> slow_inflation = Eigen::Matrix<double, 6, 1>::Ones();
  int rows = 0;                   // N
  std::vector<std::string> log;   // one line per selection step
  std::vector<TermLimit> limits;  // every non-fixed candidate not in the model
};

// Selects terms explaining `residual` (n x 6) over bins [row_begin, row_end) (row_end < 0: all).
// Throws std::invalid_argument when the residual is not n x 6, the library is empty or term 0 is
// not the nuisance.
SelectionResult selectTerms(const Eigen::MatrixXd& residual,
                            const std::vector<CandidateTerm>& terms,
                            const SelectionOptions& options = {}, int row_begin = 0,
                            int row_end = -1);

// Fits a given set of terms (plus the nuisance and the terms they require) without selection;
// evidence is filled in too.
SelectionResult fitTerms(const Eigen::MatrixXd& residual, const std::vector<CandidateTerm>& terms,
                         const std::vector<int>& term_indices, const SelectionOptions& options = {},
                         int row_begin = 0, int row_end = -1);

// The covariance P with each variance raised to at least Q's, its correlations kept:
// D P D, D = diag(max(1, sqrt(Q_ii / P_ii))). Two noise models that agree on every Haar level's
// variance but not on the levels' correlation (the level-diagonal GLS and the random-walk
// sandwich) each hold for some residuals; a parameter is stated with the larger variance.
Eigen::MatrixXd atLeastTheVariances(const Eigen::MatrixXd& P, const Eigen::MatrixXd& Q);

// Model prediction on all n bins (n x 6): the selected terms, plus the nuisance when asked.
Eigen::MatrixXd predictSelection(const SelectionResult& sel,
                                 const std::vector<CandidateTerm>& terms, int n,
                                 bool include_nuisance);

}  // namespace graftnav
