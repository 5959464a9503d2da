#include "graftnav/mismatch/linear_response.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/core.h>

#include "graftnav/mismatch/term_spec.h"
#include "graftnav/nav/units.h"

namespace graftnav {
namespace {

constexpr double kGravity_m_s2 = units::kStandardGravity_m_s2;  // the tilt's gravity projection
constexpr double kRadToDeg = units::kRadToDeg;

// Long-run noise density of a channel's residual (per sqrt(s)): the AR(1) innovation's long-run
// sd sigma / (1 - rho) per bin, times sqrt(bin_s) and sqrt(variance inflation).
double noiseDensity(const SelectionResult& sel, int channel, double bin_s) {
  const double rho = std::min(sel.rho(channel), 0.99);
  return sel.sigma(channel) / (1.0 - rho) * std::sqrt(bin_s * std::max(1.0, sel.inflation));
}

}  // namespace

void LinearResponseOptions::validate() const {
  if (!(excitation_rate_rad_s > 0.0) || !(excitation_tilt_rad > 0.0) ||
      !(excitation_tilt_rad < 1.5707963267948966) || !(resolve_fraction > 0.0))
    throw std::invalid_argument(
        fmt::format("LinearResponseOptions: excitation_rate_rad_s = {}, excitation_tilt_rad = {}, "
                    "resolve_fraction = {}: rate and fraction must be > 0, tilt in (0, pi/2)",
                    excitation_rate_rad_s, excitation_tilt_rad, resolve_fraction));
}

SeparationNeed separationNeed(const BinnedImu& x, const SelectionResult& sel, double bin_s,
                              double bound_rad, const LinearResponseOptions& options) {
  options.validate();
  if (!(bound_rad > 0.0) || !(bin_s > 0.0))
    throw std::invalid_argument(
        fmt::format("separationNeed: bound_rad = {}, bin_s = {} must be > 0", bound_rad, bin_s));
  SeparationNeed need;
  need.bound_rad = bound_rad;
  need.rate_rad_s = options.excitation_rate_rad_s;
  need.tilt_rad = options.excitation_tilt_rad;
  const double sigma_target = options.resolve_fraction * bound_rad;
  double gyro_density = 0.0, accel_density = 0.0;
  for (int c = 0; c < 3; ++c) {
    gyro_density = std::max(gyro_density, noiseDensity(sel, c, bin_s));
    accel_density = std::max(accel_density, noiseDensity(sel, 3 + c, bin_s));
  }
  const double a_rate = options.excitation_rate_rad_s;
  const double a_tilt = kGravity_m_s2 * std::sin(options.excitation_tilt_rad);
  need.separable = true;
  for (int j = 0; j < 2; ++j) {
    const Eigen::VectorXd w = x.omega_rad_s.col(j);
    const double energy = (w.array() - w.mean()).square().sum() * bin_s;  // integral omega_j^2 dt
    need.gyro_present_s(j) = energy / (a_rate * a_rate);
    need.gyro_needed_s(j) = std::pow(gyro_density / (sigma_target * a_rate), 2);
    need.accel_needed_s(j) = std::pow(accel_density / (sigma_target * a_tilt), 2);
    need.separable = need.separable && need.gyro_present_s(j) >= need.gyro_needed_s(j);
  }
  return need;
}

void SeparationNeed::shrinkPresent(double share) {
  information_share = std::clamp(share, 0.0, 1.0);
  gyro_present_s *= information_share;
  separable = (gyro_present_s.array() >= gyro_needed_s.array()).all();
}

std::string SeparationNeed::text() const {
  return fmt::format(
      "to split them each column must be known to a third of the class's non-orthogonality bound "
      "({:.3g} deg): that needs roll- and pitch-rate excitation of {:.3g} s and {:.3g} s at {:.3g} "
      "deg/s RMS (this record holds the equivalent of {:.3g} s and {:.3g} s, {:.1f} % of its "
      "roll and pitch excitation being left by the correlation of the terms), and for the "
      "accelerometers {:.3g} s and {:.3g} s held at {:.3g} deg of roll and of pitch",
      bound_rad * kRadToDeg, gyro_needed_s(0), gyro_needed_s(1), rate_rad_s * kRadToDeg,
      gyro_present_s(0), gyro_present_s(1), 100.0 * information_share, accel_needed_s(0),
      accel_needed_s(1), tilt_rad * kRadToDeg);
}

CandidateTerm linearResponseTerm(const BinnedImu& x) {
  CandidateTerm t(termSpec(TermKind::mounting_scale_nonorthogonality), SensorScope::both);
  t.explanation = "mounting rotation, non-orthogonality and scale factor as one matrix per sensor";
  for (int s = 0; s < 2; ++s) {
    const Eigen::MatrixX3d& in = s == 0 ? x.omega_rad_s : x.f_m_s2;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        RegressorColumn col;
        col.channel[s * 3 + i] = in.col(j);
        t.columns.push_back(col);
      }
  }
  return t;
}

bool isLinearResponseTerm(TermKind kind) {
  return kind == TermKind::mounting_misalignment || kind == TermKind::non_orthogonality ||
         kind == TermKind::scale_factor;
}

}  // namespace graftnav
