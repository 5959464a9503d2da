#include "solution_outputs.h"

#include <fmt/core.h>

#include <cmath>
#include <stdexcept>

#include "graftnav/io/atomic_file.h"
#include "graftnav/nav/units.h"

namespace graftnav::app {
namespace {

constexpr double kMilliGalPerMPerSec2 = 1e5;
constexpr double kPpmPerFraction = 1e6;

void appendRow(std::string* out, const std::string& path, double t_s, const double* v, int n) {
  *out += fmt::format("{:.4f}", t_s);
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(v[i])) {
      throw std::runtime_error(fmt::format("{}: non-finite value in column {} at t={:.4f}", path, i + 2, t_s));
    }
    *out += fmt::format(" {:.9g}", v[i]);
  }
  *out += '\n';
}

}  // namespace

bool writeImuErrors(const std::string& path, const NavSolution& sol) {
  const size_t n = sol.states.size();
  if (n == 0 || sol.gyro_bias_rad_s.size() != n || sol.accel_bias_m_s2.size() != n ||
      sol.gyro_scale.size() != n || sol.accel_scale.size() != n) {
    return false;
  }
  std::string out =
      "# time_s gyro_bias_x_deg_h gyro_bias_y_deg_h gyro_bias_z_deg_h accel_bias_x_mGal accel_bias_y_mGal "
      "accel_bias_z_mGal gyro_scale_x_ppm gyro_scale_y_ppm gyro_scale_z_ppm accel_scale_x_ppm "
      "accel_scale_y_ppm accel_scale_z_ppm\n";
  for (size_t k = 0; k < n; ++k) {
    double v[12];
    for (int i = 0; i < 3; ++i) {
      v[i] = sol.gyro_bias_rad_s[k][i] / units::kDegPerHourToRadPerSec;
      v[3 + i] = sol.accel_bias_m_s2[k][i] * kMilliGalPerMPerSec2;
      v[6 + i] = sol.gyro_scale[k][i] * kPpmPerFraction;
      v[9 + i] = sol.accel_scale[k][i] * kPpmPerFraction;
    }
    appendRow(&out, path, sol.states[k].t_s, v, 12);
  }
  writeFileAtomically(path, out);
  return true;
}

bool writeStateStd(const std::string& path, const NavSolution& sol) {
  const size_t n = sol.states.size();
  if (n == 0 || sol.sigma.size() != n) return false;
  for (const auto& s : sol.sigma)
    if (!s.allFinite()) return false;  // an estimator without covariance fills NaN
  std::string out =
      "# time_s pos_std_n_m pos_std_e_m pos_std_d_m vel_std_n_m_s vel_std_e_m_s vel_std_d_m_s "
      "att_std_n_deg att_std_e_deg att_std_d_deg\n";
  for (size_t k = 0; k < n; ++k) {
    double v[9];
    for (int i = 0; i < 9; ++i) v[i] = i < 6 ? sol.sigma[k][i] : sol.sigma[k][i] * units::kRadToDeg;
    appendRow(&out, path, sol.states[k].t_s, v, 9);
  }
  writeFileAtomically(path, out);
  return true;
}

}  // namespace graftnav::app
