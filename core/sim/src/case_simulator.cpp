#include "graftnav/sim/case_simulator.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>

#include "graftnav/io/atomic_file.h"
#include "graftnav/io/case_config.h"
#include "graftnav/imu/gauss_markov.h"
#include "graftnav/io/gnss_io.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/sim/imu_simulator.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/io/odometer_io.h"
#include "graftnav/nav/units.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;

struct FieldTrajectory {
  std::unique_ptr<Trajectory> trj;
  double t_begin = 0.0, t_end = 0.0;
  TrackFitReport fit;
};

FieldTrajectory buildTrajectory(const SimConfig& c) {
  FieldTrajectory f;
  if (c.track) {
    const SimTrackSource& s = *c.track;
    const GnssSeries all = readGnssPos(s.path, GnssReadPolicy::real());
    const double first = all.front().t_s, last = all.back().t_s;
    const double t0 = first + s.start_offset_s;
    const double t1 = s.duration_s > 0.0 ? std::min(t0 + s.duration_s, last) : last;
    if (!(t1 > t0)) {
      throw std::invalid_argument(
          c.source_path + ": trajectory.start_offset_s = " + std::to_string(s.start_offset_s) +
          " is past the end of " + s.path);
    }
    GnssSeries piece;
    for (const auto& fix : all) {
      if (fix.t_s >= t0 - s.margin_s && fix.t_s <= t1 + s.margin_s) piece.push_back(fix);
    }
    auto trj = std::make_unique<TrackTrajectory>(piece, s.smoothing);
    f.fit = trj->report();
    f.t_begin = std::max(t0, trj->startTime_s());
    f.t_end = std::min(t1, trj->endTime_s());
    f.trj = std::move(trj);
  } else {
    auto trj = std::make_unique<ScriptTrajectory>(*c.script);
    f.t_begin = trj->startTime_s();
    f.t_end = trj->endTime_s();
    f.trj = std::move(trj);
  }
  // Keep a whole number of truth intervals (a multiple of the IMU interval), so that the last
  // IMU epoch has a truth epoch.
  const double n = std::floor((f.t_end - f.t_begin) * c.truth_rate_hz + 1e-6);
  f.t_end = f.t_begin + n / c.truth_rate_hz;
  return f;
}

// The tested IMU's files carry the warm-up temperature when the config has one.
ImuSeries withTemperature(const ImuSeries& in, const std::optional<SimTemperature>& temp) {
  if (!temp || in.empty()) return in;
  ImuSeries out = in;
  const double t0 = in.front().t_s - in.front().dt_s;
  for (auto& s : out) s.temperature_degC = temp->at(s.t_s - 0.5 * s.dt_s - t0);
  return out;
}

// True when the field IMUs can be simulated sample by sample and written as they go: no error
// term needs neighbouring samples (lever arm, misalignment, time offset go through
// applyGeometry on a whole series) and the lab does not reuse the field noise stream.
bool fieldImuStreams(const SimConfig& c, const ImuErrorModel& ref, const ImuErrorModel& tested) {
  return !ref.hasGeometry() && !tested.hasGeometry() && !c.lab_common_random_numbers;
}

