#include "graftnav/navigate/streamed_problem.h"

#include <stdexcept>
#include <utility>

#include "graftnav/case/problem.h"
#include "graftnav/navigate/streamed_imu_file.h"

namespace graftnav {
namespace {

// The first prefix an in-motion alignment is tried on, and how much longer each retry reads.
constexpr double kFirstMotionPrefix_s = 30.0;
constexpr double kMotionPrefixGrowth = 1.5;

// makeProblem on the samples through an in-motion alignment. alignInMotion takes the first GNSS
// epoch that passes its speed and gap tests and has samples in its levelling window; every
// earlier epoch's window lies before it. So the problem made from a prefix that holds the window
// of the epoch it picked equals the one made from the whole file; otherwise (or when the prefix
// held no such epoch) a longer prefix is read.
EstimationProblem motionProblem(const CaseInputs& c, const ImuSelection& sel, const RunConfig& rc,
                                const std::optional<OutageScheduleConfig>& outages,
                                const TimeRangeConfig& range, std::vector<std::string>* notes) {
  const ImuSeries& span = sel.imu;
  const double t_first_s = span.front().t_s - span.front().dt_s;
  const double half_window_s = 0.5 * rc.alignment.motion.level_window_s;
  for (double length_s = kFirstMotionPrefix_s;; length_s *= kMotionPrefixGrowth) {
    const double t_end_s = t_first_s + length_s;
    ImuSelection prefix = sel;
    bool complete = false;
    prefix.imu = imuPrefix(sel, span, range, t_end_s, &complete);
    std::vector<std::string> tried_notes;
    EstimationProblem pr;
    try {
      pr = makeProblem(c, std::move(prefix), rc, outages, &tried_notes);
    } catch (const std::runtime_error&) {
      if (complete) throw;  // the whole series: makeProblem's own error
      continue;
    }
    if (complete || pr.initial.t_s + half_window_s <= t_end_s) {
      if (notes) notes->insert(notes->end(), tried_notes.begin(), tried_notes.end());
      return pr;
    }
  }
}

}  // namespace

EstimationProblem makeStreamedProblem(const CaseInputs& c, const ImuSelection& imu,
                                      const RunConfig& rc,
                                      const std::optional<OutageScheduleConfig>& outages,
                                      const TimeRangeConfig& range,
                                      std::vector<std::string>* notes) {
  if (rc.alignment.mode == AlignmentMode::kMotion)
    return motionProblem(c, imu, rc, outages, range, notes);
  ImuSelection problem_imu = imu;
  problem_imu.imu = alignmentPrefix(imu, rc, imu.imu, range);
  return makeProblem(c, std::move(problem_imu), rc, outages, notes);
}

}  // namespace graftnav
