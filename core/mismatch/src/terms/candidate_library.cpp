// The candidate library (candidate_terms.h) from its term specs (term_spec.h): each row's builder
// appends its term in its group's order, which is the column order of every fit in the selection.
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/mismatch/term_spec.h"

namespace graftnav {

void CandidateLibraryOptions::validate() const {
  if (!(knot_spacing_s > 0.0))
    throw std::invalid_argument("CandidateLibraryOptions: knot_spacing_s = " +
                                std::to_string(knot_spacing_s) + " must be > 0");
  if (max_knots < 2)
    throw std::invalid_argument(
        "CandidateLibraryOptions: max_knots = " + std::to_string(max_knots) + " must be >= 2");
  if (terms.empty() || terms[0] == nullptr || terms[0]->role != TermRole::nuisance)
    throw std::invalid_argument("CandidateLibraryOptions: terms must start with the nuisance");
  for (const TermSpec* spec : terms) {
    if (spec == nullptr) throw std::invalid_argument("CandidateLibraryOptions: a null term spec");
    // A kind of its own is its built-in row: the other rows' required terms and parts name it so.
    if (spec->kind != TermKind::generic && spec != &termSpec(spec->kind))
      throw std::invalid_argument(std::string("CandidateLibraryOptions: term ") + spec->name +
                                  " copies the kind of a built-in row (give it "
                                  "TermKind::generic)");
    if (spec->build == nullptr && spec->group != LibraryGroup::not_built)
      throw std::invalid_argument(std::string("CandidateLibraryOptions: term ") + spec->name +
                                  " has a library group but no builder");
  }
}

namespace {

// The reference input x of a triad and the bin means of |x| and x^2 (RegressorInputs::even_powers,
// else of the bin means).
TriadInputs triadInputs(const RegressorInputs& in, int n, Sensor s) {
  const BinnedImu& x = in.reference;
  const bool gyro = s == Sensor::gyro;
  TriadInputs t;
  t.u = gyro ? x.omega_rad_s : x.f_m_s2;
  const Eigen::MatrixX3d& abs_given =
      gyro ? in.even_powers.abs_omega_rad_s : in.even_powers.abs_f_m_s2;
  const Eigen::MatrixX3d& sq_given = gyro ? in.even_powers.sq_omega : in.even_powers.sq_f;
  t.u_abs = abs_given.rows() == n ? abs_given : t.u.cwiseAbs().eval();
  t.u_sq = sq_given.rows() == n ? sq_given : t.u.cwiseAbs2().eval();
  return t;
}

constexpr std::array<LibraryGroup, 4> kGroupOrder = {
    LibraryGroup::nuisance, LibraryGroup::bias_wander, LibraryGroup::triad, LibraryGroup::pair};

SensorScope scopeOfRow(TermSensors sensors) {
  switch (sensors) {
    case TermSensors::gyro:
      return SensorScope::gyro;
    case TermSensors::accel:
      return SensorScope::accel;
    default:
      return SensorScope::both;
  }
}

}  // namespace

std::vector<CandidateTerm> buildCandidateLibrary(const RegressorInputs& in,
                                                 const CandidateLibraryOptions& opt) {
  opt.validate();
  const BinnedImu& x = in.reference;
  const int n = x.size();
  if (n < 10) throw std::invalid_argument("buildCandidateLibrary: fewer than 10 bins");
  TermBuildContext ctx{in, opt, n, n * x.grid.bin_s, {}};
  for (const Sensor s : kSensors) ctx.triad[s] = triadInputs(in, n, s);
  std::vector<CandidateTerm> terms;
  for (const LibraryGroup group : kGroupOrder) {
    for (const Sensor s : kSensors)
      for (const TermSpec* spec : opt.terms)
        if (spec->group == group && spec->sensors == TermSensors::each_triad)
          spec->build(*spec, ctx, scopeOf(s), &terms);
    for (const TermSpec* spec : opt.terms)
      if (spec->group == group && spec->sensors != TermSensors::each_triad)
        spec->build(*spec, ctx, scopeOfRow(spec->sensors), &terms);
  }
  return terms;
}

}  // namespace graftnav