// The reference and tested field IMUs one sample at a time, each written as it comes: the
// samples, noise streams and bytes of simulateIdealImu + applyErrors + writeImu, with memory
// that does not grow with the recording (an 8 h, 200 Hz case holds no series). Returns the
// sample count.
std::size_t streamFieldImu(const SimConfig& c, const FieldTrajectory& f, const IdealImuOptions& io,
                           const ImuErrorModel& ref_model, const ImuErrorModel& tested_model,
                           const CasePaths& paths,
                           const std::function<void(const std::string&)>& say) {
  io.validate();
  if (!(f.t_end > f.t_begin)) {
    throw std::invalid_argument("simulateIdealImu: empty time span [" + std::to_string(f.t_begin) +
                                ", " + std::to_string(f.t_end) + "]");
  }
  const GaussLegendreRule rule = gaussLegendreRule(io.quadrature_nodes);
  const long n = static_cast<long>(std::floor((f.t_end - f.t_begin) * io.rate_hz + 1e-6));
  ImuWriter ref_out(paths.refImu()), tested_out(paths.testedImu());
  ImuErrorGenerator ref_gen(ref_model, deriveStreamSeed(c.seed, 1));
  ImuErrorGenerator tested_gen(tested_model, deriveStreamSeed(c.seed, 2));
  const long step = std::max(1L, n / 10);
  double t_prev = f.t_begin, temperature_t0 = 0.0;
  for (long k = 1; k <= n; ++k) {
    const double t = f.t_begin + static_cast<double>(k) / io.rate_hz;
    ImuSample s = idealImuSample(*f.trj, t_prev, t, rule, io.lever_arm_b_m);
    t_prev = t;
    ref_out.add(ref_gen.apply(s));
    if (k == 1) temperature_t0 = s.t_s - s.dt_s;  // as withTemperature
    if (c.temperature)
      s.temperature_degC = c.temperature->at(s.t_s - 0.5 * s.dt_s - temperature_t0);
    tested_out.add(tested_gen.apply(s));
    if (k % step == 0) say("field IMUs (streamed) " + std::to_string(100 * k / n) + "%");
  }
  ref_out.commit();
  tested_out.commit();
  return static_cast<std::size_t>(n);
}

void describeModel(YAML::Emitter& out, const ImuErrorModel& m) {
  out << YAML::BeginSeq;
  for (const auto& d : m.describe()) {
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "term" << YAML::Value << d.name << YAML::Key
        << "sensor" << YAML::Value << d.sensor << YAML::Key << "parameters" << YAML::Value
        << d.parameters << YAML::EndMap;
  }
  out << YAML::EndSeq;
}

}  // namespace

