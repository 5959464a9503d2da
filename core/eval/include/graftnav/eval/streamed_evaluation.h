#pragma once
// Errors of a solution against a reference while the estimator writes: the solution's epochs are
// added one at a time, the reference is read from a NavSource only as far as the join on time
// needs it, and each evaluated epoch's error goes to a sink as it is made. The interpolation,
// the epochs and the statistics are those of evaluateSolution (evaluation.h), number for number;
// memory holds a window of a few dozen epochs of each series, whatever their length.
//
// EvaluationEpochs::kAuto evaluates at the epochs of the sparser series, compared by their rates
// (count - 1) / span, which are known only when both have ended. With expected rates whose ratio
// is beyond kDecisiveRateRatio (e.g. a 10 Hz truth and a 200 Hz solution) only the sparser
// series' epochs are evaluated; otherwise (equal nominal rates, where the choice turns on the
// last digit) both sets are evaluated side by side, each into its own sink, and finish() keeps
// the one the final rates choose.

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "graftnav/eval/evaluation.h"
#include "graftnav/nav/nav_source.h"

namespace graftnav {

// Where evaluated epochs go as they are made (an errors.csv writer, a 1 Hz series).
class EpochErrorSink {
 public:
  virtual ~EpochErrorSink() = default;
  virtual void add(const EpochError& e) = 0;
  // Called on the kept sink only, when its output is final (a file writer commits here); a sink
  // that is not kept is destroyed without it.
  virtual void commit() {}
};
using EpochSinkFactory = std::function<std::unique_ptr<EpochErrorSink>()>;

// The rates the caller expects (Hz; 0 = unknown): the solution's from the IMU it navigates and
// its output decimation, the reference's from a look at its file. They only choose which epoch
// sets are worth evaluating; the choice itself is made from the series as they were.
struct ExpectedRates {
  double solution_hz = 0.0;
  double reference_hz = 0.0;
};

class StreamedEvaluation {
 public:
  // Expected rates further apart than this factor decide kAuto before the run.
  static constexpr double kDecisiveRateRatio = 1.25;

  // `reference` is read as needed (a strict .nav reader throws on a bad line when it reaches
  // it). `make_sink` (may be empty) makes one sink per evaluated epoch set. Throws
  // std::invalid_argument for invalid options.
  StreamedEvaluation(std::unique_ptr<NavSource> reference, const std::vector<TimeWindow>& outages,
                     const EvaluationOptions& options, std::string solution_name,
                     const ExpectedRates& expected = {}, const EpochSinkFactory& make_sink = {});
  ~StreamedEvaluation();
  StreamedEvaluation(const StreamedEvaluation&) = delete;
  StreamedEvaluation& operator=(const StreamedEvaluation&) = delete;

  // The next solution epoch (times not decreasing), with its PVA 1-sigma or null; a solution
  // gives a sigma at every epoch or at none (std::invalid_argument otherwise).
  void add(const NavState& state, const PvaSigma* sigma);
  // Ends the solution, reads the rest of the reference and returns the evaluation (epochs empty,
  // epoch_count set). Throws std::invalid_argument as evaluateSolution does when the series do not
  // overlap or no epoch was evaluated.
  Evaluation finish();
  // Commits the kept sink (after finish()).
  void commitEpochs();

  // How many epoch sets are being evaluated (1, or 2 while kAuto is undecided).
  int epochSets() const;
  // Epochs of the two series held now (the join's window): bounded whatever their length.
  std::size_t heldEpochs() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// evaluateSolution through StreamedEvaluation: the solution's epochs added one by one against
// `reference` (no expected rates: both epoch sets are evaluated under kAuto). The reference
// test of the streamed path against the in-memory one.
Evaluation evaluateSolutionStreamed(const NavSolution& solution, const NavOpenFn& reference,
                                    const std::vector<TimeWindow>& outages,
                                    const EvaluationOptions& options = {},
                                    const EpochSinkFactory& make_sink = {});

}  // namespace graftnav
