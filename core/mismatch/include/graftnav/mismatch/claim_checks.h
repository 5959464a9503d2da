#pragma once
// The last step before a fitted term is claimed (diagnosis.h, after the selection):
//   1. correlations: the canonical correlation of every pair of fitted terms is reported
//      (term_correlation.h);
//   2. plausibility: a fitted effect whose largest element is outside the tested IMU's plausible
//      range (plausible_ranges.h) moves from `effects` to `implausible`, naming the fitted term
//      it correlates with most ("probably absorbing X");
//   3. identifiability: without a lab calibration of the tested IMU, and when the record's roll
//      and pitch excitation cannot split them (linear_response.h), the claimed mounting rotation,
//      non-orthogonality and scale factor are replaced by one effect,
//      mounting_scale_nonorthogonality, E per sensor fitted beside the other fitted terms, with
//      the reason and the excitation the split needs; its diagonal (the scale part, which a
//      rotation does not have) is range-checked like a scale factor.
// The model (SG#3, the residuals, the hold-out check) is not changed: only what is claimed.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "graftnav/mismatch/diagnosis.h"

namespace graftnav {

struct ClaimCheckInputs {
  const std::vector<CandidateTerm>* terms = nullptr;
  const SelectionResult* selection = nullptr;  // the final model
  const BinnedImu* reference = nullptr;        // binned true inputs on the residual's grid
  const Eigen::MatrixXd* residual = nullptr;   // n x 6, the residual the selection fitted
  const std::vector<char>* masked = nullptr;   // per bin
  double bin_s = 0.0;
  bool lab_calibrated = false;  // the simulation carries a lab calibration of M
  std::optional<PlausibleRanges> ranges;
};

// The element of `e` farthest outside its bound: parameter key, |value| and bound; nullopt when
// every bounded element is inside or the effect has no bound in `ranges`.
struct RangeExcess {
  std::string parameter;
  double value = 0.0;
  double bound = 0.0;
};
std::optional<RangeExcess> outsidePlausibleRange(const Effect& e, const PlausibleRanges& ranges);

// Applies steps 1-3 to out->effects (throws std::invalid_argument when an input is missing).
void checkClaims(const ClaimCheckInputs& in, const DiagnoseOptions& options, DiagnosisResult* out);

}  // namespace graftnav
