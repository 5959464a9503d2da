#include "graftnav/estimation/ekf_options.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace graftnav {
namespace {

void requirePositive(double v, const char* name) {
  if (!(v > 0.0) || !std::isfinite(v)) {
    throw std::invalid_argument(std::string("EkfOptions: ") + name + " must be > 0, got " +
                                std::to_string(v));
  }
}

}  // namespace

void EkfOptions::validate() const {
  requirePositive(covariance_interval_s, "covariance_interval_s");
  requirePositive(record_interval_s, "record_interval_s");
  requirePositive(gnss_std_scale, "gnss_std_scale");
  requirePositive(gnss_std_floor_m, "gnss_std_floor_m");
  requirePositive(gnss_default_std_m, "gnss_default_std_m");
  requirePositive(init_pos_std_m, "init_pos_std_m");
  requirePositive(init_vel_std_m_s, "init_vel_std_m_s");
  requirePositive(init_roll_pitch_std_rad, "init_roll_pitch_std_rad");
  requirePositive(init_heading_std_rad, "init_heading_std_rad");
  if (max_consecutive_rejections < 0) {
    throw std::invalid_argument("EkfOptions: max_consecutive_rejections must be >= 0, got " +
                                std::to_string(max_consecutive_rejections));
  }
  if (output_decimation < 1) {
    throw std::invalid_argument("EkfOptions: output_decimation must be >= 1, got " +
                                std::to_string(output_decimation));
  }
}

}  // namespace graftnav