namespace {

// The lab records: every lab file goes through ONE error realization, in recording order, so the
// slowly wandering bias (Gauss-Markov) carries on from file to file as it does on a real bench.
// Independent realizations per file gave each of the six poses its own bias, which the
// calibration then mistook for scale and cross-axis errors (0.05 % instead of 0.003 %).
// Returns the number of files written.
std::size_t writeLabRecords(const SimConfig& config, const std::string& case_dir,
                            const ImuErrorModel& tested_model, std::size_t field_samples,
                            uint64_t tested_noise_seed,
                            const std::function<void(const std::string&)>& say) {
  LabSimOptions lab_options = config.lab;
  if (config.lab_common_random_numbers) {
    // Every field sample needs its lab static partner: extend a shorter static record.
    const double field_s = static_cast<double>(field_samples) / config.imu_rate_hz;
    if (lab_options.static_duration_s > 0.0 && lab_options.static_duration_s < field_s) {
      say("lab static record extended from " + std::to_string(lab_options.static_duration_s) +
          " s to the field length " + std::to_string(field_s) + " s (common random numbers)");
      lab_options.static_duration_s = field_s;
    }
  }
  const std::vector<LabSession> lab = simulateLabSessions(lab_options);
  std::vector<ImuSeries> lab_ideal;
  lab_ideal.reserve(lab.size());
  for (const LabSession& l : lab) {
    lab_ideal.push_back(withTemperature(
        l.ideal, config.temperature ? std::optional<SimTemperature>(config.temperature->lab())
                                    : std::nullopt));
  }
  // Lab: the same sensor without the field-mounting geometry (relative to the reference IMU).
  // One noise stream through the sessions in order; each session is its own record (the pose
  // change between two files is not vibration: ImuErrorGenerator::startRecord).
  uint64_t lab_noise_seed = deriveStreamSeed(config.seed, 100);
  if (config.lab_common_random_numbers) {
    if (lab.empty() || lab.front().relative_path != "lab/static.txt" ||
        lab.front().ideal.size() < field_samples) {
      throw std::invalid_argument(
          config.source_path +
          ": lab.common_random_numbers needs a lab static record (lab.static_duration_s > 0)");
    }
    lab_noise_seed = tested_noise_seed;
  }
  const std::vector<ImuSeries> lab_meas =
      applyErrorsToRecords(lab_ideal, labErrorModel(tested_model), lab_noise_seed);
  for (std::size_t i = 0; i < lab.size(); ++i)
    writeImu((fs::path(case_dir) / lab[i].relative_path).string(), lab_meas[i]);
  return lab.size();
}

void writeSimulatedCaseYaml(const SimConfig& config, const NavState& initial_state,
                            const CasePaths& paths) {
  CaseConfig cc;
  cc.name = config.name;
  cc.imu_rate_hz = config.imu_rate_hz;
  cc.reference_imu = config.reference_imu.profile;
  cc.reference_imu_noise_given = true;
  cc.tested_imu = config.tested_imu.profile;
  cc.tested_imu_noise_given = true;
  cc.lever_arm_m = config.gnss.lever_arm_b_m;
  cc.gnss_week = config.gnss_week;
  cc.initial_state = initial_state;
  LabConfig lc;
  lc.latitude_rad = config.lab.latitude_rad;
  lc.height_m = config.lab.height_m;
  lc.static_euler_rad = config.lab.static_euler_rad;
  lc.six_position_euler_rad = sixPositionPoses();
  lc.rate_table_axis_up = true;
  lc.tilt_euler_rad = config.lab.tilt_euler_rad;
  cc.lab = lc;
  saveCaseConfig(paths.caseYaml(), cc);
}

// What was simulated, for checking estimates against the truth (not part of dataset.md).
void writeSimulationYaml(const SimConfig& config, const std::string& case_dir, double field_begin_s,
                         double field_end_s, const ImuErrorModel& ref_model,
                         const ImuErrorModel& tested_model) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "config" << YAML::Value << config.source_path;
  out << YAML::Key << "seed" << YAML::Value << config.seed;
  out << YAML::Key << "ideal" << YAML::Value << config.ideal;
  out << YAML::Key << "field_begin_s" << YAML::Value << field_begin_s;
  out << YAML::Key << "field_end_s" << YAML::Value << field_end_s;
  out << YAML::Key << "truth_rate_hz" << YAML::Value << config.truth_rate_hz;
  out << YAML::Key << "reference_imu_errors" << YAML::Value;
  describeModel(out, ref_model);
  out << YAML::Key << "tested_imu_errors" << YAML::Value;
  describeModel(out, tested_model);
  if (config.odometer) {
    const OdometerSimOptions& o = *config.odometer;
    out << YAML::Key << "odometer" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "scale_error_ppm" << YAML::Value << o.scale_error * 1e6;
    out << YAML::Key << "noise_std_m_s" << YAML::Value << o.noise_std_m_s;
    out << YAML::Key << "rate_hz" << YAML::Value << o.rate_hz;
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  writeFileAtomically((fs::path(case_dir) / "simulation.yaml").string(),
                      std::string(out.c_str()) + "\n");
}

}  // namespace

