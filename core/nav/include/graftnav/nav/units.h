#pragma once
// Unit conversions, in one place. Code inside graftnav is SI (rad, m, s, m/s^2); these factors
// are used only where files, configs and reports speak other units, and the name says which.

namespace graftnav::units {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;
constexpr double kRadToDeg = 180.0 / kPi;
constexpr double kStandardGravity_m_s2 = 9.80665;  // the "g" of datasheets (mg, g)

constexpr double kDegPerHourToRadPerSec = kDegToRad / 3600.0;  // deg/h -> rad/s
constexpr double kDegPerSqrtHourToRadPerSqrtSec =
    kDegToRad / 60.0;  // ARW deg/sqrt(h) -> rad/sqrt(s)
constexpr double kMPerSecPerSqrtHourToMPerSecPerSqrtSec =
    1.0 / 60.0;  // VRW m/s/sqrt(h) -> m/s/sqrt(s)
constexpr double kMilliGToMPerSec2 = 1e-3 * kStandardGravity_m_s2;  // mg -> m/s^2
constexpr double kMicroGToMPerSec2 = 1e-6 * kStandardGravity_m_s2;  // ug -> m/s^2
constexpr double kPpmToFraction = 1e-6;
constexpr double kDegPerSecToRadPerSec = kDegToRad;

}  // namespace graftnav::units
