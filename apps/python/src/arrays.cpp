#include "arrays.h"

#include <fmt/core.h>

#include <cmath>
#include <stdexcept>

#include "graftnav/nav/rotation.h"
#include "graftnav/nav/units.h"

namespace graftnav::python {
namespace {

constexpr double kMilliGalPerMPerSec2 = 1e5;  // 1 mGal = 1e-5 m/s^2 (imu_errors.txt)
constexpr double kPpmPerFraction = 1e6;

Array newArray(std::size_t rows, std::size_t cols) {
  return Array({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)});
}

// The array's rows, checked: 2-D with the list's column count.
auto checkedRows(const Array& a, const std::vector<std::string>& columns, const std::string& name) {
  if (a.ndim() != 2 || a.shape(1) != static_cast<py::ssize_t>(columns.size()))
    throw std::invalid_argument(
        fmt::format("{}: expected {} columns, got shape ({})", name, columns.size(),
                    a.ndim() == 2 ? fmt::format("{}, {}", a.shape(0), a.shape(1))
                                  : std::to_string(a.ndim()) + "-D"));
  if (a.shape(0) == 0) throw std::invalid_argument(name + ": no rows");
  return a.unchecked<2>();
}

template <typename Rows>
void requireFinite(const Rows& r, py::ssize_t row, std::initializer_list<int> cols,
                   const std::vector<std::string>& names, const std::string& name) {
  for (int c : cols)
    if (!std::isfinite(r(row, c)))
      throw std::invalid_argument(
          fmt::format("{}: row {}: {} is not finite ({})", name, row, names[c], r(row, c)));
}

template <typename Rows>
void requireIncreasing(const Rows& r, py::ssize_t row, int col, const std::string& name) {
  if (row > 0 && !(r(row, col) > r(row - 1, col)))
    throw std::invalid_argument(
        fmt::format("{}: row {}: time {:.6f} s is not after the previous {:.6f} s", name, row,
                    r(row, col), r(row - 1, col)));
}

double headingDeg(double yaw_deg) {
  double h = yaw_deg < 0.0 ? yaw_deg + 360.0 : yaw_deg;  // [0, 360) as in .nav files
  return h >= 360.0 ? h - 360.0 : h;
}

void fillNavRow(const NavState& s, double* v) {
  const Eigen::Vector3d e_deg = eulerFromQuat(s.q_nb.normalized()) * units::kRadToDeg;
  const double row[11] = {static_cast<double>(s.gnss_week),
                          s.t_s,
                          s.pos.lat_rad * units::kRadToDeg,
                          s.pos.lon_rad * units::kRadToDeg,
                          s.pos.h_m,
                          s.v_n.x(),
                          s.v_n.y(),
                          s.v_n.z(),
                          e_deg.x(),
                          e_deg.y(),
                          headingDeg(e_deg.z())};
  std::copy(row, row + 11, v);
}

}  // namespace

const std::vector<std::string>& imuColumns() {
  static const std::vector<std::string> c{"t_s",          "dt_s",         "dtheta_x_rad",
                                          "dtheta_y_rad", "dtheta_z_rad", "dvel_x_m_s",
                                          "dvel_y_m_s",   "dvel_z_m_s",   "temperature_degC"};
  return c;
}
const std::vector<std::string>& gnssColumns() {
  static const std::vector<std::string> c{"t_s",     "lat_deg", "lon_deg",  "height_m", "std_n_m",
                                          "std_e_m", "std_d_m", "fix_type", "num_sv"};
  return c;
}
const std::vector<std::string>& navColumns() {
  static const std::vector<std::string> c{"gnss_week", "t_s",       "lat_deg",    "lon_deg",
                                          "height_m",  "v_n_m_s",   "v_e_m_s",    "v_d_m_s",
                                          "roll_deg",  "pitch_deg", "heading_deg"};
  return c;
}
const std::vector<std::string>& sigmaColumns() {
  static const std::vector<std::string> c{"pos_std_n_m",   "pos_std_e_m",   "pos_std_d_m",
                                          "vel_std_n_m_s", "vel_std_e_m_s", "vel_std_d_m_s",
                                          "att_std_n_deg", "att_std_e_deg", "att_std_d_deg"};
  return c;
}
const std::vector<std::string>& imuErrorColumns() {
  static const std::vector<std::string> c{"t_s",
                                          "gyro_bias_x_deg_h",
                                          "gyro_bias_y_deg_h",
                                          "gyro_bias_z_deg_h",
                                          "accel_bias_x_mGal",
                                          "accel_bias_y_mGal",
                                          "accel_bias_z_mGal",
                                          "gyro_scale_x_ppm",
                                          "gyro_scale_y_ppm",
                                          "gyro_scale_z_ppm",
                                          "accel_scale_x_ppm",
                                          "accel_scale_y_ppm",
                                          "accel_scale_z_ppm"};
  return c;
}