CaseSimSummary simulateCase(const SimConfig& config, const std::string& case_dir,
                            const std::function<void(const std::string&)>& progress) {
  config.validate();
  auto say = [&](const std::string& m) {
    if (progress) progress(m);
  };
  const CasePaths paths(case_dir);
  for (const char* d : {"field", "lab/six_position", "lab/rate", "lab/tilt"}) {
    fs::create_directories(fs::path(case_dir) / d);
  }
  const uint64_t seed = config.seed;
  CaseSimSummary sum;

  say("trajectory");
  FieldTrajectory f = buildTrajectory(config);
  sum.t_begin_s = f.t_begin;
  sum.t_end_s = f.t_end;
  sum.track_fit = f.fit;

  IdealImuOptions io;
  io.rate_hz = config.imu_rate_hz;
  io.quadrature_nodes = config.quadrature_nodes;
  const ImuErrorModel ref_model =
      buildSimErrorModel(config.reference_imu, deriveStreamSeed(seed, 4), config.ideal);
  const ImuErrorModel tested_model =
      buildSimErrorModel(config.tested_imu, deriveStreamSeed(seed, 3), config.ideal);
  const bool stream = fieldImuStreams(config, ref_model, tested_model);
  ImuSeries ideal;  // held only when the field IMUs are not streamed
  if (stream) {
    sum.imu_samples = streamFieldImu(config, f, io, ref_model, tested_model, paths, say);
  } else {
    int last_pct = -10;
    ideal = simulateIdealImu(*f.trj, f.t_begin, f.t_end, io, [&](double x) {
      const int pct = static_cast<int>(x * 100.0);
      if (pct >= last_pct + 10) {
        last_pct = pct;
        say("field ideal IMU " + std::to_string(pct) + "%");
      }
    });
    sum.imu_samples = ideal.size();
  }

  say("truth");
  const NavSeries truth =
      sampleTruth(*f.trj, f.t_begin, f.t_end, config.truth_rate_hz, config.gnss_week);
  writeNav(paths.truthNav(), truth);
  sum.truth_epochs = truth.size();
  for (std::size_t k = 1; k < truth.size(); ++k) {
    sum.path_length_m += earth::nedFromGeodetic(truth[k - 1].pos, truth[k].pos).norm();
  }

  // The tested IMU's own motion is integrated from the trajectory, exactly: with late tags (tau)
  // over the shifted intervals, and at its lever arm from the reference IMU with the
  // instantaneous rates at the sample ends. The error model's versions work on the increment
  // series (interpolated shift, 5-point node rates): exact for smooth motion but on road
  // vibration (8-40 Hz at 100 Hz sampling) the shift lost 8 % (read by the finder as a scale
  // factor) and the lever arm's tangential term most of its 30-40 Hz part (r_m 2-5 % short on
  // random cases). The rest of the model (misalignment, sensor errors) applies unchanged.
  ImuSeries tested_ideal;
  ImuErrorModel tested_field_model = tested_model;
  if (!stream && (tested_model.time_offset.isActive() || tested_model.lever_arm.isActive())) {
    const double tau = tested_model.time_offset.tau_s;
    IdealImuOptions tested_io = io;
    tested_io.lever_arm_b_m = tested_model.lever_arm.r_m;
    say("tested IMU ideal increments at its lever arm and time offset");
    tested_ideal = simulateIdealImu(*f.trj, f.t_begin - tau, f.t_end - tau, tested_io);
    for (ImuSample& smp : tested_ideal) smp.t_s += tau;
    tested_field_model.time_offset = TimeOffset{};
    tested_field_model.lever_arm = LeverArm{};
  }

  if (!stream) {
    say("reference IMU");
    writeImu(paths.refImu(), applyErrors(ideal, ref_model, deriveStreamSeed(seed, 1)));
    say("tested IMU");
    writeImu(paths.testedImu(),
             applyErrors(
                 withTemperature(tested_ideal.empty() ? ideal : tested_ideal, config.temperature),
                 tested_field_model, deriveStreamSeed(seed, 2)));
    tested_ideal = {};
    ideal = {};
  }
  const uint64_t tested_noise_seed = deriveStreamSeed(seed, 2);

  say("GNSS");
  GnssSimOptions gopt = config.gnss;
  gopt.add_noise = !config.ideal;
  const GnssSeries gnss = simulateGnss(*f.trj, f.t_begin, f.t_end, gopt, deriveStreamSeed(seed, 5));
  writeGnssPos(paths.gnssPos(), gnss);
  sum.gnss_fixes = gnss.size();

  if (config.odometer) {
    say("odometer");
    OdometerSimOptions oopt = *config.odometer;
    oopt.add_noise = !config.ideal;
    writeOdometer(paths.odometer(),
                  simulateOdometer(*f.trj, f.t_begin, f.t_end, oopt, deriveStreamSeed(seed, 6)));
  }

  say("lab sessions");
  sum.lab_files =
      writeLabRecords(config, case_dir, tested_model, sum.imu_samples, tested_noise_seed, say);
  say("case.yaml");
  writeSimulatedCaseYaml(config, truth.front(), paths);
  writeSimulationYaml(config, case_dir, f.t_begin, f.t_end, ref_model, tested_model);
  say("done");
  return sum;
}

}  // namespace graftnav
