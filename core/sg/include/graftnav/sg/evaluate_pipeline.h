#pragma once
// The SG evaluation pipeline behind `graftnav evaluate`, `real-sg` and `batch`: draw K grafted
// realizations of SG#1 and SG#2 from one graft plan (sg/realization.h), navigate each and (when
// recorded) the real tested IMU with one outage schedule, optionally repeated at N shifted starts,
// and compare their errors against SOL_REF. ERR_SGx is the mean over realizations; the
// realizations' spread gives the predictive interval in which ERR_REAL should fall when grafting
// lacks no physics (sg/predictive.h).
//
// With a streamed navigator nothing grows with the recording: the reference IMU and REAL are read
// in blocks (io/imu_recording.h), a realization's grafted IMU is made block by block as the
// reference IMU plus that realization's error signal (GraftSignal: the lab record, or its
// surrogate built once for the realization and shared by its strategies and schedules), and each
// solution is evaluated against SOL_REF as its epochs come (StreamedEvaluation, SOL_REF read as a
// NavSource). A worker holds one navigation and a read window of its realization's signal at a
// time (a surrogate is spooled as it is made, one at a time across workers); the lab record is
// held once. The held form (SgNavigator) hands each grafted series whole to the
// navigator and evaluates the solution it returns with the same code.
//
// The pipeline does not know how a recording is navigated: the caller injects an
// SgStreamNavigator (the apps build the EstimationProblem of the case and run the chosen
// estimator), so core/sg does not depend on filters/ or graph/. Navigations run on worker threads;
// results land at their unit's index, so the outcome does not depend on the thread schedule.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/eval/evaluation.h"
#include "graftnav/eval/outage_schedule.h"
#include "graftnav/eval/streamed_evaluation.h"
#include "graftnav/imu/imu_profile.h"
#include "graftnav/io/imu_recording.h"
#include "graftnav/nav/nav_source.h"
#include "graftnav/nav/types.h"
#include "graftnav/sg/graft_case.h"
#include "graftnav/sg/realization.h"
#include "graftnav/sg/sg_evaluation_report.h"

