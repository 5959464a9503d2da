#pragma once
// The two sensor triads of an IMU as a type, what a term acts on (one triad or both), and a value
// per triad. The finder's channels are [gyro x, y, z, accel x, y, z]: a sensor's first channel is
// 3 * index(sensor). Files and diagnosis.json name them through sensorName / scopeName only.

#include <array>
#include <cstddef>

namespace graftnav {

enum class Sensor { gyro = 0, accel = 1 };

// What a candidate term or an effect acts on: one triad, or both (time offset, mounting rotation).
enum class SensorScope { gyro = 0, accel = 1, both = 2 };

inline constexpr std::array<Sensor, 2> kSensors{Sensor::gyro, Sensor::accel};

constexpr std::size_t index(Sensor s) { return static_cast<std::size_t>(s); }
constexpr std::size_t index(SensorScope s) { return static_cast<std::size_t>(s); }
// First channel of the sensor in a 6-channel residual (0 or 3).
constexpr int firstChannel(Sensor s) { return 3 * static_cast<int>(s); }
constexpr Sensor otherSensor(Sensor s) { return s == Sensor::gyro ? Sensor::accel : Sensor::gyro; }
constexpr SensorScope scopeOf(Sensor s) { return static_cast<SensorScope>(s); }
constexpr bool isSingleSensor(SensorScope s) { return s != SensorScope::both; }
// The triad of a single-sensor scope; throws std::invalid_argument for SensorScope::both.
Sensor sensorOf(SensorScope s);

// The name table: "gyro", "accel" (and "both" for a scope), as diagnosis.json writes them.
const char* sensorName(Sensor s);
const char* scopeName(SensorScope s);
// The triad in prose: "gyro", "accelerometer".
const char* sensorNoun(Sensor s);

// One value per sensor triad, indexed by Sensor.
template <class T>
struct PerSensor {
  std::array<T, 2> values{};
  T& operator[](Sensor s) { return values[index(s)]; }
  const T& operator[](Sensor s) const { return values[index(s)]; }
};

}  // namespace graftnav
