#pragma once
// The numbers of `graftnav compare` and its files: each estimator's errors against the reference
// (a row) and each pair's differences inside the outages with the cross-check (a pair), written
// as compare.md (also printed), compare.csv, compare.json, compare_outages.csv and
// compare_errors.csv (the 1 Hz error series for scripts/runtime/plot_compare.py). docs/outputs.md
// describes each file.
#include <optional>
#include <string>
#include <vector>

#include "graftnav/eval/cross_check.h"
#include "graftnav/eval/evaluation.h"
#include "graftnav/eval/outage_schedule.h"
#include "graftnav/eval/streamed_evaluation.h"

namespace graftnav {

struct CompareRow {
  std::string name;
  double seconds = 0.0;  // the estimator's run
  Evaluation eval;       // statistics only: the epochs are evaluated as a stream
  // The epochs of the 1 Hz error series: the first row's every >= 1 s, each other row's at or
  // after each of those times (the last when none is); CompareSeriesSink keeps them.
  std::vector<EpochError> series;
  int gnss_rejected = 0;
};

// Differences inside outages: a evaluated against b as the reference.
struct ComparePair {
  std::string a, b;
  DriftStats rms, max_rms;
  CrossCheck cross;  // the difference weighed by its own sigma, when both carry sigmas
};

struct CompareReport {
  std::string case_dir;
  std::string imu;               // the IMU chosen (ref, tested or a file)
  std::string imu_profile_name;  // its profile's name
  std::string reference_name;    // the reference file the errors are against
  OutageScheduleConfig schedule;
  std::vector<TimeWindow> outages;
  std::vector<CompareRow> rows;
  std::vector<ComparePair> pairs;
};

// The five files into out_dir (each written atomically). Returns compare.md's text; *absent
// counts the statistics that could not be computed (no outage epoch, a zero denominator),
// written as "-" in Markdown and as empty CSV cells.
std::string writeCompareFiles(const CompareReport& report, const std::string& out_dir, int* absent);

// Keeps the epochs of a row's 1 Hz error series as they are evaluated (CompareRow::series);
// `grid` null for the first row, else the first row's series.
class CompareSeriesSink final : public EpochErrorSink {
 public:
  CompareSeriesSink(const std::vector<EpochError>* grid, std::vector<EpochError>* out)
      : grid_(grid), out_(out) {}
  void add(const EpochError& e) override;
  void commit() override;

 private:
  const std::vector<EpochError>* grid_;
  std::vector<EpochError>* out_;
  std::vector<EpochError> kept_;
  std::optional<EpochError> last_;
  double next_t_ = 0.0;
};

}  // namespace graftnav
