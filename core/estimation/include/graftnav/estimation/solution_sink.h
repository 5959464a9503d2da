#pragma once
// Where an estimator puts its output, one epoch at a time: into a NavSolution in memory
// (NavSolutionSink) or anywhere else (a file writer), so that one filter serves both the
// in-memory path and the streaming path whose memory does not grow with the recording.

#include <cstddef>

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/estimation/imu_error_estimate.h"

namespace graftnav {

class SolutionSink {
 public:
  virtual ~SolutionSink() = default;
  // One output epoch: the state, its PVA 1-sigma (null when the estimator gives none) and the
  // sensor-error estimates at that epoch.
  virtual void add(const NavState& state, const PvaSigma* sigma,
                   const ImuErrorEstimate& sensors) = 0;
  // When the estimator estimates the odometer scale factor: its value at the epoch given next
  // to add(), called just before it. Ignored unless a sink wants it.
  virtual void addOdometerScale(const OdometerScaleEstimate& /*estimate*/) {}
};

// Appends every epoch to the vectors of a NavSolution (sigma only when given).
class NavSolutionSink : public SolutionSink {
 public:
  explicit NavSolutionSink(NavSolution* solution) : sol_(solution) {}
  void reserve(std::size_t epochs);
  void add(const NavState& state, const PvaSigma* sigma, const ImuErrorEstimate& sensors) override;
  void addOdometerScale(const OdometerScaleEstimate& estimate) override;

 private:
  NavSolution* sol_;
};

}  // namespace graftnav