namespace graftnav {

struct SgEvaluationOptions {
  int realizations =
      20;  // K per strategy; 19 is the smallest K whose [p05, p95] is a 90 % interval
  int outage_shifts = 1;  // N schedules, starts spread over one period
  std::uint64_t seed = 1;
  // Where the field test starts in the tiled lab record (s); negative: drawn per realization.
  double start_offset_s = -1.0;
  // What a realization varies besides the lab-noise segment (sg/realization.h). A basic error
  // signal recorded in the same power-on as the field test (real-sg's standstills) already holds
  // that power-on's bias: no turn-on bias is drawn for it.
  bool vary_turn_on_bias = true;
  bool vary_bias_wander = true;
  std::vector<SgStrategy> strategies{SgStrategy::kBasic, SgStrategy::kFull};
  int jobs = 0;  // navigations in parallel; 0 = all cores
  // A realization's surrogate of the lab record is written to an unlinked spool in TMPDIR and
  // read back in windows (sg/grafting.h), so a worker holds a few MB of it instead of about
  // twice the record (90 MB for 1 h at 200 Hz); false holds it. The same values either way.
  bool spool_surrogates = true;
  EvaluationOptions evaluation;
  // Throws std::invalid_argument naming the field.
  void validate() const;
};

// What the caller loaded besides the graft plan: the reference field IMU the plan is grafted onto,
// the tested IMU's profile and the outage schedule.
struct SgEvaluationInputs {
  std::string case_name;  // for messages and log lines (the case directory)
  ImuRecording reference_recording;
  // The real tested IMU (REAL), when recorded; real_imu_file names it in the report.
  std::optional<ImuRecording> real_recording;
  // The reference field IMU held instead (used when reference_recording.pass is not set).
  ImuSeries reference_imu;
  ImuProfile tested_profile;
  // The reference IMU's noise, when known: its share of the tested IMU's noise is noted.
  std::optional<ImuProfile> reference_noise_profile;
  bool has_real = false;           // REAL is navigated (set when real_recording is)
  std::string real_imu_file;       // its path, for the report
  OutageScheduleConfig outages;    // the first schedule; shifts move its start
  std::vector<std::string> notes;  // leading report notes (e.g. the lab calibration's)
};

// One navigation's outcome: the solution (its epochs only from a held navigator), the outage
// windows it was navigated with and what was assumed (kept in the report for the first unit only).
struct SgNavigation {
  NavSolution solution;
  std::vector<TimeWindow> outages;
  std::vector<std::string> notes;
};

// What a navigator navigates: one realization's grafted IMU (strategy set) or REAL.
struct SgImu {
  ImuRecording imu;
  std::optional<SgStrategy> strategy;  // empty: REAL
  int realization = 0;
};
// Where a navigation's epochs go: the state and its PVA 1-sigma (null when none), in time order.
using SgEpochFn = std::function<void(const NavState& state, const PvaSigma* sigma)>;
// Called by the navigator once its problem is made, before the first epoch, with the outage
// windows and the solution's expected output rate (Hz; 0 unknown); returns where the epochs go.
using SgStartFn =
    std::function<SgEpochFn(const std::vector<TimeWindow>& outages, double solution_rate_hz)>;
// Navigates `imu` with `schedule`: calls `start` once, then hands it every epoch. Called from
// several threads at once: it must not modify shared state.
using SgStreamNavigator = std::function<SgNavigation(
    const SgImu& imu, const OutageScheduleConfig& schedule, const SgStartFn& start)>;
// The held form: navigates `grafted` (moved in), or the real tested IMU when std::nullopt, and
// returns the solution's epochs.
using SgNavigator = std::function<SgNavigation(std::optional<ImuSeries> grafted,
                                               const OutageScheduleConfig& schedule)>;
using SgLogFn = std::function<void(const std::string&)>;

// SOL_REF: read through `open` (each evaluation reads it once, as far as it needs), else from
// `states`.
struct SolutionReference {
  SolutionReference() = default;
  SolutionReference(NavSeries s, std::string d) : states(std::move(s)), description(std::move(d)) {}
  NavSeries states;
  std::string description;  // the report's `reference`
  NavOpenFn open;
  double rate_hz = 0.0;  // expected rate (0 unknown), for the choice of evaluation epochs
};

// What a run does besides navigating: log lines, and where the representative unit's per-epoch
// errors of each solution go (label "SG1", "SG2", "REAL"; a null sink keeps them in the report's
// Evaluation::epochs, as the held form always does).
struct SgRunHooks {
  SgLogFn log;
  std::function<std::unique_ptr<EpochErrorSink>(const std::string& label)> epoch_sink;
};

class SgEvaluationPipeline {
 public:
  // Validates the options, checks that every schedule has an outage inside the reference IMU's
  // span and draws the realizations. Throws std::invalid_argument / std::runtime_error naming the
  // option or the case.
  SgEvaluationPipeline(const SgEvaluationOptions& options, GraftPlan plan,
                       SgEvaluationInputs inputs);

  const std::vector<OutageScheduleConfig>& schedules() const { return schedules_; }
  // Realization k of one strategy as a recording: its blocks grafted as they are read (e.g. to
  // write IMU_SG1.txt with an ImuWriter). The realization's signal is made once per recording.
  ImuRecording graftedRecording(SgStrategy strategy, int realization) const;
  // The same, held.
  ImuSeries graft(SgStrategy strategy, int realization) const;
  // Navigates every unit with `navigate`, evaluates against `reference` as the epochs come and
  // summarizes. Throws when a navigation throws or a realization's outage statistic is not
  // finite.
  SgEvaluationReport run(const SolutionReference& reference, const SgStreamNavigator& navigate,
                         const std::string& estimator_name, const SgRunHooks& hooks = {}) const;
  // The held form: each grafted series is held and handed to `navigate`, whose solution is then
  // evaluated (the representative units' epochs kept in the report).
  SgEvaluationReport run(const SolutionReference& reference, const SgNavigator& navigate,
                         const std::string& estimator_name, const SgLogFn& log = {}) const;

 private:
  void describeRealizations();
  GraftOptions graftOptions(int realization) const;
  const GraftPlan& plan() const { return plan_; }
  struct Work;

  SgEvaluationOptions options_;
  GraftPlan plan_;
  SgEvaluationInputs inputs_;
  std::vector<OutageScheduleConfig> schedules_;
  std::vector<RealizationDraw> draws_;
  double t_first_s_ = 0.0, t_last_s_ = 0.0;
  SgEvaluationReport header_;  // realizations, schedules, notes: filled by the constructor
};

// The N schedules: the periodic schedule with its first start moved by s * period / N.
std::vector<OutageScheduleConfig> shiftedSchedules(const OutageScheduleConfig& schedule,
                                                   int shifts);

}  // namespace graftnav
