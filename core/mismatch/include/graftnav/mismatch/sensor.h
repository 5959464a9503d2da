#pragma once
// The two sensor triads of an IMU as a type, and a value per triad. The finder's channels are
// [gyro x, y, z, accel x, y, z]: a sensor's first channel is 3 * index(sensor).

#include <array>
#include <cstddef>
#include <string>

namespace graftnav {

enum class Sensor { gyro = 0, accel = 1 };

inline constexpr std::array<Sensor, 2> kSensors{Sensor::gyro, Sensor::accel};

constexpr std::size_t index(Sensor s) { return static_cast<std::size_t>(s); }
// First channel of the sensor in a 6-channel residual (0 or 3).
constexpr int firstChannel(Sensor s) { return 3 * static_cast<int>(s); }
constexpr Sensor otherSensor(Sensor s) { return s == Sensor::gyro ? Sensor::accel : Sensor::gyro; }

// The name used in diagnosis.json and in CandidateTerm::sensor ("gyro", "accel").
const char* sensorName(Sensor s);
// The sensor of a single-sensor name; throws std::invalid_argument naming it for any other
// ("both", unknown).
Sensor sensorNamed(const std::string& name);

// One value per sensor triad, indexed by Sensor.
template <class T>
struct PerSensor {
  std::array<T, 2> values{};
  T& operator[](Sensor s) { return values[index(s)]; }
  const T& operator[](Sensor s) const { return values[index(s)]; }
};

}  // namespace graftnav
