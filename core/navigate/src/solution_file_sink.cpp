#include "graftnav/navigate/solution_file_sink.h"

#include <filesystem>

namespace graftnav {

namespace fs = std::filesystem;

SolutionFileSink::SolutionFileSink(const std::string& out_dir, bool with_imu_errors,
                                   StreamedEvaluation* evaluation)
    : nav_((fs::path(out_dir) / "solution.nav").string()),
      outputs_((fs::path(out_dir) / "imu_errors.txt").string(),
               (fs::path(out_dir) / "state_std.txt").string(), with_imu_errors,
               (fs::path(out_dir) / "odometer_scale.txt").string()),
      evaluation_(evaluation) {}

void SolutionFileSink::add(const NavState& state, const PvaSigma* sigma,
                           const ImuErrorEstimate& sensors) {
  nav_.add(state);
  outputs_.add(state, sigma, sensors);
  if (evaluation_) evaluation_->add(state, sigma);
}

void SolutionFileSink::addOdometerScale(const OdometerScaleEstimate& estimate) {
  outputs_.addOdometerScale(estimate);
  last_scale_ = estimate;
}

RunFiles SolutionFileSink::commit() {
  RunFiles f;
  nav_.commit();
  f.epochs = nav_.count();
  outputs_.commit(&f.imu_errors, &f.state_std);
  return f;
}

}  // namespace graftnav
