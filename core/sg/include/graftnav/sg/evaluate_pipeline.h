#pragma once
// The SG evaluation pipeline behind `graftnav evaluate`, `real-sg` and `batch`: draw K grafted
// realizations of SG#1 and SG#2 from one graft plan (sg/realization.h), navigate each and (when
// recorded) the real tested IMU with one outage schedule, optionally repeated at N shifted starts,
// and compare their errors against SOL_REF. ERR_SGx is the mean over realizations; the
// realizations' spread gives the predictive interval in which ERR_REAL should fall when grafting
// lacks no physics (sg/predictive.h).
//
// The pipeline does not know how a series is navigated: the caller injects an SgNavigator (the
// apps build the EstimationProblem of the case and run the chosen estimator), so core/sg does not
// depend on filters/ or graph/. Navigations run on worker threads; results land at their unit's
// index, so the outcome does not depend on the thread schedule.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/eval/evaluation.h"
#include "graftnav/eval/outage_schedule.h"
#include "graftnav/imu/imu_profile.h"
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
  EvaluationOptions evaluation;
  // Throws std::invalid_argument naming the field (the flag spelling of `evaluate`).
  void validate() const;
};

// What the caller loaded besides the graft plan: the reference field IMU the plan is grafted onto,
// the tested IMU's profile and the outage schedule.
struct SgEvaluationInputs {
  std::string case_name;  // for messages and log lines (the case directory)
  ImuSeries reference_imu;
  ImuProfile tested_profile;
  // The reference IMU's noise, when known: its share of the tested IMU's noise is noted.
  std::optional<ImuProfile> reference_noise_profile;
  bool has_real = false;           // a real tested IMU recording is navigated too (REAL)
  std::string real_imu_file;       // its path, for the report
  OutageScheduleConfig outages;    // the first schedule; shifts move its start
  std::vector<std::string> notes;  // leading report notes (e.g. the lab calibration's)
};

// One navigation's outcome: the solution, the outage windows it was navigated with and what was
// assumed (kept in the report for the first unit only).
struct SgNavigation {
  NavSolution solution;
  std::vector<TimeWindow> outages;
  std::vector<std::string> notes;
};
// Navigates `grafted` (moved in), or the real tested IMU when std::nullopt, with `schedule`.
// Called from several threads at once: it must not modify shared state.
using SgNavigator = std::function<SgNavigation(std::optional<ImuSeries> grafted,
                                               const OutageScheduleConfig& schedule)>;
using SgLogFn = std::function<void(const std::string&)>;

struct SolutionReference {
  NavSeries states;
  std::string description;  // the report's `reference`
};

class SgEvaluationPipeline {
 public:
  // Validates the options, checks that every schedule has an outage inside the reference IMU's
  // span and draws the realizations. Throws std::invalid_argument / std::runtime_error naming the
  // option or the case.
  SgEvaluationPipeline(const SgEvaluationOptions& options, GraftPlan plan,
                       SgEvaluationInputs inputs);

  const std::vector<OutageScheduleConfig>& schedules() const { return schedules_; }
  // Realization k of one strategy: the series the navigator receives (e.g. to write IMU_SG1.txt).
  ImuSeries graft(SgStrategy strategy, int realization) const;
  // Navigates every unit with `navigate`, evaluates against `reference` and summarizes. Throws
  // when a navigation throws or a realization's outage statistic is not finite.
  SgEvaluationReport run(const SolutionReference& reference, const SgNavigator& navigate,
                         const std::string& estimator_name, const SgLogFn& log = {}) const;

 private:
  void describeRealizations();

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
