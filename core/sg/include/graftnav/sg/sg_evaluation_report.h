#pragma once
// What an SG evaluation found (evaluate_pipeline.h): per solution (SG1, SG2, REAL) the outage
// errors against SOL_REF, the K realizations' ERR and their predictive summary, and the run's
// outage schedule and notes. The apps turn it into evaluation.json, tables.md and the CSVs.
#include <optional>
#include <string>
#include <vector>

#include "graftnav/eval/evaluation.h"
#include "graftnav/nav/time_window.h"
#include "graftnav/sg/predictive.h"
#include "graftnav/sg/sg_statistics.h"
#include "graftnav/imu/imu_grade.h"

namespace graftnav {

struct SgSolutionErrors {
  std::string label;     // "SG1", "SG2", "REAL", "SG3"
  std::string imu_file;  // what was navigated (for SG: realization 0)
  // Against SOL_REF, of realization 0 at the first outage schedule: the per-epoch and per-outage
  // CSVs and the plots.
  Evaluation evaluation;
  // The reported ERR: mean over realizations (SG) and over outage schedules.
  DriftStats err_rms;             // the seed's statistic
  DriftStats err_max_rms;         // the peers' statistic
  std::vector<DriftStats> draws;  // SG only: ERR of each realization
  PredictiveStats predictive;     // SG only
  // For results built from one Evaluation (one realization, one schedule).
  static SgSolutionErrors single(const std::string& label, const std::string& imu_file,
                                 Evaluation e);
};

struct SgEvaluationReport {
  std::string case_name;
  std::string estimator;
  std::string
      reference;  // what SOL_REF is: "truth", "reference_solution", "smoothed reference IMU (rts)"
  std::optional<ImuGrade> tested_grade;  // case.yaml's tested_imu grade, when it has one
  std::vector<TimeWindow> outages;       // of the first schedule
  double outage_length_s = 0.0;
  int realizations = 1;   // K per SG strategy
  int outage_shifts = 1;  // N schedules
  std::vector<double>
      shift_starts_s;  // first-outage start of each schedule (s after the first epoch)
  double static_record_s = 0.0;
  double shared_sample_fraction = 0.0;
  double csv_rate_hz = 10.0;
  std::vector<SgSolutionErrors> solutions;  // SG1, SG2 and REAL when present
  std::vector<std::string> notes;

  const SgSolutionErrors* find(const std::string& label) const;
  // DIFF_x per statistic, when REAL exists.
  std::optional<DriftStats> diff(const std::string& label) const;
};

}  // namespace graftnav
