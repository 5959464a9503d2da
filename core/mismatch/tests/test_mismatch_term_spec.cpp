// The term specs (term_spec.h): one row per term, effects read in the rows' layout, the docs
// tables written from the rows, and a term added through one row and its builder alone, which
// the library builds, the selection finds, diagnose() claims and the range check bounds.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "graftnav/mismatch/claim_checks.h"
#include "graftnav/mismatch/term_effect.h"
#include "graftnav/mismatch/term_spec.h"
#include "mismatch_diagnosis_fixture.h"
#include "mismatch_signal_fixture.h"
#include "test_support.h"

namespace graftnav {
namespace {

const std::vector<std::string> kClasses = {"consumer_mems", "industrial_mems", "tactical",
                                           "navigation"};

TEST(MismatchTermSpec, EveryKindHasOneRowAndEveryRowWhatItsRoleNeeds) {
  std::set<TermKind> kinds;
  std::set<std::string> names;
  for (const TermSpec* spec : builtInTermSpecs()) {
    EXPECT_TRUE(names.insert(spec->name).second) << spec->name;
    if (spec->kind != TermKind::generic) {
      EXPECT_TRUE(kinds.insert(spec->kind).second) << spec->name;
      EXPECT_EQ(&termSpec(spec->kind), spec);
    }
    const bool built = spec->role == TermRole::nuisance || spec->role == TermRole::candidate;
    EXPECT_EQ(spec->build != nullptr, built) << spec->name;
    EXPECT_EQ(spec->group != LibraryGroup::not_built, built) << spec->name;
    EXPECT_NE(std::string(spec->regressor_doc), "") << spec->name;
    for (const ParameterSpec& p : spec->parameters)
      if (p.layout != ParameterLayout::regressor_name)
        for (const SensorScope s : {SensorScope::gyro, SensorScope::accel, SensorScope::both}) {
          // A bound needs the unit it is in; a both-sensor term has no triad's, and vice versa.
          if (boundOf(p, s) != nullptr) {
            EXPECT_NE(unitOf(p, s), nullptr) << spec->name;
          }
          const bool single = spec->sensors != TermSensors::both;
          if (single == (s == SensorScope::both)) {
            EXPECT_EQ(unitOf(p, s), nullptr) << spec->name;
          }
        }
  }
  EXPECT_EQ(builtInTermSpecs().front()->role, TermRole::nuisance);
  EXPECT_EQ(static_cast<int>(kinds.size()), static_cast<int>(TermKind::generic))
      << "every kind but generic has its row";
  EXPECT_THROW(termSpec(TermKind::generic), std::invalid_argument);
}

// Every term of a library holding all of them (the synthetic inputs' temperature, attitude and
// vibration levels, lab quadratics, a pivoted rotation) reports, fitted, exactly its row's parameters, in order, each of its size.
TEST(MismatchTermSpec, EffectsCarryTheRowsParameters) {
  using namespace mismatch_test;
  const Motion m = carMotion(3);
  RegressorInputs in = syntheticInputs(m, 300.0, 0.0);
  const int n = in.reference.size();
  in.gyro_response_c2 << 0.0, 0.0, 1e-3;
  in.accel_response_c2 << 0.0, 0.0, 1e-4;
  in.mounting_rotation_pivot_rad << 0.01, -0.02, 0.03;
  const std::vector<CandidateTerm> terms = buildCandidateLibrary(in);
  std::set<TermKind> built;
  for (std::size_t t = 1; t < terms.size(); ++t) {
    const CandidateTerm& term = terms[t];
    built.insert(term.kind());
    TermFit tf;
    tf.term = static_cast<int>(t);
    const Eigen::Index k = static_cast<Eigen::Index>(term.columns.size());
    tf.theta = Eigen::VectorXd::LinSpaced(k, 1.0, 2.0);
    tf.sigma = Eigen::VectorXd::Constant(k, 0.1);
    tf.covariance = Eigen::MatrixXd::Identity(k, k) * 0.01;
    const Effect e = effectFromTerm(term, tf, n);
    EXPECT_EQ(e.spec, term.spec);
    EXPECT_EQ(e.sensor, term.sensor);
    std::vector<std::string> want;
    for (const ParameterSpec& p : term.spec->parameters)
      if (p.layout != ParameterLayout::set_by_claims) want.push_back(p.key);
    ASSERT_EQ(e.parameters.size(), want.size()) << term.key().text();
    for (std::size_t i = 0; i < want.size(); ++i) {
      const EffectParameter& p = e.parameters[i];
      EXPECT_EQ(p.key, want[i]) << term.key().text();
      const std::size_t size = p.text.empty() ? p.values.size() : 1;
      EXPECT_TRUE(size == 1 || size == 3 || size == 9) << term.key().text() << " " << p.key;
    }
  }
  // Every candidate kind is in this library (the symmetric N, the asymmetry replacing the lab
  // quadratic and both vibration levels too).
  for (const TermSpec* spec : builtInTermSpecs())
    if (spec->role == TermRole::candidate) {
      EXPECT_TRUE(built.count(spec->kind)) << spec->name;
    }
}

// The text between `<!-- begin NAME -->` and `<!-- end NAME -->` in docs/mismatch.md.
std::string docsSection(const std::string& name) {
  std::ifstream f(test::sourceDir() + "/docs/mismatch.md");
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string page = ss.str();
  const std::string begin = "<!-- begin " + name + " -->\n", end = "<!-- end " + name + " -->";
  const std::size_t a = page.find(begin), b = page.find(end);
  if (a == std::string::npos || b == std::string::npos || b < a) return "(no section " + name + ")";
  return page.substr(a + begin.size(), b - a - begin.size());
}

// docs/mismatch.md shows the rows as they are: the test prints the tables it expects.
TEST(MismatchTermSpec, DocsTablesAreTheRows) {
  const std::string terms = candidateTermTable(builtInTermSpecs());
  EXPECT_EQ(docsSection("term-table"), terms) << "docs/mismatch.md term table should be:\n"
                                              << terms;
  const std::string ranges = plausibleRangeTable(builtInTermSpecs(), kClasses);
  EXPECT_EQ(docsSection("range-table"), ranges) << "docs/mismatch.md range table should be:\n"
                                                << ranges;
}

// ---- a term added through one row and its builder ----

// A cubic gain, written as the gain change at a reference input x_ref (1 rad/s, 1 g):
// output = input (1 + k3 (input / x_ref)^2).
constexpr double kCubicReference[2] = {1.0, 9.80665};

void buildGainCubic(const TermSpec& spec, const TermBuildContext& ctx, SensorScope scope,
                    std::vector<CandidateTerm>* out) {
  const Sensor s = sensorOf(scope);
  const Eigen::MatrixX3d& u = ctx.triad[s].u;
  CandidateTerm t(spec, scope);
  t.explanation = std::string("the ") + sensorName(s) + " gain grows with the input squared";
  for (int a = 0; a < 3; ++a) {
    RegressorColumn col;
    const Eigen::ArrayXd x = u.col(a).array() / kCubicReference[index(s)];
    col.channel[firstChannel(s) + a] = (x * x * u.col(a).array()).matrix();
    t.columns.push_back(col);
  }
  out->push_back(std::move(t));
}

const TermSpec kGainCubic{
    TermKind::generic,
    "gain_cubic",
    TermRole::candidate,
    TermSensors::each_triad,
    LibraryGroup::triad,
    buildGainCubic,
    "k3 (x / x_ref)^2 x per axis, x_ref 1 rad/s or 1 g",
    {{"k3",
      ParameterLayout::per_axis,
      {"1", "1", nullptr},
      {&PlausibleRanges::gyro_scale_max, &PlausibleRanges::accel_scale_max, nullptr},
      false,
      "gain change at x_ref"}}};

std::vector<const TermSpec*> withGainCubic() {
  std::vector<const TermSpec*> specs = builtInTermSpecs();
  specs.push_back(&kGainCubic);
  return specs;
}

TEST(MismatchTermSpec, AnAddedTermIsBuiltSelectedReportedAndBounded) {
  using namespace mismatch_test;
  const Motion m = carMotion(21);
  const RegressorInputs in = syntheticInputs(m, 300.0, 0.0);
  CandidateLibraryOptions lib;
  lib.terms = withGainCubic();
  const std::vector<CandidateTerm> terms = buildCandidateLibrary(in, lib);
  const int t = findTerm(terms, TermKey{&kGainCubic, SensorScope::gyro});
  ASSERT_GE(t, 0);
  EXPECT_GE(findTerm(terms, TermKey{&kGainCubic, SensorScope::accel}), 0);
  const int n = in.reference.size();
  const Eigen::Vector3d k3(0.0, 0.01, -0.02);
  Eigen::MatrixXd r = termContribution(terms[t], k3, n) + ar1Noise(n, 0.5, 22);
  r.col(2).array() += 2e-3;  // turn-on bias: the nuisance
  const SelectionResult sel = selectTerms(r, terms);
  const auto it = std::find_if(sel.selected.begin(), sel.selected.end(),
                               [&](const TermFit& f) { return f.term == t; });
  ASSERT_NE(it, sel.selected.end()) << "selection log: " << sel.log.size();
  EXPECT_TRUE(it->claimed);
  const Effect e = effectFromTerm(terms[t], *it, n);
  EXPECT_STREQ(e.name(), "gain_cubic");
  ASSERT_EQ(e.parameters.size(), 1u);
  EXPECT_EQ(e.parameters[0].key, "k3");
  for (int a = 1; a < 3; ++a)
    EXPECT_LT(std::abs(e.parameters[0].values[a] - k3(a)), 3.5 * e.parameters[0].sigma[a]);
  // Its bound is its row's: 2 % is beyond a tactical gyro's gain (0.1 %), inside a consumer
  // MEMS's (3 %). (The x axis, with little roll rate, is not determined: the injected values.)
  Effect injected = e;
  injected.parameters[0].values = {k3(0), k3(1), k3(2)};
  EXPECT_FALSE(
      outsidePlausibleRange(injected, plausibleRangesForClass("consumer_mems")).has_value())
      << e.parameters[0].values[0] << " +- " << e.parameters[0].sigma[0];
  const std::optional<RangeExcess> x =
      outsidePlausibleRange(injected, plausibleRangesForClass("tactical"));
  ASSERT_TRUE(x.has_value());
  EXPECT_EQ(x->parameter, "k3");
  EXPECT_EQ(x->bound, plausibleRangesForClass("tactical").gyro_scale_max);
  // And its docs row.
  EXPECT_NE(candidateTermTable(withGainCubic()).find("| gain_cubic | candidate | gyro, accel |"),
            std::string::npos);
}

// Through the whole finder: the real gyro bends cubically on z, and diagnose() claims the added
// term by its row's name and parameter, in the result and in diagnosis.json.
TEST(MismatchTermSpec, DiagnoseClaimsAnAddedTerm) {
  using namespace diagnosis_test;
  Pair p = makePair(ImuErrorModel{}, 31);
  const double k3_z = 0.03;
  for (ImuSample& smp : p.in.real) {
    if (!(smp.dt_s > 0.0)) continue;
    const double w = smp.dtheta_rad(2) / smp.dt_s;
    smp.dtheta_rad(2) += k3_z * std::pow(w / kCubicReference[0], 2) * w * smp.dt_s;
  }
  DiagnoseOptions opt;
  opt.library.terms = withGainCubic();
  const DiagnosisResult r = diagnose(p.in, opt);
  const Effect* e = nullptr;
  for (const Effect& f : r.effects)
    if (f.spec == &kGainCubic) e = &f;
  ASSERT_NE(e, nullptr) << diagnosisMarkdown(r);
  EXPECT_EQ(e->sensor, SensorScope::gyro);
  EXPECT_LT(std::abs(e->parameters[0].values[2] - k3_z), 3.5 * e->parameters[0].sigma[2])
      << diagnosisMarkdown(r);
  const nlohmann::json j = nlohmann::json::parse(diagnosisJson(r));
  bool in_json = false;
  for (const nlohmann::json& f : j["effects"])
    in_json |= f["name"] == "gain_cubic" && f["sensor"] == "gyro" && f["parameters"].contains("k3");
  EXPECT_TRUE(in_json) << j["effects"].dump(1);
}

}  // namespace
}  // namespace graftnav
