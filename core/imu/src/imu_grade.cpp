#include "graftnav/imu/imu_grade.h"

namespace graftnav {

const char* imuGradeName(ImuGrade grade) {
  switch (grade) {
    case ImuGrade::kNavigation:
      return "navigation";
    case ImuGrade::kTactical:
      return "tactical";
    case ImuGrade::kMems:
      return "mems";
  }
  return "mems";
}

bool parseImuGrade(const std::string& text, ImuGrade* out) {
  for (const ImuGrade g : {ImuGrade::kNavigation, ImuGrade::kTactical, ImuGrade::kMems})
    if (text == imuGradeName(g)) {
      *out = g;
      return true;
    }
  return false;
}

}  // namespace graftnav
