#include "graftnav/sg/graft_case.h"

#include <cmath>
#include <stdexcept>

namespace graftnav {

SensorDynamicFit dynamicFitFromCalibration(const SensorCalibration& cal, bool use_cross_axis) {
  SensorDynamicFit fit;
  fit.M = cal.M;
  fit.use_cross_axis = use_cross_axis;
  for (int i = 0; i < 3; ++i) {
    if (cal.has_fit && !cal.fit[i].coeffs.empty()) {
      fit.poly[i] = cal.fit[i].coeffs;
    } else {
      fit.poly[i] = {cal.bias[i], cal.M(i, i)};
    }
  }
  return fit;
}

GraftedCase graftCase(const ImuSeries& ref, const LabCalibrationReport& lab,
                      const GraftCaseOptions& options) {
  if (!lab.has_basic) {
    throw std::invalid_argument(
        "graftCase: the lab session has no static record (lab/static.txt), so there is no basic "
        "error signal to graft");
  }
  if (ref.empty()) throw std::invalid_argument("graftCase: the reference IMU series is empty");
  const BasicErrorSignal basic(lab.basic.error);
  GraftedCase out;
  out.gyro_fit = dynamicFitFromCalibration(lab.result.gyro, options.use_cross_axis);
  out.accel_fit = dynamicFitFromCalibration(lab.result.accel, options.use_cross_axis);
  // The basic error signal holds the dynamic error at the static attitude already.
  out.gyro_fit.static_point = lab.basic.omega_ie_b;
  out.accel_fit.static_point = lab.basic.f_b;
  GraftOptions g = options.graft;
  g.start_offset_s = graftStartOffset(g, basic);
  out.start_offset_s = g.start_offset_s;
  out.static_record_s = basic.recordLength_s();
  const double span = ref.back().t_s - (ref.front().t_s - ref.front().dt_s);
  out.tiles = static_cast<int>(std::ceil((span + g.start_offset_s) / basic.recordLength_s()));
  out.sg1 = graftBasic(ref, basic, g);
  out.sg2 = graftFull(ref, basic, out.gyro_fit, out.accel_fit, g);
  return out;
}

}  // namespace graftnav