const std::vector<std::string>& odometerColumns() {
  static const std::vector<std::string> c{"t_s", "speed_m_s"};
  return c;
}

OdometerSeries odometerFromArray(const Array& a, const std::string& name) {
  const auto r = checkedRows(a, odometerColumns(), name);
  OdometerSeries odo(r.shape(0));
  for (py::ssize_t k = 0; k < r.shape(0); ++k) {
    requireFinite(r, k, {0, 1}, odometerColumns(), name);
    requireIncreasing(r, k, 0, name);
    odo[k] = OdometerSample{r(k, 0), r(k, 1)};
  }
  return odo;
}

Array imuToArray(const ImuSeries& imu) {
  Array a = newArray(imu.size(), imuColumns().size());
  auto r = a.mutable_unchecked<2>();
  for (std::size_t k = 0; k < imu.size(); ++k) {
    const ImuSample& s = imu[k];
    const double row[9] = {
        s.t_s,          s.dt_s,         s.dtheta_rad.x(), s.dtheta_rad.y(),  s.dtheta_rad.z(),
        s.dvel_m_s.x(), s.dvel_m_s.y(), s.dvel_m_s.z(),   s.temperature_degC};
    for (int c = 0; c < 9; ++c) r(k, c) = row[c];
  }
  return a;
}

Array gnssToArray(const GnssSeries& gnss) {
  Array a = newArray(gnss.size(), gnssColumns().size());
  auto r = a.mutable_unchecked<2>();
  for (std::size_t k = 0; k < gnss.size(); ++k) {
    const GnssFix& f = gnss[k];
    const double row[9] = {f.t_s,
                           f.pos.lat_rad * units::kRadToDeg,
                           f.pos.lon_rad * units::kRadToDeg,
                           f.pos.h_m,
                           f.std_ned_m.x(),
                           f.std_ned_m.y(),
                           f.std_ned_m.z(),
                           static_cast<double>(f.fix_type),
                           static_cast<double>(f.num_sv)};
    for (int c = 0; c < 9; ++c) r(k, c) = row[c];
  }
  return a;
}

Array navToArray(const NavSeries& nav) {
  Array a = newArray(nav.size(), navColumns().size());
  double* d = a.mutable_data();
  for (std::size_t k = 0; k < nav.size(); ++k) fillNavRow(nav[k], d + 11 * k);
  return a;
}

ImuSeries imuFromArray(const Array& a, double nominal_rate_hz, const std::string& name) {
  const auto r = checkedRows(a, imuColumns(), name);
  ImuSeries imu(r.shape(0));
  for (py::ssize_t k = 0; k < r.shape(0); ++k) {
    requireFinite(r, k, {0, 2, 3, 4, 5, 6, 7}, imuColumns(), name);
    requireIncreasing(r, k, 0, name);
    ImuSample& s = imu[k];
    s.t_s = r(k, 0);
    if (std::isnan(r(k, 1))) {
      if (k == 0 && !(nominal_rate_hz > 0.0))
        throw std::invalid_argument(name + ": no dt_s and no IMU rate for the first sample");
      s.dt_s = k == 0 ? 1.0 / nominal_rate_hz : r(k, 0) - r(k - 1, 0);
    } else {
      requireFinite(r, k, {1}, imuColumns(), name);
      s.dt_s = r(k, 1);
    }
    s.dtheta_rad = {r(k, 2), r(k, 3), r(k, 4)};
    s.dvel_m_s = {r(k, 5), r(k, 6), r(k, 7)};
    s.temperature_degC = r(k, 8);
  }
  return imu;
}

