#include "selection_models.h"

#include "graftnav/mismatch/term_spec.h"

#include <algorithm>
#include <string>
#include <vector>

namespace graftnav::selection_detail {

TermModels::TermModels(const std::vector<CandidateTerm>& terms) : terms_(terms) {}

bool TermModels::isSlow(int t) const { return terms_[t].slow(); }

// Step 4's gauge. The antisymmetric parts of the two full non-orthogonalities span a rotation
// common to both triads, which mounting_misalignment spans as well: with all three in a model
// the split is arbitrary, and with both N the misalignment fails its own test (no evidence
// left) and is dropped, so one physical rotation was named as two cross-axis matrices
// depending on the order of selection (wid_car_trial07; the CRN misalignment case). A final
// model with both full N is re-expressed as mounting_misalignment + gyro N + the
// accelerometer's symmetric N: the same span and fit, evidence measured per name.
std::vector<int> TermModels::gaugeFixed(std::vector<int> model,
                                        std::vector<std::string>* log) const {
  const int ng = indexOf(termKey(TermKind::non_orthogonality, SensorScope::gyro)),
            na = indexOf(termKey(TermKind::non_orthogonality, SensorScope::accel)),
            na_sym = indexOf(
                termKey(TermKind::non_orthogonality, SensorScope::accel, TermVariant::symmetric)),
            rot = indexOf(termKey(TermKind::mounting_misalignment, SensorScope::both));
  const auto has = [&](int t) { return std::find(model.begin(), model.end(), t) != model.end(); };
  if (ng < 0 || na < 0 || na_sym < 0 || rot < 0 || !has(ng) || !has(na)) return model;
  model.erase(std::remove(model.begin(), model.end(), na), model.end());
  if (!has(rot)) model = withRequired(model, rot);
  model.push_back(na_sym);
  std::sort(model.begin(), model.end());
  log->push_back(
      "gauge: both non_orthogonality terms re-expressed as mounting_misalignment + "
      "non_orthogonality:gyro + non_orthogonality:accel:symmetric (same fit)");
  return model;
}

int TermModels::indexOf(const TermKey& key) const {
  for (std::size_t k = 0; k < terms_.size(); ++k)
    if (terms_[k].key() == key) return static_cast<int>(k);
  return -1;
}

// The model a term is tested against: the current one plus the terms it requires.
std::vector<int> TermModels::baseFor(const std::vector<int>& model, int t) const {
  std::vector<int> base = model;
  for (const TermKey& req : terms_[t].requires_terms) {
    const int k = indexOf(req);
    if (k >= 0) base = withTerm(base, k);
  }
  return base;
}

// The model with t and the terms t requires.
std::vector<int> TermModels::withRequired(const std::vector<int>& model, int t) const {
  return withTerm(baseFor(model, t), t);
}

bool TermModels::requiredByOthers(const std::vector<int>& model, int t) const {
  for (int m : model)
    for (const TermKey& req : terms_[m].requires_terms)
      if (req == terms_[t].key()) return true;
  return false;
}

std::vector<int> TermModels::withTerm(std::vector<int> model, int t) const {
  for (const TermKey& ex : terms_[t].excludes)  // with its parts
    model.erase(
        std::remove_if(model.begin(), model.end(),
                       [&](int m) { return terms_[m].key() == ex || terms_[m].part_of == ex; }),
        model.end());
  for (int m : model)  // a term that excludes t keeps t out
    for (const TermKey& ex : terms_[m].excludes)
      if (ex == terms_[t].key()) return model;
  if (std::find(model.begin(), model.end(), t) == model.end()) model.push_back(t);
  std::sort(model.begin(), model.end());
  return model;
}

// The model without t. A term t replaced (excludes) is not brought back: it is an alternative
// explanation, which forward selection offers again after any drop. Restoring it here made
// backward elimination cycle between two alternatives of equal evidence, each failing against
// the other.
// The parts of t (part_of) leave with it.
std::vector<int> TermModels::withoutTerm(std::vector<int> model, int t) const {
  model.erase(std::remove_if(model.begin(), model.end(),
                             [&](int m) { return m == t || terms_[m].part_of == terms_[t].key(); }),
              model.end());
  return model;
}

// A model without the parts whose term is not in it (e.g. after a gate took the term out).
std::vector<int> TermModels::withoutOrphanParts(std::vector<int> model) const {
  const std::vector<int> in = model;
  model.erase(std::remove_if(model.begin(), model.end(),
                             [&](int m) {
                               if (!terms_[m].part_of.has_value()) return false;
                               return std::none_of(in.begin(), in.end(), [&](int o) {
                                 return terms_[o].key() == terms_[m].part_of;
                               });
                             }),
              model.end());
  return model;
}

}  // namespace graftnav::selection_detail
