#pragma once
// A solution written once, epoch by epoch, to temporary binary files (io/nav_spool.h,
// io/record_spool.h): its states and, when the estimator gives them, its PVA 1-sigmas, read back
// in passes bit for bit. Two solutions of one drive are then compared epoch by epoch (the
// spooled forms of evaluateSolution and crossCheck, cross_check.h) without either being held.
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/estimation/solution_sink.h"
#include "graftnav/io/nav_spool.h"
#include "graftnav/io/record_spool.h"
#include "graftnav/nav/nav_source.h"

namespace graftnav {

class SolutionSpool : public SolutionSink {
 public:
  // Its files in `directory` (empty: TMPDIR), io/record_spool.h.
  explicit SolutionSpool(const std::string& directory = {});
  // The next epoch; a solution gives a sigma at every epoch or at none (std::invalid_argument
  // otherwise). The sensor estimates are not kept.
  void add(const NavState& state, const PvaSigma* sigma, const ImuErrorEstimate& sensors) override;
  void add(const NavState& state, const PvaSigma* sigma);
  // Ends the writing; the passes may be opened from now on.
  void finish();

  std::size_t size() const { return states_.size(); }
  // Every epoch has a sigma (and there is one at least): NavSolution::sigma's rule.
  bool hasSigma() const { return with_sigma_ && size() > 0; }
  // A pass over the states.
  NavOpenFn states() const { return states_.opener(); }

  // A pass over the sigmas in epoch order (only when hasSigma()).
  class SigmaPass {
   public:
    explicit SigmaPass(std::shared_ptr<const RecordSpool> spool);
    bool next(PvaSigma* sigma);

   private:
    RecordPass pass_;
  };
  SigmaPass sigmas() const { return SigmaPass(sigma_); }

 private:
  NavSpool states_;
  std::shared_ptr<RecordSpool> sigma_;
  bool with_sigma_ = false;
};

// Every epoch of a solution held in memory into a finished spool (an estimator run in memory).
void spoolSolution(const NavSolution& solution, SolutionSpool* spool);

}  // namespace graftnav
