#pragma once
// One TermSpec per term of the mismatch finder: everything the finder, its report and its docs
// know about a term apart from the physics of its builder. The candidate library
// (buildCandidateLibrary), the names diagnosis.json writes, the parameters an effect reports
// (effectFromTerm), the plausible ranges a claim is checked against (claim_checks.h) and the
// table of docs/mismatch.md (candidateTermTable) all read the rows of builtInTermSpecs()
// (src/terms/term_specs.cpp).
//
// Adding a candidate term (docs/mismatch.md, "Adding a candidate term"): one row there, of kind
// TermKind::generic unless a stage must test for it, plus its builder. A row outside the built-in
// table works the same way when handed to the library (CandidateLibraryOptions::terms).

#include <array>
#include <string>
#include <vector>

#include "graftnav/imu/plausible_ranges.h"
#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/mismatch/sensor.h"
#include "graftnav/mismatch/term_kind.h"

namespace graftnav {

// How an effect's parameter is read from a fitted term (effectFromTerm), in the order of the
// spec's parameters; the fitted layouts take the term's columns in turn.
enum class ParameterLayout {
  per_axis,      // 3 columns, one per axis
  scalar,        // 1 column
  matrix,        // 9 columns, a row-major 3 x 3
  cross_axis,    // off-diagonal 3 x 3, zero diagonal (6 columns; the symmetric variant 3)
  negated,       // the previous parameter, sign reversed (k_neg = -k_pos of one |x| column)
  wander_sd,     // per axis, the sd over the record of the fitted path (all columns)
  knot_spacing,  // the term's knot spacing (s), not fitted
  reference_temperature,  // the term's t_ref_degC, not fitted
  regressor_name,         // the variant's name, as text
  set_by_claims,          // added by a claim stage (e.g. k2_missing), not read from the fit
};

// Per scope of the effect (gyro, accel, both): a unit, or a plausible-range bound.
template <class T>
using PerScope = std::array<T, 3>;

struct ParameterSpec {
  const char* key;  // diagnosis.json's parameter key
  ParameterLayout layout;
  PerScope<const char*> unit;  // SI unit for a gyro, accel and both-sensor effect (nullptr: n/a)
  // The PlausibleRanges field bounding |every element| (nullptr: not bounded), per scope.
  PerScope<double PlausibleRanges::*> bound{};
  bool diagonal_only = false;  // a 3 x 3 of which only the diagonal is bounded
  const char* doc = "";        // what it is, for the docs table
};

// What the library builds a term for.
enum class TermSensors { each_triad, gyro, accel, both };

// Where a term's columns go in the library, whose order is the column order of every fit: the
// groups in this order; in a group, the per-triad rows are built for the gyro, then for the
// accelerometer, then the other rows once each, in table order.
enum class LibraryGroup { nuisance, bias_wander, triad, pair, not_built };

enum class TermRole {
  nuisance,   // always in the model, never claimed (constant_bias)
  candidate,  // selected or not by the evidence
  part,       // a fixed part its candidate's builder adds with it
  reported,   // an effect a claim stage reports; no columns of its own in the library
};

// Everything one builder reads: the regressor inputs, the options, and per triad the binned input
// x with the bin means of |x| and x^2 (RegressorInputs::even_powers, else of the bin means).
struct TriadInputs {
  Eigen::MatrixX3d u, u_abs, u_sq;
};
struct TermBuildContext {
  const RegressorInputs& in;
  const CandidateLibraryOptions& opt;
  int n = 0;          // bins
  double span_s = 0;  // n x bin length
  PerSensor<TriadInputs> triad;
  const BinnedImu& x() const { return in.reference; }
};

// Appends the term of `spec` on `scope` (a triad, or the row's scope), with its variants and fixed
// parts, to `out`; appends nothing when its inputs are missing.
// (A function type: `TermBuildFunction myBuilder;` declares one.)
using TermBuildFunction = void(const TermSpec& spec, const TermBuildContext& ctx, SensorScope scope,
                               std::vector<CandidateTerm>* out);
using TermBuilder = TermBuildFunction*;

struct TermSpec {
  TermKind kind;
  const char* name;  // diagnosis.json's effect name
  TermRole role;
  TermSensors sensors;
  LibraryGroup group;
  TermBuilder build;          // nullptr: not built by the library (parts, reported effects)
  const char* regressor_doc;  // the docs table's regressor: what r is, from what
  std::vector<ParameterSpec> parameters;
  // Signal on the coarse time scales a bias wander shares (temperature, bias wander, Earth,
  // gravity): fitted by white least squares with the block-mean slow-noise factors
  // (term_selection.h, step 2).
  bool slow = false;
  bool fixed = false;  // coefficients fixed at 1 (earth_rotation_omitted, the parts)
  // Terms of the same scope that must be in the model when this one is tested and stay while it
  // does (term_selection.h); with paid_requires a forward step measures the term together with
  // them against the model (hierarchy: a quadratic enters with its linear term and pays for both),
  // without, against the model with them (the earth/gravity terms must beat a wander).
  std::vector<TermKind> requires_kinds = {};
  bool paid_requires = false;
  // Other kinds of the same scope whose regressors are another shape of the same physics here
  // (|x| and x^2): a selected term is named only when it beats the best of them (step 5).
  std::vector<TermKind> shape_alternatives = {};
};

// The built-in rows: the nuisance, the candidates in the library's order, the parts and the
// reported effects. Also CandidateLibraryOptions::terms' default.
const std::vector<const TermSpec*>& builtInTermSpecs();
// The built-in row of a kind; throws std::invalid_argument for TermKind::generic (many rows).
const TermSpec& termSpec(TermKind kind);
// Its name (termSpec(kind).name).
const char* termName(TermKind kind);

// The unit and bound of a parameter on an effect's scope.
const char* unitOf(const ParameterSpec& p, SensorScope scope);
double PlausibleRanges::*boundOf(const ParameterSpec& p, SensorScope scope);

// The key of a term of `kind` on `scope` (a built-in row).
TermKey termKey(TermKind kind, SensorScope scope, TermVariant variant = TermVariant::none);

// The rows of `specs` as docs/mismatch.md shows them (Markdown): term, role, sensors, regressor
// and parameters with units; and every bounded parameter with its bound per sensor class
// (plausibleRangesForClass of each of `classes`). The test MismatchTermSpec.DocsTablesAreTheRows
// checks the page against them.
std::string candidateTermTable(const std::vector<const TermSpec*>& specs);
std::string plausibleRangeTable(const std::vector<const TermSpec*>& specs,
                                const std::vector<std::string>& classes);

}  // namespace graftnav
