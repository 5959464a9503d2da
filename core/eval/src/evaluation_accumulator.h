#pragma once
// The statistics of an Evaluation, summed epoch by epoch in time order: shared by the in-memory
// evaluation (evaluation.cpp) and the streamed one (streamed_evaluation.cpp), so that both give
// the same numbers from the same epochs.

#include <functional>
#include <vector>

#include "graftnav/eval/evaluation.h"

namespace graftnav::eval_detail {

// The error of a solution state against the reference state at the same time.
EpochError epochError(const NavState& s, const NavState& ref);

// Epoch errors in time order, summed into the statistics of an Evaluation: overall and outage
// RMS, per-outage maxima, NEES at most every nees_interval_s. Each epoch's error is handed to
// `on_epoch` (the in-memory evaluation keeps it, the streamed one writes it).
class EvaluationAccumulator {
 public:
  using EpochFn = std::function<void(const EpochError&)>;
  // `windows` sorted by start; `windows`, `options` and `ev` must outlive the accumulator.
  EvaluationAccumulator(const std::vector<TimeWindow>& windows, const EvaluationOptions& options,
                        Evaluation* ev, EpochFn on_epoch);

  void add(const NavState& s, const PvaSigma* sg, const NavState& ref);
  // Fills the statistics of the Evaluation from the epochs added.
  void finish();

 private:
  struct RmsSum {
    double h2 = 0, v2 = 0, r2 = 0, p2 = 0, y2 = 0;
    long n = 0;
    void add(double h, double v, double r, double p, double y);
    DriftStats rms() const;
  };
  void addNees(EpochError& e, const PvaSigma& sg, double t_s);

  const std::vector<TimeWindow>& windows_;
  const EvaluationOptions& options_;
  Evaluation* ev_;
  EpochFn on_epoch_;
  std::vector<OutageDrift> drift_;
  RmsSum all_, in_outage_;
  size_t w_ = 0;
  double nees_sum_ = 0.0, last_nees_t_;
};

// The outages sorted by start (the accumulator's order).
std::vector<TimeWindow> sortedWindows(std::vector<TimeWindow> outages);

// The rate of a series for EvaluationEpochs::kAuto: (count - 1) / span, 0 for fewer than 2.
double seriesRate(std::size_t count, double t_first_s, double t_last_s);

}  // namespace graftnav::eval_detail
