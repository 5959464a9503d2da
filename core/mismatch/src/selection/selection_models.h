#pragma once
// Internal to the mismatch module's term selection (term_selection.h): models as sets of
// candidate indices (sorted, 0 the nuisance), and how the library's structure acts on them:
// required terms, mutually exclusive alternatives, fixed parts, and the gauge of one rotation.
#include <string>
#include <vector>

#include "graftnav/mismatch/candidate_terms.h"

namespace graftnav::selection_detail {

class TermModels {
 public:
  explicit TermModels(const std::vector<CandidateTerm>& terms);

  // A term whose signal shares the coarse time scales with a bias wander (temperature, bias
  // instability, Earth rotation, gravity): measured against the block-mean slow noise.
  bool isSlow(int t) const;
  // Index of the term with this key, -1 when absent.
  int indexOf(const TermKey& key) const;
  // The model a term is tested against: the current one plus the terms it requires.
  std::vector<int> baseFor(const std::vector<int>& model, int t) const;
  // The model with t and the terms t requires.
  std::vector<int> withRequired(const std::vector<int>& model, int t) const;
  bool requiredByOthers(const std::vector<int>& model, int t) const;
  // The model with t, without what t excludes; unchanged when a term in it excludes t.
  std::vector<int> withTerm(std::vector<int> model, int t) const;
  // The model without t and its parts.
  std::vector<int> withoutTerm(std::vector<int> model, int t) const;
  // A model without the parts whose term is not in it.
  std::vector<int> withoutOrphanParts(std::vector<int> model) const;
  // Both full non-orthogonalities re-expressed as mounting_misalignment + the gyro's N + the
  // accelerometer's symmetric N (a line in `log` when it applies).
  std::vector<int> gaugeFixed(std::vector<int> model, std::vector<std::string>* log) const;

 private:
  const std::vector<CandidateTerm>& terms_;
};

}  // namespace graftnav::selection_detail
