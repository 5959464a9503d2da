#include "graftnav/case/aiding_config.h"

#include <stdexcept>

#include "graftnav/nav/units.h"

namespace graftnav {
namespace {

namespace yf = yaml_fields;

// A scalar (the first component, the others zero) or a list of `n` numbers.
Eigen::VectorXd scalarOrList(const yf::Context& ctx, const YAML::Node& v, const std::string& key,
                             int n) {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(n);
  if (v.IsSequence()) {
    const std::vector<double> list = yf::asDoubleList(ctx, v, key, n);
    for (int i = 0; i < n; ++i) out(i) = list[static_cast<std::size_t>(i)];
  } else {
    out(0) = yf::asDouble(ctx, v, key);
  }
  return out;
}

}  // namespace

const std::vector<std::string>& odometerSectionKeys() {
  static const std::vector<std::string> keys = {
      "enabled",     "std_m_s",      "scale_std_ppm", "scale_random_walk_ppm_sqrt_s",
      "lever_arm_m", "mounting_deg", "rate_hz",       "max_gap_s",
      "forward_only"};
  return keys;
}

const std::vector<std::string>& nhcSectionKeys() {
  static const std::vector<std::string> keys = {"enabled", "std_m_s", "rate_hz"};
  return keys;
}

void parseOdometerSection(const yf::Context& ctx, const YAML::Node& s, AidingConfig* c) {
  OdometerOptions& o = c->options.odometer;
  yf::readOptional(ctx, s, "odometer", "enabled", &o.enabled);
  if (const YAML::Node v = s["std_m_s"]) {
    const Eigen::VectorXd std = scalarOrList(ctx, v, "odometer.std_m_s", 3);
    o.std_m_s = std.head<3>();
    if (!(o.std_m_s.x() > 0.0) || (v.IsSequence() && !(o.std_m_s.minCoeff() > 0.0)))
      yf::fail(ctx, v, "odometer.std_m_s", "must be > 0 m/s");
  }
  double ppm = o.scale_std / units::kPpmToFraction;
  if (yf::readOptional(ctx, s, "odometer", "scale_std_ppm", &ppm)) {
    if (!(ppm >= 0.0) || ppm >= 5e5)
      yf::fail(ctx, s["scale_std_ppm"], "odometer.scale_std_ppm", "must be in [0, 500000) ppm");
    o.scale_std = ppm * units::kPpmToFraction;
  }
  double rw = o.scale_random_walk_per_sqrt_s / units::kPpmToFraction;
  if (yf::readOptional(ctx, s, "odometer", "scale_random_walk_ppm_sqrt_s", &rw)) {
    if (!(rw >= 0.0))
      yf::fail(ctx, s["scale_random_walk_ppm_sqrt_s"], "odometer.scale_random_walk_ppm_sqrt_s",
               "must be >= 0");
    o.scale_random_walk_per_sqrt_s = rw * units::kPpmToFraction;
  }
  if (const YAML::Node v = s["lever_arm_m"])
    o.lever_arm_b_m = yf::asVector3(ctx, v, "odometer.lever_arm_m");
  if (const YAML::Node v = s["mounting_deg"])
    o.mounting_rad = yf::asVector3(ctx, v, "odometer.mounting_deg") * units::kDegToRad;
  yf::readOptional(ctx, s, "odometer", "rate_hz", &o.rate_hz);
  yf::readOptional(ctx, s, "odometer", "max_gap_s", &o.max_gap_s);
  yf::readOptional(ctx, s, "odometer", "forward_only", &c->odometer_read.forward_only);
  yf::warnUnknownKeys(ctx, s, "odometer", odometerSectionKeys());
}

void parseNhcSection(const yf::Context& ctx, const YAML::Node& s, AidingConfig* c) {
  NhcOptions& n = c->options.nhc;
  yf::readOptional(ctx, s, "nhc", "enabled", &n.enabled);
  if (const YAML::Node v = s["std_m_s"]) {
    const Eigen::VectorXd std = scalarOrList(ctx, v, "nhc.std_m_s", 2);
    n.std_m_s = v.IsSequence() ? Eigen::Vector2d(std(0), std(1)) : Eigen::Vector2d(std(0), std(0));
    if (!(n.std_m_s.minCoeff() > 0.0)) yf::fail(ctx, v, "nhc.std_m_s", "must be > 0 m/s");
  }
  yf::readOptional(ctx, s, "nhc", "rate_hz", &n.rate_hz);
  yf::warnUnknownKeys(ctx, s, "nhc", nhcSectionKeys());
}

void validateAidingConfig(const yf::Context& ctx, const AidingConfig& c) {
  try {
    c.options.validate();
    c.odometer_read.validate();
  } catch (const std::invalid_argument& ex) {
    throw std::runtime_error(ctx.path + ": " + ex.what());
  }
}

}  // namespace graftnav
