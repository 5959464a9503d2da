#pragma once
// Per-epoch outputs of a navigation run beside solution.nav, in the i2Nav column layouts
// (KF-GINS's IMU_ERR and STD files) with one '#' header line naming every column and its unit:
//   imu_errors.txt  time (s), gyro bias x y z (deg/h), accel bias x y z (mGal),
//                   gyro scale x y z (ppm), accel scale x y z (ppm)
//   state_std.txt   time (s), position std N E D (m), velocity std N E D (m/s),
//                   attitude error std about north, east, down (deg)
// docs/outputs.md lists them with every other output file.
#include <string>

#include "graftnav/estimation/nav_solution.h"

namespace graftnav::app {

// Written only when the estimator gives the series (NavSolution fields non-empty); returns
// whether the file was written. Throws std::runtime_error naming the path on a write error or a
// non-finite value (no NaN is ever written).
bool writeImuErrors(const std::string& path, const NavSolution& sol);
bool writeStateStd(const std::string& path, const NavSolution& sol);

}  // namespace graftnav::app
