#pragma once
// How far two fitted terms can be told apart on this record: the largest canonical correlation
// between their regressor column spaces, in the metric the selection fits in to first order
// (each channel's rows AR(1)-prewhitened with the selection's rho and sigma, masked bins left
// out, the per-channel constant of the nuisance projected out). 1: some combination of one
// term's columns is a combination of the other's, so the data cannot say which term carries it;
// above ~0.95 the split between them rests on a few per cent of their signal.

#include <vector>

#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/mismatch/term_selection.h"

namespace graftnav {

struct TermCorrelation {
  TermKey term_a, term_b;
  double canonical = 0.0;  // largest canonical correlation, in [0, 1]
};

// Every pair of the fitted terms of `selection` (fixed terms left out). `masked` has one entry per
// bin (1 = left out) or is empty. Throws std::invalid_argument when a term index is out of range.
std::vector<TermCorrelation> termCorrelations(const std::vector<CandidateTerm>& terms,
                                              const SelectionResult& selection,
                                              const std::vector<char>& masked);

// The largest canonical correlation of `key` with any other term in `correlations` (0 and
// term_b without a spec when there is none).
TermCorrelation mostCorrelatedWith(const std::vector<TermCorrelation>& correlations,
                                   const TermKey& key);

}  // namespace graftnav
