#include "graftnav/nav/earth.h"

#include <GeographicLib/Constants.hpp>
#include <GeographicLib/Ellipsoid.hpp>
#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/NormalGravity.hpp>
#include <cmath>

#include "graftnav/nav/units.h"

namespace graftnav::earth {
namespace {
const GeographicLib::NormalGravity& normalGravity() {
  return GeographicLib::NormalGravity::WGS84();
}
const GeographicLib::Geocentric& geocentric() { return GeographicLib::Geocentric::WGS84(); }
const GeographicLib::Ellipsoid& ellipsoid() { return GeographicLib::Ellipsoid::WGS84(); }
}  // namespace

double rotationRate_rad_s() { return GeographicLib::Constants::WGS84_omega(); }
double semiMajorAxis_m() { return GeographicLib::Constants::WGS84_a(); }
double flattening() { return GeographicLib::Constants::WGS84_f(); }

Radii radiiOfCurvature(double lat_rad) {
  const double lat_deg = lat_rad * units::kRadToDeg;
  return {ellipsoid().MeridionalCurvatureRadius(lat_deg),
          ellipsoid().TransverseCurvatureRadius(lat_deg)};
}

Eigen::Vector3d gravity_n(const Geodetic& pos) {
  double gamma_north = 0.0, gamma_up = 0.0;
  normalGravity().Gravity(pos.lat_rad * units::kRadToDeg, pos.h_m, gamma_north, gamma_up);
  return {gamma_north, 0.0, -gamma_up};
}

double gravityMagnitude(const Geodetic& pos) { return gravity_n(pos).norm(); }

Eigen::Vector3d omega_ie_n(double lat_rad) {
  const double we = rotationRate_rad_s();
  return {we * std::cos(lat_rad), 0.0, -we * std::sin(lat_rad)};
}

Eigen::Vector3d omega_en_n(const Geodetic& pos, const Eigen::Vector3d& v_n) {
  const Radii r = radiiOfCurvature(pos.lat_rad);
  const double rn_h = r.prime_vertical_m + pos.h_m;
  const double rm_h = r.meridian_m + pos.h_m;
  return {v_n.y() / rn_h, -v_n.x() / rm_h, -v_n.y() * std::tan(pos.lat_rad) / rn_h};
}

Eigen::Vector3d ecefFromGeodetic(const Geodetic& pos) {
  double x, y, z;
  geocentric().Forward(pos.lat_rad * units::kRadToDeg, pos.lon_rad * units::kRadToDeg, pos.h_m, x,
                       y, z);
  return {x, y, z};
}

Geodetic geodeticFromEcef(const Eigen::Vector3d& p_e) {
  double lat, lon, h;
  geocentric().Reverse(p_e.x(), p_e.y(), p_e.z(), lat, lon, h);
  return {lat * units::kDegToRad, lon * units::kDegToRad, h};
}

Eigen::Matrix3d C_en(const Geodetic& pos) {
  const double sl = std::sin(pos.lat_rad), cl = std::cos(pos.lat_rad);
  const double so = std::sin(pos.lon_rad), co = std::cos(pos.lon_rad);
  Eigen::Matrix3d C;
  // Columns: north, east, down unit vectors in ECEF.
  C << -sl * co, -so, -cl * co,  //
      -sl * so, co, -cl * so,    //
      cl, 0.0, -sl;
  return C;
}

Eigen::Vector3d nedFromGeodetic(const Geodetic& origin, const Geodetic& pos) {
  return C_en(origin).transpose() * (ecefFromGeodetic(pos) - ecefFromGeodetic(origin));
}

Geodetic geodeticFromNed(const Geodetic& origin, const Eigen::Vector3d& ned_m) {
  return geodeticFromEcef(ecefFromGeodetic(origin) + C_en(origin) * ned_m);
}

Eigen::Vector3d llhRatePerNed(const Geodetic& pos) {
  const Radii r = radiiOfCurvature(pos.lat_rad);
  return {1.0 / (r.meridian_m + pos.h_m),
          1.0 / ((r.prime_vertical_m + pos.h_m) * std::cos(pos.lat_rad)), -1.0};
}

Geodetic offsetByNed(const Geodetic& pos, const Eigen::Vector3d& dned_m) {
  const Eigen::Vector3d k = llhRatePerNed(pos);
  return {pos.lat_rad + k.x() * dned_m.x(), pos.lon_rad + k.y() * dned_m.y(),
          pos.h_m + k.z() * dned_m.z()};
}

}  // namespace graftnav::earth

namespace graftnav {

Eigen::Vector3d positionErrorNed(const Geodetic& sol, const Geodetic& ref) {
  const earth::Radii r = earth::radiiOfCurvature(ref.lat_rad);
  double dlon = sol.lon_rad - ref.lon_rad;
  if (dlon > M_PI) dlon -= 2.0 * M_PI;
  if (dlon < -M_PI) dlon += 2.0 * M_PI;
  return {(sol.lat_rad - ref.lat_rad) * (r.meridian_m + ref.h_m),
          dlon * (r.prime_vertical_m + ref.h_m) * std::cos(ref.lat_rad), -(sol.h_m - ref.h_m)};
}

}  // namespace graftnav
