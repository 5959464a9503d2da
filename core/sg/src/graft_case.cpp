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

const char* sgLabel(SgStrategy s) { return s == SgStrategy::kBasic ? "SG1" : "SG2"; }

GraftPlan makeGraftPlan(const LabCalibrationReport& lab, bool use_cross_axis) {
  if (!lab.has_basic) {
    throw std::invalid_argument(
        "graftCase: the lab session has no static record (lab/static.txt), so there is no basic "
        "error signal to graft");
  }
  GraftPlan plan{BasicErrorSignal(lab.basic.error),
                 dynamicFitFromCalibration(lab.result.gyro, use_cross_axis),
                 dynamicFitFromCalibration(lab.result.accel, use_cross_axis)};
  // The basic error signal holds the dynamic error at the static attitude already.
  plan.gyro_fit.static_point = lab.basic.omega_ie_b;
  plan.accel_fit.static_point = lab.basic.f_b;
  return plan;
}

ImuSeries graftSeries(const ImuSeries& ref, const GraftPlan& plan, SgStrategy strategy,
                      const GraftOptions& options) {
  return strategy == SgStrategy::kBasic
             ? graftBasic(ref, plan.basic, options)
             : graftFull(ref, plan.basic, plan.gyro_fit, plan.accel_fit, options);
}

GraftedCase graftCase(const ImuSeries& ref, const LabCalibrationReport& lab,
                      const GraftCaseOptions& options) {
  const GraftPlan plan = makeGraftPlan(lab, options.use_cross_axis);
  if (ref.empty()) throw std::invalid_argument("graftCase: the reference IMU series is empty");
  GraftedCase out;
  out.gyro_fit = plan.gyro_fit;
  out.accel_fit = plan.accel_fit;
  GraftOptions g = options.graft;
  g.start_offset_s = graftStartOffset(g, plan.basic);
  out.start_offset_s = g.start_offset_s;
  out.static_record_s = plan.basic.recordLength_s();
  const double span = ref.back().t_s - (ref.front().t_s - ref.front().dt_s);
  out.tiles = static_cast<int>(std::ceil((span + g.start_offset_s) / plan.basic.recordLength_s()));
  out.sg1 = graftSeries(ref, plan, SgStrategy::kBasic, g);
  out.sg2 = graftSeries(ref, plan, SgStrategy::kFull, g);
  return out;
}

}  // namespace graftnav