GnssSeries gnssFromArray(const Array& a, const std::string& name) {
  const auto r = checkedRows(a, gnssColumns(), name);
  GnssSeries gnss(r.shape(0));
  for (py::ssize_t k = 0; k < r.shape(0); ++k) {
    requireFinite(r, k, {0, 1, 2, 3, 4, 5, 6}, gnssColumns(), name);
    requireIncreasing(r, k, 0, name);
    GnssFix& f = gnss[k];
    f.t_s = r(k, 0);
    f.pos = Geodetic{r(k, 1) * units::kDegToRad, r(k, 2) * units::kDegToRad, r(k, 3)};
    f.std_ned_m = {r(k, 4), r(k, 5), r(k, 6)};
    f.fix_type = std::isfinite(r(k, 7)) ? static_cast<int>(r(k, 7)) : 0;
    f.num_sv = std::isfinite(r(k, 8)) ? static_cast<int>(r(k, 8)) : 0;
  }
  return gnss;
}

NavSeries navFromArray(const Array& a, const std::string& name) {
  const auto r = checkedRows(a, navColumns(), name);
  NavSeries nav(r.shape(0));
  for (py::ssize_t k = 0; k < r.shape(0); ++k) {
    requireFinite(r, k, {1, 2, 3, 4, 5, 6, 7, 8, 9, 10}, navColumns(), name);
    requireIncreasing(r, k, 1, name);
    NavState& s = nav[k];
    s.gnss_week = std::isfinite(r(k, 0)) ? static_cast<int>(r(k, 0)) : 0;
    s.t_s = r(k, 1);
    s.pos = Geodetic{r(k, 2) * units::kDegToRad, r(k, 3) * units::kDegToRad, r(k, 4)};
    s.v_n = {r(k, 5), r(k, 6), r(k, 7)};
    s.q_nb = quatFromEuler(Eigen::Vector3d(r(k, 8), r(k, 9), r(k, 10)) * units::kDegToRad);
  }
  return nav;
}

std::vector<std::size_t> decimatedRows(const NavSeries& states, double rate_hz) {
  std::vector<std::size_t> rows;
  rows.reserve(rate_hz > 0.0 ? 0 : states.size());
  double last = -1e300;
  const double interval = rate_hz > 0.0 ? 1.0 / rate_hz : 0.0;
  for (std::size_t k = 0; k < states.size(); ++k) {
    if (states[k].t_s - last < interval - 1e-9) continue;
    last = states[k].t_s;
    rows.push_back(k);
  }
  return rows;
}

Array solutionToArray(const NavSolution& sol, const std::vector<std::size_t>& rows) {
  // An estimator without covariance fills NaN: no sigma columns then.
  const bool with_sigma =
      sol.sigma.size() == sol.states.size() && !sol.states.empty() && sol.sigma.front().allFinite();
  const std::size_t cols = navColumns().size() + (with_sigma ? sigmaColumns().size() : 0);
  Array a = newArray(rows.size(), cols);
  double* d = a.mutable_data();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    double* v = d + cols * i;
    fillNavRow(sol.states[rows[i]], v);
    if (!with_sigma) continue;
    const PvaSigma& s = sol.sigma[rows[i]];
    for (int j = 0; j < 9; ++j) v[11 + j] = j < 6 ? s[j] : s[j] * units::kRadToDeg;
  }
  return a;
}

Array imuErrorsToArray(const NavSolution& sol, const std::vector<std::size_t>& rows) {
  const std::size_t n = sol.states.size();
  const bool biases = n > 0 && sol.gyro_bias_rad_s.size() == n && sol.accel_bias_m_s2.size() == n;
  const bool scales = n > 0 && sol.gyro_scale.size() == n && sol.accel_scale.size() == n;
  if (!biases) return newArray(0, imuErrorColumns().size());
  Array a = newArray(rows.size(), imuErrorColumns().size());
  auto r = a.mutable_unchecked<2>();
  const double nan = std::nan("");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::size_t k = rows[i];
    r(i, 0) = sol.states[k].t_s;
    for (int j = 0; j < 3; ++j) {
      r(i, 1 + j) = sol.gyro_bias_rad_s[k][j] / units::kDegPerHourToRadPerSec;
      r(i, 4 + j) = sol.accel_bias_m_s2[k][j] * kMilliGalPerMPerSec2;
      r(i, 7 + j) = scales ? sol.gyro_scale[k][j] * kPpmPerFraction : nan;
      r(i, 10 + j) = scales ? sol.accel_scale[k][j] * kPpmPerFraction : nan;
    }
  }
  return a;
}

}  // namespace graftnav::python
