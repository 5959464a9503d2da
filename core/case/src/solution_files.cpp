#include "graftnav/case/solution_files.h"

#include <fmt/core.h>

#include <cmath>
#include <stdexcept>

#include "graftnav/io/atomic_file.h"
#include "graftnav/nav/units.h"

namespace graftnav {
namespace {

// A file's text is written once it passes kFlushBytes; its buffer's capacity is set once (with a
// few lines more), so that it never doubles as the file grows.
constexpr std::size_t kFlushBytes = std::size_t{1} << 18;
constexpr std::size_t kBufferBytes = kFlushBytes + 1024;
constexpr double kMilliGalPerMPerSec2 = 1e5;
constexpr double kPpmPerFraction = 1e6;

void appendRow(std::string* out, const std::string& path, double t_s, const double* v, int n) {
  *out += fmt::format("{:.4f}", t_s);
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(v[i])) {
      throw std::runtime_error(
          fmt::format("{}: non-finite value in column {} at t={:.4f}", path, i + 2, t_s));
    }
    *out += fmt::format(" {:.9g}", v[i]);
  }
  *out += '\n';
}

constexpr const char* kImuErrorsHeader =
    "# time_s gyro_bias_x_deg_h gyro_bias_y_deg_h gyro_bias_z_deg_h accel_bias_x_mGal accel_bias_y_mGal "
    "accel_bias_z_mGal gyro_scale_x_ppm gyro_scale_y_ppm gyro_scale_z_ppm accel_scale_x_ppm "
    "accel_scale_y_ppm accel_scale_z_ppm\n";
constexpr const char* kStateStdHeader =
    "# time_s pos_std_n_m pos_std_e_m pos_std_d_m vel_std_n_m_s vel_std_e_m_s vel_std_d_m_s "
    "att_std_n_deg att_std_e_deg att_std_d_deg\n";

constexpr const char* kOdometerScaleHeader = "# time_s odometer_scale_ppm odometer_scale_std_ppm\n";
constexpr const char* kOdometerScaleHeaderNoStd = "# time_s odometer_scale_ppm\n";

void appendOdometerScaleRow(std::string* out, const std::string& path, double t_s,
                            const OdometerScaleEstimate& k, bool with_std) {
  const double v[2] = {k.scale * kPpmPerFraction, k.std * kPpmPerFraction};
  appendRow(out, path, t_s, v, with_std ? 2 : 1);
}

// One row of each file (shared by the in-memory writers and the streamed sink).
void appendImuErrorsRow(std::string* out, const std::string& path, double t_s,
                        const ImuErrorEstimate& e) {
  double v[12];
  for (int i = 0; i < 3; ++i) {
    v[i] = e.gyro_bias_rad_s[i] / units::kDegPerHourToRadPerSec;
    v[3 + i] = e.accel_bias_m_s2[i] * kMilliGalPerMPerSec2;
    v[6 + i] = e.gyro_scale[i] * kPpmPerFraction;
    v[9 + i] = e.accel_scale[i] * kPpmPerFraction;
  }
  appendRow(out, path, t_s, v, 12);
}

void appendStateStdRow(std::string* out, const std::string& path, double t_s,
                       const PvaSigma& sigma) {
  double v[9];
  for (int i = 0; i < 9; ++i) v[i] = i < 6 ? sigma[i] : sigma[i] * units::kRadToDeg;
  appendRow(out, path, t_s, v, 9);
}

}  // namespace

bool writeImuErrors(const std::string& path, const NavSolution& sol) {
  const size_t n = sol.states.size();
  if (n == 0 || sol.gyro_bias_rad_s.size() != n || sol.accel_bias_m_s2.size() != n ||
      sol.gyro_scale.size() != n || sol.accel_scale.size() != n) {
    return false;
  }
  std::string out = kImuErrorsHeader;
  for (size_t k = 0; k < n; ++k) {
    ImuErrorEstimate e;
    e.gyro_bias_rad_s = sol.gyro_bias_rad_s[k];
    e.accel_bias_m_s2 = sol.accel_bias_m_s2[k];
    e.gyro_scale = sol.gyro_scale[k];
    e.accel_scale = sol.accel_scale[k];
    appendImuErrorsRow(&out, path, sol.states[k].t_s, e);
  }
  writeFileAtomically(path, out);
  return true;
}

