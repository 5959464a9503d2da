#include "graftnav/filters/filter_estimators.h"

#include "graftnav/filters/ekf.h"
#include "graftnav/filters/free_inertial.h"
#include "graftnav/filters/rts_smoother.h"

namespace graftnav {

void addFilterEstimators(EstimatorRegistry* registry) {
  registry->add({"ekf", "forward closed-loop 21-state GNSS/INS EKF",
                 [](const EstimationProblem& p, const EstimatorOptions& o, const ProgressFn& f) {
                   return runEkf(p, o.ekf, nullptr, f);
                 },
                 [](const EstimationProblem& p, const ImuPassFn& imu, const EstimatorOptions& o,
                    SolutionSink& sink) { return runEkfStreaming(p, o.ekf, imu, sink); }});
  EstimatorEntry rts{"rts", "EKF + Rauch-Tung-Striebel smoother",
                     [](const EstimationProblem& p, const EstimatorOptions& o,
                        const ProgressFn& f) { return runRts(p, o.ekf, nullptr, nullptr, f); },
                     [](const EstimationProblem& p, const ImuPassFn& imu, const EstimatorOptions& o,
                        SolutionSink& sink) { return runRtsStreaming(p, o.ekf, imu, sink); }};
  rts.smooths = "ekf";
  registry->add(std::move(rts));
  EstimatorEntry free_inertial{
      "free-inertial",
      "mechanization from the initial state, no GNSS",
      [](const EstimationProblem& p, const EstimatorOptions& o, const ProgressFn& f) {
        return runFreeInertial(p, o.ekf.output_decimation, f);
      },
      {}};
  free_inertial.uses_gnss = false;
  registry->add(std::move(free_inertial));
}

}  // namespace graftnav
