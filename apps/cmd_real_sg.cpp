// graftnav real-sg CASE_DIR --out DIR --run-config FILE --ref-profile FILE --tested-profile FILE
//   [--realizations K] [--seed S] [--estimator rts]
//   The tested IMU's basic errors from its own standstill spans (sg/standstill_errors.h) grafted
//   onto the reference IMU in K realizations (SG#1 only: no lab, no dynamic model), navigated
//   next to the real tested IMU as in `evaluate` (sg/evaluate_pipeline.h); ERR against SOL_REF
//   with the 90 % predictive interval, REAL's percentile and a verdict. Reader repairs printed.
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli_vocabulary.h"
#include "commands.h"
#include "graftnav/case/reference_solution.h"
#include "graftnav/estimators/estimator_table.h"
#include "graftnav/io/atomic_file.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/sg/evaluate_pipeline.h"
#include "graftnav/sg/standstill_errors.h"
#include "real_case.h"
#include "sg_evaluate.h"

namespace graftnav::app {
namespace {

namespace fs = std::filesystem;

struct RealSgArgs {
  std::string case_dir, out, run_config, ref_profile, tested_profile, estimator = "rts";
  std::uint64_t seed = 1;
  std::optional<int> realizations;  // K; default from the run config (20)
  int jobs = 0;
  StandstillOptions standstill;
  bool no_plots = false;
};

// The standstills of the tested IMU as a basic error signal, and their description.
BasicErrorSignal standstillSignal(const RealSgArgs& a, const CaseInputs& c,
                                  const ImuSelection& tested, std::string* md) {
  const StandstillSpans sp = findStandstills(tested.imu, c.gnss, a.standstill);
  fmt::print(
      stderr,
      "static detector: {} spans, {} dropped because the median GNSS speed inside exceeds {:.2f} m/s\n",
      sp.detection.intervals.size(), sp.dropped_moving, a.standstill.max_gnss_speed_m_s);
  const double yaw0 =
      c.config.initial_state ? eulerFromQuat(c.config.initial_state->q_nb).z() : 0.0;
  const Geodetic pos0 = c.config.initial_state ? c.config.initial_state->pos : c.gnss.front().pos;
  BasicErrorSignal basic(staticErrorIncrements(tested.imu, sp.kept, pos0, yaw0));
  const double t_first = tested.imu.front().t_s - tested.imu.front().dt_s;
  *md = fmt::format(
      "Standstill spans of the tested IMU (static detector: gyro <= {:.3f} rad/s, accel <= {:.2f} "
      "m/s^2 std over 1 s, >= {:.1f} s, {:.1f} s trimmed): ",
      sp.detection.gyro_threshold_rad_s, sp.detection.accel_threshold_m_s2,
      a.standstill.detector.min_duration_s, a.standstill.detector.trim_s);
  for (const auto& s : sp.kept)
    *md += fmt::format("{:.1f}-{:.1f} s, ", s.t_begin_s - t_first, s.t_end_s - t_first);
  *md += fmt::format("({} detected spans dropped: median GNSS speed above {:.2f} m/s inside), ",
                     sp.dropped_moving, a.standstill.max_gnss_speed_m_s);
  const Eigen::Vector3d bg = basic.meanGyro_rad_s() * kRadToDeg, ba = basic.meanAccel_m_s2();
  *md += fmt::format(
      "total {:.1f} s.\nBasic biases (mean of the error signal): gyro [{:.3f} {:.3f} {:.3f}] deg/s, "
      "accel [{:.3f} {:.3f} {:.3f}] m/s^2 (horizontal accel bias absorbed by levelling).\n\n",
      basic.recordLength_s(), bg.x(), bg.y(), bg.z(), ba.x(), ba.y(), ba.z());
  return basic;
}

// Grafted series navigated with the tested IMU's profile; REAL is the tested IMU itself.
SgNavigator realNavigator(const CaseInputs& c, const RunConfig& rc, const ImuSelection& ref,
                          const ImuSelection& tested, const std::string& estimator) {
  return [&c, &rc, &ref, &tested, estimator](std::optional<ImuSeries> grafted,
                                             const OutageScheduleConfig& schedule) {
    SgNavigation nav;
    EstimationProblem pr;
    if (grafted) {
      const ImuSelection sel =
          graftedSelection(std::move(*grafted), tested.profile, ref.read_options);
      grafted.reset();
      pr = problemReal(c, sel, rc, schedule, false, &nav.notes);
    } else {
      pr = problemReal(c, tested, rc, schedule, false, &nav.notes);
    }
    nav.solution = estimatorTable().run(estimator, pr, rc);
    nav.outages = pr.outages;
    return nav;
  };
}

SgEvaluationOptions pipelineOptions(const RealSgArgs& a, const RunConfig& rc) {
  SgEvaluationOptions o;
  o.realizations = a.realizations.value_or(rc.grafting.realizations);
  o.seed = a.seed;
  o.start_offset_s = rc.grafting.start_offset_s;
  o.jobs = a.jobs;
  o.evaluation = rc.evaluation.options;
  o.strategies = {SgStrategy::kBasic};  // no lab: no dynamic model
  o.vary_turn_on_bias = false;          // the standstills hold this power-on's bias
  return o;
}

void runRealSg(const RealSgArgs& a) {
  const CaseInputs c = loadReal(a.case_dir);
  std::vector<std::string> warnings;
  const RunConfig rc = loadRunConfig(a.run_config, &warnings);
  requireTimeRangeUnset(rc.time_range, a.run_config, "graftnav real-sg");
  for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
  if (!rc.outages_given)
    throw std::runtime_error(a.run_config + ": an outages: section is required");
  const ImuSelection ref = loadImuReal(c, "ref", a.ref_profile);
  const ImuSelection tested = loadImuReal(c, "tested", a.tested_profile);
  const SgEvaluationOptions po = pipelineOptions(a, rc);
  po.validate();
  std::string md;
  SgEvaluationInputs in;
  in.case_name = a.case_dir;
  in.reference_imu = ref.imu;
  in.tested_profile = tested.profile;
  in.reference_noise_profile = ref.profile;
  in.has_real = true;
  in.real_imu_file = tested.path;
  in.outages = rc.outages;
  const SgEvaluationPipeline pipeline(po, GraftPlan{standstillSignal(a, c, tested, &md), {}, {}},
                                      std::move(in));
  fmt::print(stderr, "{}", md);

  // SOL_REF: the reference IMU smoothed with all GNSS, from its initial state's epoch as every
  // navigation of the recording (the case's reference.nav comes from another system).
  fmt::print(stderr, "SOL_REF: reference IMU, rts, no outages\n");
  ReferenceSolutionOptions ro;
  ro.use_case_reference = false;
  ro.start_at_initial_state = true;
  const ReferenceSolution sol_ref = resolveReferenceSolution(
      c, [&ref] { return ref; }, rc, estimatorTable(), ro);
  for (const auto& n : sol_ref.notes) fmt::print(stderr, "  note: {}\n", n);
  fs::create_directories(a.out);
  writeNav((fs::path(a.out) / "sol_ref.nav").string(), sol_ref.states);
  const auto log = [](const std::string& m) { fmt::print(stderr, "{}\n", m); };
  SgEvaluationReport rep =
      pipeline.run({sol_ref.states, "RTS-smoothed reference IMU with all GNSS"},
                   realNavigator(c, rc, ref, tested, a.estimator), a.estimator, log);
  rep.case_name = c.config.name;
  if (c.config.tested_imu) rep.tested_grade = c.config.tested_imu->grade;
  rep.csv_rate_hz = rc.evaluation.csv_rate_hz;
  for (auto& s : rep.solutions)
    if (s.label != "REAL") s.imu_file = "(grafted in memory, not written)";
  writeSgOutputs(a.out, rep, !a.no_plots, log);
  writeFileAtomically((fs::path(a.out) / "standstills.md").string(), md);
  printEvaluationSummary(rep);
  fmt::print(
      "wrote {0}/tables.md, {0}/evaluation.json, standstills.md, predictive.csv, sol_ref.nav\n",
      a.out);
}

}  // namespace

void registerRealSg(CLI::App& app) {
  auto s = std::make_shared<RealSgArgs>();
  CLI::App* sg = app.add_subcommand(
      "real-sg",
      "real-data signal grafting: K realizations of the tested IMU's standstill errors on the reference IMU");
  sg->add_option("case_dir", s->case_dir, "case directory (ref_imu.txt and tested_imu.txt)")
      ->required();
  sg->add_option("--out", s->out, "output directory")->required();
  sg->add_option("--run-config", s->run_config,
                 "run config YAML (outages:, gnss:, ekf:, grafting:); required")
      ->check(CLI::ExistingFile);
  addDeprecatedOption(sg, "--config", "--run-config", &s->run_config);
  sg->add_flag("--no-plots", s->no_plots, "skip the matplotlib plots");
  sg->add_option("--ref-profile", s->ref_profile, "reference IMU profile")
      ->required()
      ->check(CLI::ExistingFile);
  sg->add_option("--tested-profile", s->tested_profile, "tested IMU profile")
      ->required()
      ->check(CLI::ExistingFile);
  sg->add_option("--estimator", s->estimator, "estimator (default rts)");
  sg->add_option("--seed", s->seed, "grafting seed (realization k draws from seed and k)");
  sg->add_option("--realizations", s->realizations,
                 "grafted realizations, K (default 20, or grafting.realizations)")
      ->check(CLI::Range(1, 100000));
  sg->add_option("--jobs", s->jobs, "solutions navigated in parallel (0: all cores)")
      ->check(CLI::Range(0, 1024));
  StaticDetectorOptions& d = s->standstill.detector;
  sg->add_option("--static-gyro-threshold", d.gyro_threshold_rad_s,
                 "static detector gyro threshold (rad/s)");
  sg->add_option("--static-accel-threshold", d.accel_threshold_m_s2,
                 "static detector accel threshold (m/s^2)");
  sg->add_option("--min-static", d.min_duration_s, "minimum standstill span (s)");
  sg->add_option(
      "--max-static-speed", s->standstill.max_gnss_speed_m_s,
      "median GNSS speed (1-s chords) above which a detected span is not a standstill (m/s)");
  sg->callback([s]() {
    requireValue(s->run_config, "--run-config");
    runRealSg(*s);
  });
}

}  // namespace graftnav::app