bool writeStateStd(const std::string& path, const NavSolution& sol) {
  const size_t n = sol.states.size();
  if (n == 0 || sol.sigma.size() != n) return false;
  for (const auto& s : sol.sigma)
    if (!s.allFinite()) return false;  // an estimator without covariance fills NaN
  std::string out = kStateStdHeader;
  for (size_t k = 0; k < n; ++k) appendStateStdRow(&out, path, sol.states[k].t_s, sol.sigma[k]);
  writeFileAtomically(path, out);
  return true;
}

bool writeOdometerScale(const std::string& path, const NavSolution& sol) {
  const size_t n = sol.states.size();
  if (n == 0 || sol.odometer_scale.size() != n || sol.odometer_scale_std.size() != n) return false;
  bool with_std = true;
  for (double sd : sol.odometer_scale_std) with_std = with_std && std::isfinite(sd);
  std::string out = with_std ? kOdometerScaleHeader : kOdometerScaleHeaderNoStd;
  for (size_t k = 0; k < n; ++k) {
    appendOdometerScaleRow(&out, path, sol.states[k].t_s,
                           {sol.odometer_scale[k], sol.odometer_scale_std[k]}, with_std);
  }
  writeFileAtomically(path, out);
  return true;
}

SolutionOutputsSink::SolutionOutputsSink(const std::string& imu_errors_path,
                                         const std::string& state_std_path, bool with_imu_errors,
                                         const std::string& odometer_scale_path)
    : odometer_scale_path_(odometer_scale_path) {
  if (with_imu_errors) imu_errors_.file = std::make_unique<AtomicFile>(imu_errors_path);
  imu_errors_.buffer = kImuErrorsHeader;
  state_std_.file = std::make_unique<AtomicFile>(state_std_path);
  state_std_.buffer = kStateStdHeader;
  if (imu_errors_.file) imu_errors_.buffer.reserve(kBufferBytes);
  state_std_.buffer.reserve(kBufferBytes);
}

void SolutionOutputsSink::File::flush(bool force) {
  if (!file || (!force && buffer.size() < kFlushBytes)) return;
  file->write(buffer);
  buffer.clear();
}

void SolutionOutputsSink::addOdometerScale(const OdometerScaleEstimate& estimate) {
  pending_scale_ = estimate;
}

void SolutionOutputsSink::add(const NavState& state, const PvaSigma* sigma,
                              const ImuErrorEstimate& sensors) {
  ++epochs_;
  if (pending_scale_ && !odometer_scale_path_.empty()) {
    if (!odometer_scale_.file) {  // the first epoch decides the columns, as writeOdometerScale
      odometer_scale_.file = std::make_unique<AtomicFile>(odometer_scale_path_);
      scale_with_std_ = std::isfinite(pending_scale_->std);
      odometer_scale_.buffer = scale_with_std_ ? kOdometerScaleHeader : kOdometerScaleHeaderNoStd;
      odometer_scale_.buffer.reserve(kBufferBytes);
    }
    appendOdometerScaleRow(&odometer_scale_.buffer, odometer_scale_path_, state.t_s,
                           *pending_scale_, scale_with_std_);
    odometer_scale_.flush(false);
    ++scale_epochs_;
  }
  pending_scale_.reset();
  if (imu_errors_.file) {
    appendImuErrorsRow(&imu_errors_.buffer, imu_errors_.file->path(), state.t_s, sensors);
    imu_errors_.flush(false);
  }
  if (!state_std_.file) return;
  if (!sigma || !sigma->allFinite()) {  // as writeStateStd: no file (the destructor removes it)
    state_std_.file.reset();
    state_std_.buffer.clear();
    return;
  }
  appendStateStdRow(&state_std_.buffer, state_std_.file->path(), state.t_s, *sigma);
  state_std_.flush(false);
}

void SolutionOutputsSink::commit(bool* imu_errors, bool* state_std, bool* odometer_scale) {
  *imu_errors = epochs_ > 0 && imu_errors_.file;
  *state_std = epochs_ > 0 && state_std_.file;
  // Every epoch has a scale, or the file is not written (as writeOdometerScale).
  const bool scale = scale_epochs_ == epochs_ && epochs_ > 0 && odometer_scale_.file;
  if (odometer_scale) *odometer_scale = scale;
  if (scale) {
    odometer_scale_.flush(true);
    odometer_scale_.file->commit();
  }
  if (*imu_errors) {
    imu_errors_.flush(true);
    imu_errors_.file->commit();
  }
  if (*state_std) {
    state_std_.flush(true);
    state_std_.file->commit();
  }
}

}  // namespace graftnav
