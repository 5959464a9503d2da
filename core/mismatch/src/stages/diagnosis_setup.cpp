#include "graftnav/mismatch/diagnosis_setup.h"

#include <fmt/core.h>

#include <algorithm>
#include <functional>
#include <optional>
#include <stdexcept>
#include <utility>

#include "graftnav/calibration/lab_calibration.h"
#include "graftnav/io/imu_recording.h"
#include "graftnav/nav/units.h"
#include "graftnav/sg/graft_case.h"
#include "graftnav/sg/grafting.h"

namespace graftnav {

SensorPriors labPriors(const SensorCalibration& cal) {
  SensorPriors p;
  p.lab_M_sigma = cal.M_sigma;
  p.lab_M = cal.M;
  if (cal.has_allan)
    p.lab_noise = LabNoiseFigures{cal.allan.bias_instability, cal.allan.rate_random_walk};
  if (!cal.has_fit) return p;
  LabQuadratic q;
  for (int a = 0; a < 3; ++a) {
    const PolynomialFit& fit = cal.fit[a];
    if (fit.degree >= 2 && fit.coeffs.size() >= 3) {
      q.c2(a) = fit.coeffs[2];
      q.c2_sigma(a) = fit.coeffs_sigma.size() >= 3 ? fit.coeffs_sigma[2] : 0.0;
    }
    q.c2_tested(a) = fit.c2_tested;
    q.c2_tested_sigma(a) = fit.c2_tested_sigma;
    q.slope_per_abs(a) = fit.slope_per_abs;
    q.slope_per_sq(a) = fit.slope_per_sq;
    q.c2_tested_per_abs(a) = fit.c2_tested_per_abs;
  }
  p.lab_quadratic = q;
  return p;
}

namespace {

// What SG#2 takes from the lab: the graft plan, the lab record's temperature tiled as the
// graft tiles its errors (when every sample has one), and the priors the finder takes from the
// calibration. The calibration report itself (its error signal as long as the lab record) and
// the lab's static record are gone when this returns.
struct LabSimulation {
  GraftPlan plan;
  std::optional<BasicErrorSignal> lab_temperature;
  PerSensor<SensorPriors> priors;
};

// The lab static record's temperature as a tiled signal (its first channel), or nothing.
std::optional<BasicErrorSignal> labTemperatureSignal(const ImuSeries& lab_static) {
  if (lab_static.empty() || !std::all_of(lab_static.begin(), lab_static.end(),
                                         [](const ImuSample& s) { return s.hasTemperature(); }))
    return std::nullopt;
  ImuSeries temp = lab_static;
  for (ImuSample& s : temp) {
    s.dtheta_rad = Eigen::Vector3d(s.temperature_degC * s.dt_s, 0.0, 0.0);
    s.dvel_m_s.setZero();
  }
  return BasicErrorSignal(temp);
}

// Each SG#2 sample's temperature from the tiled lab temperature; t0_s: the start of the whole
// record's first interval (the tiling clock's origin).
void attachTiledTemperature(const BasicErrorSignal& tiled, double start_offset_s, double t0_s,
                            ImuSeries* sg2) {
  const double t0 = t0_s;
  for (ImuSample& s : *sg2) {
    const double u1 = s.t_s - t0 + start_offset_s;
    s.temperature_degC = tiled.integral(u1 - s.dt_s, u1)(0) / s.dt_s;
  }
}

LabSimulation labSimulation(LabData* lab) {
  const LabCalibrationReport report = calibrateLab(*lab);
  std::optional<BasicErrorSignal> temperature = labTemperatureSignal(lab->static_imu);
  ImuSeries().swap(lab->static_imu);  // read by the calibration; the graft tiles its errors
  LabSimulation out{makeGraftPlan(report), std::move(temperature), {}};
  out.priors[Sensor::gyro] = labPriors(report.result.gyro);
  out.priors[Sensor::accel] = labPriors(report.result.accel);
  return out;
}

// SG#2 of `reference`: graftCase's tiling and SG#2 without its SG#1, and the tiled lab
// temperature. Sets *start_offset_s_out and *record_s_out when given.
ImuSeries sg2FromPlan(const LabSimulation& sim, const ImuSeries& reference, double start_offset_s,
                      double* start_offset_s_out = nullptr, double* record_s_out = nullptr) {
  const GraftPlan& plan = sim.plan;
  if (reference.empty())
    throw std::invalid_argument("simulateFromLab: the reference IMU series is empty");
  GraftOptions graft;
  graft.start_offset_s = start_offset_s;
  graft.start_offset_s = graftStartOffset(graft, plan.basic);
  ImuSeries sg2 = graftSeries(reference, plan, SgStrategy::kFull, graft);
  if (sim.lab_temperature && !sg2.empty())
    attachTiledTemperature(*sim.lab_temperature, graft.start_offset_s,
                           sg2.front().t_s - sg2.front().dt_s, &sg2);
  if (start_offset_s_out) *start_offset_s_out = graft.start_offset_s;
  if (record_s_out) *record_s_out = plan.basic.recordLength_s();
  return sg2;
}

// SG#2 of `reference` as sg2FromPlan makes it, grafted block by block into an unlinked spool that
// each pass of the returned recording reads back; sets in's graft tiling.
ImuRecording spooledSg2(const LabSimulation& sim, const ImuSeries& reference, double start_offset_s,
                        DiagnosisInputs* in) {
  if (reference.empty())
    throw std::invalid_argument("simulateFromLab: the reference IMU series is empty");
  GraftOptions graft;
  graft.start_offset_s = start_offset_s;
  graft.start_offset_s = graftStartOffset(graft, sim.plan.basic);
  in->graft_start_offset_s = graft.start_offset_s;
  in->graft_static_record_s = sim.plan.basic.recordLength_s();
  const GraftSignal signal(sim.plan.basic, graft);
  const double t0 = reference.front().t_s - reference.front().dt_s;
  return spooledRecording([&](const ImuBlockFn& block) {
    constexpr std::size_t kBlock = 4096;
    ImuSeries part, sg2;
    for (std::size_t i = 0; i < reference.size(); i += kBlock) {
      part.assign(reference.begin() + i,
                  reference.begin() + std::min(reference.size(), i + kBlock));
      signal.graft(part, t0, &sim.plan.gyro_fit, &sim.plan.accel_fit, &sg2);
      if (sim.lab_temperature)
        attachTiledTemperature(*sim.lab_temperature, graft.start_offset_s, t0, &sg2);
      block(sg2);
    }
  });
}

}  // namespace

void simulateFromLab(LabData lab, double start_offset_s,
                     const PerSensor<double>& reference_scale_std, DiagnosisInputs* in,
                     std::function<LabData()> reload_lab, bool spooled) {
  {
    const LabSimulation sim = labSimulation(&lab);
    if (spooled) {
      in->simulated_recording = spooledSg2(sim, in->reference, start_offset_s, in);
    } else {
      in->simulated = sg2FromPlan(sim, in->reference, start_offset_s, &in->graft_start_offset_s,
                                  &in->graft_static_record_s);
    }
    in->priors = sim.priors;
  }
  // Made again from the lab files, not held: the lab record and its error signal can be as long
  // as the field test.
  if (reload_lab)
    in->remake_simulated = [reload_lab, start_offset_s](const ImuSeries& reference) {
      LabData again = reload_lab();
      return sg2FromPlan(labSimulation(&again), reference, start_offset_s);
    };
  in->simulation_kind = "SG#2 (lab calibration + grafting)";
  for (const Sensor s : kSensors)
    if (reference_scale_std[s] > 0.0) in->priors[s].reference_scale_sigma = reference_scale_std[s];
}

void simulateWithoutLab(DiagnosisInputs* in, std::vector<std::string>* notes,
                        std::vector<std::string>* warnings) {
  try {
    StaticBiasSimulation sim = simulateFromReferenceAndStaticBias(in->reference, in->real);
    in->simulated = std::move(sim.simulated);
    in->remake_simulated = [gyro = sim.gyro_bias_rad_s, accel = sim.accel_bias_m_s2,
                            temp = sim.temperature_degC](const ImuSeries& reference) {
      return withStaticBias(reference, gyro, accel, temp);
    };
    in->simulation_kind = fmt::format(
        "reference IMU + tested IMU static bias (no lab data; bias from the static span "
        "{:.2f}-{:.2f} s: gyro [{:.4f} {:.4f} {:.4f}] deg/s, accel [{:.4f} {:.4f} {:.4f}] m/s^2)",
        sim.t_start_s, sim.t_end_s, sim.gyro_bias_rad_s.x() * units::kRadToDeg,
        sim.gyro_bias_rad_s.y() * units::kRadToDeg, sim.gyro_bias_rad_s.z() * units::kRadToDeg,
        sim.accel_bias_m_s2.x(), sim.accel_bias_m_s2.y(), sim.accel_bias_m_s2.z());
  } catch (const std::runtime_error& e) {
    // A recording that starts moving has no static span: the simulation is the reference alone;
    // the per-channel constant of the model (the nuisance) carries the bias instead.
    in->simulated = in->reference;
    in->remake_simulated = [](const ImuSeries& reference) { return reference; };
    in->simulation_kind = "reference IMU (no lab data, no static span for the tested bias)";
    notes->push_back(std::string("no static span in the tested record (") + e.what() +
                     "): the simulation is the reference IMU alone and the tested bias is the "
                     "fitted constant (constant_bias in diagnosis.json)");
    warnings->push_back(notes->back());
  }
  notes->push_back(
      "the reference IMU's own errors are in the simulation: effects are relative to it");
}

void attachLabTemperature(const ImuSeries& lab_static, double start_offset_s, ImuSeries* sg2) {
  if (sg2->empty()) return;
  if (const auto tiled = labTemperatureSignal(lab_static))
    attachTiledTemperature(*tiled, start_offset_s, sg2->front().t_s - sg2->front().dt_s, sg2);
}

}  // namespace graftnav
