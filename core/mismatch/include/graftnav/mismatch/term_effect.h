#pragma once
// The effect a fitted term reports: its parameters read from the fit in the layout of its
// TermSpec's parameters (term_spec.h), so diagnosis.json's keys are the spec's.

#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/mismatch/diagnosis.h"
#include "graftnav/mismatch/term_selection.h"

namespace graftnav {

// `n_bins`: the grid's bins (the wander's sd is taken over them). Parameters set by the claim
// stages (ParameterLayout::set_by_claims) are left out.
Effect effectFromTerm(const CandidateTerm& term, const TermFit& fit, int n_bins);

// A scalar parameter (diagnosis.json writes a number, not a list).
EffectParameter scalarParam(const std::string& key, double value, double sigma);

}  // namespace graftnav
