// graftnav calibrate CASE_DIR --out OUT_DIR [--gravity G] [--max-degree N] [--no-plots]
// graftnav calibrate --raw-counts ACC GYRO --out OUT_DIR   (multi-position, imu_tk text files)
// graftnav calibrate --multi-position IMU.txt --out OUT_DIR (multi-position, graftnav IMU file)
//
// Writes OUT_DIR/calibration.yaml (see calibration_io.h), OUT_DIR/report.md, CSV tables and, when
// python3 + matplotlib are available, PNG plots made by scripts/runtime/plot_allan.py and
// scripts/runtime/plot_calibration.py.
#include <fmt/core.h>
#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "script_locator.h"
#include "graftnav/calibration/calibration_io.h"
#include "graftnav/calibration/lab_calibration.h"
#include "graftnav/calibration/multi_position.h"
#include "graftnav/case/input_checks.h"
#include "graftnav/io/atomic_file.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/nav/units.h"

namespace graftnav::app {
namespace {

namespace fs = std::filesystem;

struct CalibArgs {
  std::string case_dir, out, multi_position, scripts_dir;
  std::vector<std::string> raw_counts;
  double gravity = 0.0;
  double init_static_s = 0.0;
  int max_degree = 3;
  bool no_plots = false;
};

// Plots through the shared script runner (scripts dir and python with matplotlib found once).
void runPlot(const std::string& script, const std::string& out, std::vector<std::string>& made) {
  const std::string w = runPythonScript(script, {out});
  if (!w.empty()) {
    fmt::print(stderr, "warning: {}\n", w);
  } else {
    made.push_back(script);
  }
}

std::string mat(const Eigen::Matrix3d& M, double scale, const char* f) {
  std::string s;
  for (int i = 0; i < 3; ++i) {
    s += "| ";
    for (int j = 0; j < 3; ++j) s += fmt::format(fmt::runtime(f), M(i, j) * scale) + " | ";
    s += "\n";
  }
  return s;
}

std::string vec(const Eigen::Vector3d& v, double scale, const char* f) {
  return fmt::format("[{}, {}, {}]", fmt::format(fmt::runtime(f), v[0] * scale),
                     fmt::format(fmt::runtime(f), v[1] * scale),
                     fmt::format(fmt::runtime(f), v[2] * scale));
}

void writeSensorSection(std::ostringstream& md, const char* title, const SensorCalibration& s,
                        bool gyro, const PoseDriftEstimate& pose_drift, double drift_window_s,
                        double drift_separation_s, const PolynomialFitOptions& poly) {
  const double bs = gyro ? units::kRadToDeg * 3600.0 : 1.0 / units::kMilliGToMPerSec2;
  const char* bu = gyro ? "deg/h" : "mg";
  md << "### " << title << " (" << s.method << ")\n\n";
  md << "M - I (ppm; measured = M true + bias):\n\n| | | |\n|---|---|---|\n"
     << mat(s.M - Eigen::Matrix3d::Identity(), 1e6, "{:.0f}");
  md << "\nM_sigma (ppm):\n\n| | | |\n|---|---|---|\n" << mat(s.M_sigma, 1e6, "{:.1f}");
  md << "\nbias " << vec(s.bias, bs, "{:.3f}") << " " << bu << ", 1-sigma "
     << vec(s.bias_sigma, bs, "{:.3f}") << " " << bu << "\n\n";
  if (s.has_allan) {
    const double ws = gyro ? units::kRadToDeg * 60.0 : 60.0;
    const char* wu = gyro ? "deg/sqrt(h)" : "m/s/sqrt(h)";
    md << "Allan: white noise " << vec(s.allan.white_noise, ws, "{:.4f}") << " " << wu << " (+- "
       << vec(s.allan.white_noise_sigma, ws, "{:.4f}") << "); bias instability "
       << vec(s.allan.bias_instability, bs, "{:.3f}") << " " << bu << " (+- "
       << vec(s.allan.bias_instability_sigma, bs, "{:.3f}") << "); rate random walk "
       << vec(s.allan.rate_random_walk, 1.0, "{:.3e}")
       << (gyro ? " rad/s/sqrt(s)" : " m/s^2/sqrt(s)") << "\n\n";
  }
  if (s.has_fit) {
    md << fmt::format(
        "Fitting functions (Eq. 21, SI, lowest order first; degree by backward chi-square/F test at "
        "{:g} % for the sensor, {:.2g} % per axis):\n\n",
        100.0 * poly.degree_alpha, 100.0 * poly.perAxisAlpha());
    md << "Point sigmas include a pose-to-pose drift of " << vec(pose_drift.sigma, bs, "{:.3f}")
       << " " << bu
       << fmt::format(
              " (static record, {:.0f}-s windows {:.0f} s apart, RMS over the axes; 0 when unknown)",
              drift_window_s, drift_separation_s)
       << (std::isfinite(pose_drift.dof[0])
               ? fmt::format(
                     ", its square estimated to {:.1f} degrees of freedom (the degree test's F "
                     "reference adds them to the residuals')\n\n",
                     pose_drift.dof[0])
               : std::string("\n\n"));
    md << "| axis | degree | coefficients | 1-sigma | CV rms | points |\n|---|---|---|---|---|---|\n";
    for (int a = 0; a < 3; ++a) {
      const PolynomialFit& f = s.fit[a];
      std::string c, cs;
      for (std::size_t k = 0; k < f.coeffs.size(); ++k) {
        c += fmt::format("{}{:.6e}", k ? ", " : "", f.coeffs[k]);
        cs += fmt::format("{}{:.1e}", k ? ", " : "", f.coeffs_sigma[k]);
      }
      md << "| " << char('x' + a) << " | " << f.degree << " | " << c << " | " << cs << " | "
         << fmt::format("{:.2e}", f.cv_rms) << " | " << f.n_points << " |\n";
    }
    md << "\n";
  }
}

void writeAllanCsv(const std::string& path, const AllanCurve& c, const AllanFit& f) {
  std::ostringstream o;
  o << "tau_s,adev_x,adev_y,adev_z,rel_error,model_x,model_y,model_z,N_x,N_y,N_z,B_x,B_y,B_z,K_x,K_y,K_z\n";
  for (std::size_t i = 0; i < c.tau_s.size(); ++i) {
    o << fmt::format("{:.6g},{:.8e},{:.8e},{:.8e},{:.5f}", c.tau_s[i], c.adev[i][0], c.adev[i][1],
                     c.adev[i][2], c.rel_error[i]);
    for (int a = 0; a < 3; ++a) o << fmt::format(",{:.8e}", f.modelAdev(a, c.tau_s[i]));
    for (const Eigen::Vector3d* v :
         {&f.terms.white_noise, &f.terms.bias_instability, &f.terms.rate_random_walk})
      for (int a = 0; a < 3; ++a) o << fmt::format(",{:.8e}", (*v)[a]);
    o << "\n";
  }
  writeFileAtomically(path, o.str());
}

void writeFitCsv(const std::string& path, const std::vector<LinearObservation>& obs,
                 const SensorCalibration& s, const PoseDriftEstimate& pose_drift) {
  std::ostringstream o;
  o << "axis,x_true,y_measured_own_axis,sigma,sigma_with_drift,fit,linear_M\n";
  for (int a = 0; a < 3; ++a)
    for (const auto& ob : obs) {
      double y = ob.measured[a];
      for (int j = 0; j < 3; ++j)
        if (j != a) y -= s.M(a, j) * ob.true_value[j];
      const double fit = s.has_fit ? s.fit[a].evaluate(ob.true_value[a]) : y;
      o << fmt::format("{},{:.10e},{:.10e},{:.4e},{:.4e},{:.10e},{:.10e}\n", a, ob.true_value[a], y,
                       ob.sigma[a], std::hypot(ob.sigma[a], pose_drift.sigma[a]), fit,
                       s.M(a, a) * ob.true_value[a] + s.bias[a]);
    }
  writeFileAtomically(path, o.str());
}

// The checks section of report.md: least-squares fits, closed forms, |f| at rest, Eq. 9-12.
void writeChecksSection(std::ostringstream& md, const LabCalibrationReport& rep) {
  md << "## Checks\n\n";
  // Own-axis powers fitted with M (six_position.h): the fitting functions' degrees.
  const auto powers = [](const LinearModelFit& f) -> std::string {
    if (f.axis_degree == std::array<int, 3>{1, 1, 1}) return "";
    return fmt::format(", with the own-axis powers of the fitting functions (degrees {} {} {})",
                       f.axis_degree[0], f.axis_degree[1], f.axis_degree[2]);
  };
  if (rep.has_accel) {
    md << fmt::format(
        "- six-position LS: chi2 {:.3g}, dof {}, covariance scale {:.3g}, residual rms {:.3e} m/s^2{}\n",
        rep.accel_fit.chi2, rep.accel_fit.dof, rep.accel_fit.covariance_scale,
        rep.accel_fit.residual_rms, powers(rep.accel_fit));
    md << fmt::format(
        "- Eq. 8 closed form minus Ceres: max |dM| {:.2e}, max |db| {:.2e} m/s^2\n",
        (rep.accel_closed_form.leftCols<3>() - rep.result.accel.M).cwiseAbs().maxCoeff(),
        (rep.accel_closed_form.col(3) - rep.result.accel.bias).cwiseAbs().maxCoeff());
    md << fmt::format(
        "- |f| - g at rest over the poses: RMS {:.5f} m/s^2 raw -> {:.5f} m/s^2 calibrated\n",
        rep.norm_rms_before, rep.norm_rms_after);
    md << "\n| pose | raw norm | calibrated norm |\n|---|---|---|\n";
    for (const auto& c : rep.norm_checks)
      md << fmt::format("| {} | {:.5f} | {:.5f} |\n", c.name, c.raw_norm, c.calibrated_norm);
    md << "\n";
  }
  if (rep.has_eq9)
    md << "- Eq. 9 gyro bias (up/down pairs, Earth rate removed): "
       << vec(rep.eq9.bias, units::kRadToDeg * 3600.0, "{:.3f}") << " deg/h\n";
  if (rep.has_eq10)
    md << fmt::format("- Eq. 10-11 (pos/neg turns, {} pairs) minus LS: max |dM| {:.2e}\n",
                      rep.eq10.pairs_used, (rep.eq10.M - rep.result.gyro.M).cwiseAbs().maxCoeff());
  if (rep.has_gyro_lsq)
    md << fmt::format("- gyro LS: chi2 {:.3g}, dof {}, covariance scale {:.3g}{}\n",
                      rep.gyro_fit.chi2, rep.gyro_fit.dof, rep.gyro_fit.covariance_scale,
                      powers(rep.gyro_fit));
  if (rep.has_basic) {
    const auto& b = rep.basic;
    md << fmt::format("\n## Basic error signal (lab/static.txt, {:.1f} s)\n\n", b.duration_s);
    md << "- mean gyro error " << vec(b.gyro_mean_rad_s, units::kRadToDeg * 3600.0, "{:.3f}")
       << " deg/h, mean accel error "
       << vec(b.accel_mean_m_s2, 1.0 / units::kMilliGToMPerSec2, "{:.3f}") << " mg\n";
    Eigen::Vector3d Dg = b.gyro_D, Da = b.accel_D;
    if (rep.has_allan)
      for (int i = 0; i < 3; ++i) {
        Dg[i] = averagedNoiseLevel(rep.result.gyro.allan.white_noise[i], b.duration_s);
        Da[i] = averagedNoiseLevel(rep.result.accel.allan.white_noise[i], b.duration_s);
      }
    md << "- Eq. 12 noise level of these means, D = sigma_RW / sqrt(t_static): gyro "
       << vec(Dg, units::kRadToDeg * 3600.0, "{:.4f}") << " deg/h, accel "
       << vec(Da, 1.0 / units::kMilliGToMPerSec2, "{:.4f}") << " mg\n";
  }
}

void runLab(const CalibArgs& a) {
  LabDataOptions lo;
  lo.gravity_override_m_s2 = a.gravity;
  const LabData data = loadLabData(a.case_dir, lo);
  for (const auto& w : data.warnings) fmt::print(stderr, "warning: {}\n", w);
  // The floor `evaluate` applies: a shorter record gives no usable basic error signal or Allan.
  if (data.has_static) checkLabStaticRecord(data.staticRecordSeconds(), data.static_file, 0.0);
  LabCalibrationOptions co;
  co.poly.max_degree = a.max_degree;
  const LabCalibrationReport rep = calibrateLab(data, co);
  fs::create_directories(a.out);
  writeCalibrationYaml(a.out + "/calibration.yaml", rep.result);

  if (rep.has_allan) {
    writeAllanCsv(a.out + "/allan_gyro.csv", rep.gyro_allan, rep.gyro_allan_fit);
    writeAllanCsv(a.out + "/allan_accel.csv", rep.accel_allan, rep.accel_allan_fit);
  }
  if (rep.has_accel)
    writeFitCsv(a.out + "/fit_accel.csv", rep.accel_obs, rep.result.accel, rep.accel_pose_drift);
  if (rep.has_gyro_lsq)
    writeFitCsv(a.out + "/fit_gyro.csv", rep.gyro_obs, rep.result.gyro, rep.gyro_pose_drift);
  if (!rep.norm_checks.empty()) {
    std::string o = "pose,raw_norm,calibrated_norm,gravity\n";
    for (const auto& c : rep.norm_checks)
      o += fmt::format("{},{:.6f},{:.6f},{:.6f}\n", c.name, c.raw_norm, c.calibrated_norm,
                       data.gravity_m_s2);
    writeFileAtomically(a.out + "/pose_norms.csv", o);
  }
  std::vector<std::string> plots;
  if (!a.no_plots) {
    if (!a.scripts_dir.empty()) setenv("GRAFTNAV_SCRIPTS_DIR", a.scripts_dir.c_str(), 1);
    if (rep.has_allan) runPlot("plot_allan.py", a.out, plots);
    runPlot("plot_calibration.py", a.out, plots);
  }

  std::ostringstream md;
  md << "# Lab calibration: " << data.name << "\n\n";
  md << "Case `" << a.case_dir << "`; gravity " << fmt::format("{:.5f}", data.gravity_m_s2)
     << " m/s^2"
     << (data.latitude_known
             ? fmt::format(", latitude {:.4f} deg", data.lab.lat_rad * units::kRadToDeg)
             : std::string(", latitude unknown"))
     << "; six-position poses " << data.six_position.size() << ", tilts " << data.tilts.size()
     << ", rate runs " << data.rate_runs.size() << ", static record "
     << (data.has_static ? "yes" : "no") << ".\n\n";
  for (const auto& n : rep.notes) md << "- note: " << n << "\n";
  md << "\n## Results (calibration.yaml)\n\n";
  writeSensorSection(md, "Accelerometer", rep.result.accel, false, rep.accel_pose_drift,
                     rep.pose_drift_window_s, rep.pose_drift_separation_s, co.poly);
  writeSensorSection(md, "Gyro", rep.result.gyro, true, rep.gyro_pose_drift,
                     rep.pose_drift_window_s, rep.pose_drift_separation_s, co.poly);
  writeChecksSection(md, rep);
  if (!plots.empty()) {
    md << "\n## Plots\n\n";
    for (const char* p :
         {"allan_gyro.png", "allan_accel.png", "fit_gyro.png", "fit_accel.png", "pose_norms.png"})
      if (fs::exists(a.out + "/" + p)) md << "![" << p << "](" << p << ")\n\n";
  }
  writeFileAtomically(a.out + "/report.md", md.str());
  fmt::print("calibrated '{}' -> {}/calibration.yaml\n", data.name, a.out);
  if (rep.has_accel)
    fmt::print("  accel: |f|-g RMS {:.5f} -> {:.5f} m/s^2 over {} poses\n", rep.norm_rms_before,
               rep.norm_rms_after, rep.norm_checks.size());
  if (rep.has_allan)
    for (int i = 0; i < 3; ++i)
      fmt::print("  gyro {}: ARW {:.4f} deg/sqrt(h), BI {:.3f} deg/h\n", char('x' + i),
                 rep.result.gyro.allan.white_noise[i] * units::kRadToDeg * 60.0,
                 rep.result.gyro.allan.bias_instability[i] * units::kRadToDeg * 3600.0);
  for (const auto& n : rep.notes) fmt::print("  note: {}\n", n);
}

void runMultiPosition(const CalibArgs& a) {
  MultiPositionOptions o;
  o.gravity_m_s2 = a.gravity > 0.0 ? a.gravity : 9.80665;
  o.detector.init_static_s = a.init_static_s;
  ImuSeries imu;
  std::string src;
  if (!a.raw_counts.empty()) {
    imu = readRawCountPair(a.raw_counts[0], a.raw_counts[1]);
    src = a.raw_counts[0];
  } else {
    ImuReadOptions ro;
    ro.policy = ImuReadPolicy::real();
    imu = readImu(a.multi_position, ro);
    src = a.multi_position;
  }
  const MultiPositionResult r = calibrateMultiPosition(imu, o, src);
  CalibrationResult res;
  res.case_name = fs::path(src).stem().string();
  res.gravity_m_s2 = o.gravity_m_s2;
  res.accel = r.accel;
  res.gyro = r.gyro;
  fs::create_directories(a.out);
  writeCalibrationYaml(a.out + "/calibration.yaml", res);
  std::ostringstream md;
  md << "# Multi-position calibration: " << src << "\n\n";
  md << fmt::format("- gravity {:.5f} m/s^2{}\n", o.gravity_m_s2,
                    a.gravity > 0.0 ? "" : " (standard: latitude unknown)");
  md << fmt::format(
      "- static intervals found: {} (thresholds gyro {:.4f} rad/s, accel {:.4f} m/s^2)\n",
      r.intervals.size(), r.gyro_threshold_rad_s, r.accel_threshold_m_s2);
  md << fmt::format(
      "- |f| - g RMS over the intervals: {:.5f} (nominal) -> {:.5f} m/s^2 (calibrated)\n",
      r.accel_norm_rms_before, r.accel_norm_rms_after);
  md << fmt::format("- gravity-direction prediction RMS over the motions: {:.3f} -> {:.3f} deg\n",
                    r.gyro_angle_rms_before * units::kRadToDeg,
                    r.gyro_angle_rms_after * units::kRadToDeg);
  md << fmt::format("- distinct attitudes: {}\n", r.distinct_attitudes);
  for (const auto& n : r.notes) md << "- note: " << n << "\n";
  md << "\n";
  writeSensorSection(md, "Accelerometer", res.accel, false, PoseDriftEstimate{}, 0.0, 0.0,
                     PolynomialFitOptions{});
  writeSensorSection(md, "Gyro", res.gyro, true, PoseDriftEstimate{}, 0.0, 0.0,
                     PolynomialFitOptions{});
  writeFileAtomically(a.out + "/report.md", md.str());
  {
    std::string o2 = "index,t_begin_s,t_end_s,samples\n";
    for (std::size_t k = 0; k < r.intervals.size(); ++k)
      o2 += fmt::format("{},{:.3f},{:.3f},{}\n", k + 1, r.intervals[k].t_begin_s,
                        r.intervals[k].t_end_s, r.intervals[k].end - r.intervals[k].begin);
    writeFileAtomically(a.out + "/static_intervals.csv", o2);
  }
  fmt::print("multi-position calibration of {} -> {}/calibration.yaml\n", src, a.out);
  fmt::print(
      "  {} static intervals; |f|-g RMS {:.5f} -> {:.5f} m/s^2; gravity direction RMS {:.3f} -> {:.3f} deg\n",
      r.intervals.size(), r.accel_norm_rms_before, r.accel_norm_rms_after,
      r.gyro_angle_rms_before * units::kRadToDeg, r.gyro_angle_rms_after * units::kRadToDeg);
  for (const auto& n : r.notes) fmt::print("  note: {}\n", n);
}

}  // namespace

void registerCalibrate(CLI::App& app) {
  auto a = std::make_shared<CalibArgs>();
  CLI::App* cmd = app.add_subcommand("calibrate",
                                     "Lab calibration of the tested IMU (six-position, rate table, "
                                     "basic errors, Allan, fitting functions) or multi-position");
  cmd->add_option("case_dir", a->case_dir, "case directory (case.yaml + lab/)");
  cmd->add_option("--out", a->out, "output directory")->required();
  cmd->add_option("--gravity", a->gravity,
                  "gravity magnitude m/s^2 (default: normal gravity at the lab, "
                  "9.80665 when the latitude is unknown)");
  cmd->add_option("--max-degree", a->max_degree, "largest fitting-function degree (1..4)")
      ->check(CLI::Range(1, 4));
  cmd->add_flag("--no-plots", a->no_plots, "do not run the matplotlib scripts");
  cmd->add_option("--scripts-dir", a->scripts_dir, "where plot_allan.py / plot_calibration.py are");
  cmd->add_option("--multi-position", a->multi_position,
                  "multi-position recording (graftnav IMU file)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--raw-counts", a->raw_counts,
                  "multi-position recording as two imu_tk count files ACC GYRO")
      ->expected(2)
      ->check(CLI::ExistingFile);
  cmd->add_option(
      "--init-static", a->init_static_s,
      "multi-position: seconds of initial static data for adaptive detector thresholds");
  cmd->callback([a]() {
    const int modes = !a->case_dir.empty() + !a->multi_position.empty() + !a->raw_counts.empty();
    if (modes != 1)
      throw CLI::ValidationError("calibrate",
                                 "give exactly one of CASE_DIR, --multi-position, --raw-counts");
    if (!a->case_dir.empty())
      runLab(*a);
    else
      runMultiPosition(*a);
  });
}

}  // namespace graftnav::app
