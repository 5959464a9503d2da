#pragma once
// What `graftnav diagnose` writes: diagnosis.json in the shape the finder specifies (plus extra
// keys), a Markdown report, and residual.csv for the plots (scripts/runtime/plot_diagnosis.py).
//
// diagnosis.json: {"case", "located": [{channel, t_start, t_end, regime, excess_rms}],
//   "effects": [{name, sensor, parameters, uncertainty, evidence: {delta_bic, cv_gain}, explanation}],
//   "unexplained": [{channel, t_start, t_end, regime, excess_rms}],
//   extra "ambiguous": [{as an effect, evidence also name_margin, "alternative": name}] (found and
//   modelled in SG#3, shape not settled: not claimed), "modelled_in_simulation", ...
//   "fit": {signal_rms_before: {gyro: [3], accel: [3]}, signal_rms_after, diff_before, diff_after}}
// diff_* are S = {horizontal_m, vertical_m, roll_deg, pitch_deg, heading_deg} (fractions) when a
// navigation comparison was run, else null. Non-finite numbers (unknown uncertainties) are null.

#include <string>
#include <vector>

#include "graftnav/eval/evaluation.h"
#include "graftnav/mismatch/diagnosis.h"

namespace graftnav {

// Navigation level of the diagnosis: outage statistics of SG#2, SG#3 and REAL against SOL_REF.
struct NavigationComparison {
  std::string estimator;
  int outage_count = 0;
  double outage_length_s = 0.0;
  DriftStats err_sg2, err_sg3, err_real;
  DriftStats diff_before, diff_after;  // |ERR_SG2 - ERR_REAL| / ERR_REAL, same for SG3
  // Per outage: which windows carry most of |ERR_SG2 - ERR_REAL| (horizontal, m).
  struct OutageShare {
    TimeWindow window;
    double sg2_horizontal_m = 0.0, sg3_horizontal_m = 0.0, real_horizontal_m = 0.0;
    double share = 0.0;  // this outage's part of sum |SG2 - REAL|
  };
  std::vector<OutageShare> outages;
};

std::string diagnosisJson(const DiagnosisResult& result, const NavigationComparison* nav = nullptr);
std::string diagnosisMarkdown(const DiagnosisResult& result,
                              const NavigationComparison* nav = nullptr);
// Writes out_dir/diagnosis.json, diagnosis.md and residual.csv (t_s, residual x6, model x6, regime).
// Throws std::runtime_error when a file cannot be written.
void writeDiagnosisFiles(const std::string& out_dir, const DiagnosisResult& result,
                         const NavigationComparison* nav = nullptr);

}  // namespace graftnav
