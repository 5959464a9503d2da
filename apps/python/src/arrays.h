#pragma once
// numpy <-> graftnav series. The compiled module speaks 2-D float64 arrays whose columns are
// named by the lists below (exported to Python, where graftnav/_arrays.py turns them into
// structured arrays and back); units are in the names, angles in degrees as in the i2Nav files.
// An input array holds every column of its list, NaN where a value is absent (dt_s: from the
// time stamps; temperature_degC: none).
#include <pybind11/numpy.h>

#include <string>
#include <vector>

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/estimation/vehicle_aiding.h"
#include "graftnav/nav/types.h"

namespace graftnav::python {

namespace py = pybind11;
using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

const std::vector<std::string>&
imuColumns();  // t_s, dt_s, dtheta_*_rad, dvel_*_m_s, temperature_degC
const std::vector<std::string>&
gnssColumns();  // t_s, lat_deg, lon_deg, height_m, std_*_m, fix_type, num_sv
const std::vector<std::string>& navColumns();    // gnss_week, t_s, lat_deg, ..., heading_deg
const std::vector<std::string>& sigmaColumns();  // pos_std_n_m ... att_std_d_deg (state_std.txt)
const std::vector<std::string>& imuErrorColumns();
const std::vector<std::string>&
odometerColumns();  // t_s, speed_m_s (field/odometer.txt)  // t_s, gyro_bias_x_deg_h ... (imu_errors.txt)

Array imuToArray(const ImuSeries& imu);
Array gnssToArray(const GnssSeries& gnss);
Array navToArray(const NavSeries& nav);

// Throw std::invalid_argument naming the array and the row for a wrong shape, a non-finite value
// or a time not after the previous one. nominal_rate_hz gives the first sample's interval when
// dt_s is absent (as the IMU reader does).
ImuSeries imuFromArray(const Array& a, double nominal_rate_hz, const std::string& name);
GnssSeries gnssFromArray(const Array& a, const std::string& name);
NavSeries navFromArray(const Array& a, const std::string& name);
OdometerSeries odometerFromArray(const Array& a, const std::string& name);

// The returned solution: the epochs at `rows` (navColumns, then sigmaColumns when the solution
// has sigmas) and its IMU errors (imuErrorColumns; empty array when it has none).
Array solutionToArray(const NavSolution& sol, const std::vector<std::size_t>& rows);
Array imuErrorsToArray(const NavSolution& sol, const std::vector<std::size_t>& rows);
// Every epoch, or the first of each 1/rate_hz interval (rate_hz <= 0: every epoch).
std::vector<std::size_t> decimatedRows(const NavSeries& states, double rate_hz);

}  // namespace graftnav::python
