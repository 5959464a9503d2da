#pragma once
// The per-epoch files of a streamed run, written as the estimator gives its epochs:
// solution.nav, imu_errors.txt, state_std.txt and odometer_scale.txt (graftnav/case/
// solution_files.h), byte-identical to the files written from the whole solution. Each epoch is
// also handed to the evaluation against the reference when one is given. Nothing is visible
// until commit(); a sink destroyed without commit() leaves no file.
#include <cstddef>
#include <optional>
#include <string>

#include "graftnav/case/solution_files.h"
#include "graftnav/estimation/solution_sink.h"
#include "graftnav/eval/streamed_evaluation.h"
#include "graftnav/io/nav_io.h"

namespace graftnav {

// The per-epoch files of a run: how many epochs, and which of the optional files were written.
struct RunFiles {
  std::size_t epochs = 0;
  bool imu_errors = false, state_std = false;
};

class SolutionFileSink : public SolutionSink {
 public:
  // with_imu_errors: the estimator has scale-factor series (EstimatorEntry::
  // estimates_scale_factors). evaluation: null for none; must outlive the sink.
  SolutionFileSink(const std::string& out_dir, bool with_imu_errors,
                   StreamedEvaluation* evaluation);
  void add(const NavState& state, const PvaSigma* sigma, const ImuErrorEstimate& sensors) override;
  void addOdometerScale(const OdometerScaleEstimate& estimate) override;
  // The last odometer scale estimate (run_info.json), when the run estimated one.
  const std::optional<OdometerScaleEstimate>& lastOdometerScale() const { return last_scale_; }
  RunFiles commit();

 private:
  NavWriter nav_;
  SolutionOutputsSink outputs_;
  StreamedEvaluation* evaluation_;
  std::optional<OdometerScaleEstimate> last_scale_;
};

}  // namespace graftnav
