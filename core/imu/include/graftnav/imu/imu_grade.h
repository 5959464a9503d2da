#pragma once
// An IMU's grade: the class of its gyros and accelerometers. It picks the default plausible ranges
// of the finder (plausible_ranges.h) and the seed's published table an SG report prints beside
// its own (Table 2 for tactical, Table 3 for MEMS).
#include <string>

namespace graftnav {

enum class ImuGrade { kNavigation, kTactical, kMems };

// The word profiles and case.yaml use: "navigation", "tactical" or "mems".
const char* imuGradeName(ImuGrade grade);
// Sets *out from its word; false for any other text.
bool parseImuGrade(const std::string& text, ImuGrade* out);

}  // namespace graftnav
