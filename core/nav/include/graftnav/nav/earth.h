#pragma once
// WGS-84 Earth model. All geodesy (normal gravity, radii of curvature, geodetic <-> ECEF and
// local conversions) is delegated to GeographicLib; this header only fixes the frames and units
// graftnav uses (NED, radians, metres) and adds the navigation rates built from them.

#include <Eigen/Core>

namespace graftnav {

// Geodetic position on WGS-84: latitude and longitude in radians, ellipsoidal height in metres.
struct Geodetic {
  double lat_rad = 0.0;
  double lon_rad = 0.0;
  double h_m = 0.0;
};

namespace earth {

// Earth rotation rate of WGS-84 (rad/s), as given by GeographicLib.
double rotationRate_rad_s();
double semiMajorAxis_m();
double flattening();

// Meridian (north-south, R_M) and prime-vertical (east-west, R_N) radii of curvature (m).
struct Radii {
  double meridian_m;
  double prime_vertical_m;
};
Radii radiiOfCurvature(double lat_rad);

// Normal gravity vector (gravitation plus centrifugal) in NED at the given position (m/s^2),
// from GeographicLib::NormalGravity::WGS84(); includes the small northward component at height.
Eigen::Vector3d gravity_n(const Geodetic& pos);
// Magnitude of normal gravity (m/s^2).
double gravityMagnitude(const Geodetic& pos);

// Earth rate in n: omega_ie_n = [w_e cos(lat), 0, -w_e sin(lat)].
Eigen::Vector3d omega_ie_n(double lat_rad);
// Transport rate in n: omega_en_n = [vE/(R_N+h), -vN/(R_M+h), -vE tan(lat)/(R_N+h)].
Eigen::Vector3d omega_en_n(const Geodetic& pos, const Eigen::Vector3d& v_n);

// Geodetic <-> ECEF (m).
Eigen::Vector3d ecefFromGeodetic(const Geodetic& pos);
Geodetic geodeticFromEcef(const Eigen::Vector3d& p_e);
// Rotation from NED at pos to ECEF (C_en).
Eigen::Matrix3d C_en(const Geodetic& pos);

// Local NED offset of pos relative to origin (exact, through ECEF), and its inverse.
Eigen::Vector3d nedFromGeodetic(const Geodetic& origin, const Geodetic& pos);
Geodetic geodeticFromNed(const Geodetic& origin, const Eigen::Vector3d& ned_m);

// Small-offset helpers used by mechanization and filters: d(lat, lon, h)/d(north, east, down)
// at pos (the diagonal of D^-1 in Groves' notation): [1/(R_M+h), 1/((R_N+h) cos lat), -1].
Eigen::Vector3d llhRatePerNed(const Geodetic& pos);
// Moves pos by a small NED displacement (first order in curvature; exact enough below ~100 m).
Geodetic offsetByNed(const Geodetic& pos, const Eigen::Vector3d& dned_m);

}  // namespace earth

// Position error of `sol` relative to `ref` in the local NED frame of `ref` (m), first order.
Eigen::Vector3d positionErrorNed(const Geodetic& sol, const Geodetic& ref);

}  // namespace graftnav
