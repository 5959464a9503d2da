#pragma once
// Per-epoch outputs of a navigation run beside solution.nav, in the i2Nav column layouts
// (KF-GINS's IMU_ERR and STD files) with one '#' header line naming every column and its unit:
//   imu_errors.txt  time (s), gyro bias x y z (deg/h), accel bias x y z (mGal),
//                   gyro scale x y z (ppm), accel scale x y z (ppm)
//   state_std.txt   time (s), position std N E D (m), velocity std N E D (m/s),
//                   attitude error std about north, east, down (deg)
//   odometer_scale.txt  time (s), odometer scale error (ppm: +3000 reads 0.3 % fast) and, when
//                   the estimator gives it, its 1-sigma (ppm); only with an estimated scale
// docs/outputs.md lists them with every other output file.
#include <memory>
#include <optional>
#include <string>

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/estimation/solution_sink.h"
#include "graftnav/io/atomic_file.h"

namespace graftnav {

// Written only when the estimator gives the series (NavSolution fields non-empty); returns
// whether the file was written. Throws std::runtime_error naming the path on a write error or a
// non-finite value (no NaN is ever written).
bool writeImuErrors(const std::string& path, const NavSolution& sol);
bool writeStateStd(const std::string& path, const NavSolution& sol);
// The odometer scale series (NavSolution::odometer_scale); the 1-sigma column only when every
// epoch has a finite one (the factor graphs give none).
bool writeOdometerScale(const std::string& path, const NavSolution& sol);

// The same two files written epoch by epoch (a streamed run): byte-identical to writeImuErrors and
// writeStateStd on the NavSolution of the same epochs, and written under the same conditions
// (state_std.txt not when an epoch has no sigma or a non-finite one). Nothing is visible until
// commit(); a sink destroyed without commit() leaves no file. with_imu_errors = false for an
// estimator whose solution has no scale-factor series (the factor graphs: writeImuErrors writes
// nothing for them), since the sink's zero scales cannot tell.
class SolutionOutputsSink : public SolutionSink {
 public:
  // odometer_scale_path empty: no odometer_scale.txt; else written when the estimator reports
  // the scale (addOdometerScale before each add), as writeOdometerScale would.
  SolutionOutputsSink(const std::string& imu_errors_path, const std::string& state_std_path,
                      bool with_imu_errors, const std::string& odometer_scale_path = "");
  void add(const NavState& state, const PvaSigma* sigma, const ImuErrorEstimate& sensors) override;
  void addOdometerScale(const OdometerScaleEstimate& estimate) override;
  // Renames the files into place; *imu_errors / *state_std (/ *odometer_scale) tell which were
  // written.
  void commit(bool* imu_errors, bool* state_std, bool* odometer_scale = nullptr);

 private:
  struct File {
    std::unique_ptr<AtomicFile> file;
    std::string buffer;
    void flush(bool force);
  };
  File imu_errors_, state_std_, odometer_scale_;
  std::string odometer_scale_path_;
  std::optional<OdometerScaleEstimate> pending_scale_;
  bool scale_with_std_ = false;
  std::size_t epochs_ = 0, scale_epochs_ = 0;
};

}  // namespace graftnav
