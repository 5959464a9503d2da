#include "graftnav/calibration/calibration_report.h"

#include <fmt/core.h>
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "graftnav/io/atomic_file.h"
#include "graftnav/nav/units.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;

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

}  // namespace

void writeLabCalibrationTables(const std::string& out, const LabData& data,
                               const LabCalibrationReport& rep) {
  if (rep.has_allan) {
    writeAllanCsv(out + "/allan_gyro.csv", rep.gyro_allan, rep.gyro_allan_fit);
    writeAllanCsv(out + "/allan_accel.csv", rep.accel_allan, rep.accel_allan_fit);
  }
  if (rep.has_accel)
    writeFitCsv(out + "/fit_accel.csv", rep.accel_obs, rep.result.accel, rep.accel_pose_drift);
  if (rep.has_gyro_lsq)
    writeFitCsv(out + "/fit_gyro.csv", rep.gyro_obs, rep.result.gyro, rep.gyro_pose_drift);
  if (!rep.norm_checks.empty()) {
    std::string o = "pose,raw_norm,calibrated_norm,gravity\n";
    for (const auto& c : rep.norm_checks)
      o += fmt::format("{},{:.6f},{:.6f},{:.6f}\n", c.name, c.raw_norm, c.calibrated_norm,
                       data.gravity_m_s2);
    writeFileAtomically(out + "/pose_norms.csv", o);
  }
}

std::string labCalibrationMarkdown(const std::string& case_dir, const std::string& out,
                                   const LabData& data, const LabCalibrationReport& rep,
                                   const LabCalibrationOptions& options, bool with_plots) {
  std::ostringstream md;
  md << "# Lab calibration: " << data.name << "\n\n";
  md << "Case `" << case_dir << "`; gravity " << fmt::format("{:.5f}", data.gravity_m_s2)
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
                     rep.pose_drift_window_s, rep.pose_drift_separation_s, options.poly);
  writeSensorSection(md, "Gyro", rep.result.gyro, true, rep.gyro_pose_drift,
                     rep.pose_drift_window_s, rep.pose_drift_separation_s, options.poly);
  writeChecksSection(md, rep);
  if (with_plots) {
    md << "\n## Plots\n\n";
    for (const char* p :
         {"allan_gyro.png", "allan_accel.png", "fit_gyro.png", "fit_accel.png", "pose_norms.png"})
      if (fs::exists(out + "/" + p)) md << "![" << p << "](" << p << ")\n\n";
  }
  return md.str();
}

void writeMultiPositionReport(const std::string& out, const std::string& src,
                              const MultiPositionResult& result, double gravity_m_s2,
                              bool gravity_given) {
  std::ostringstream md;
  md << "# Multi-position calibration: " << src << "\n\n";
  md << fmt::format("- gravity {:.5f} m/s^2{}\n", gravity_m_s2,
                    gravity_given ? "" : " (standard: latitude unknown)");
  md << fmt::format(
      "- static intervals found: {} (thresholds gyro {:.4f} rad/s, accel {:.4f} m/s^2)\n",
      result.intervals.size(), result.gyro_threshold_rad_s, result.accel_threshold_m_s2);
  md << fmt::format(
      "- |f| - g RMS over the intervals: {:.5f} (nominal) -> {:.5f} m/s^2 (calibrated)\n",
      result.accel_norm_rms_before, result.accel_norm_rms_after);
  md << fmt::format("- gravity-direction prediction RMS over the motions: {:.3f} -> {:.3f} deg\n",
                    result.gyro_angle_rms_before * units::kRadToDeg,
                    result.gyro_angle_rms_after * units::kRadToDeg);
  md << fmt::format("- distinct attitudes: {}\n", result.distinct_attitudes);
  for (const auto& n : result.notes) md << "- note: " << n << "\n";
  md << "\n";
  writeSensorSection(md, "Accelerometer", result.accel, false, PoseDriftEstimate{}, 0.0, 0.0,
                     PolynomialFitOptions{});
  writeSensorSection(md, "Gyro", result.gyro, true, PoseDriftEstimate{}, 0.0, 0.0,
                     PolynomialFitOptions{});
  writeFileAtomically(out + "/report.md", md.str());
  {
    std::string o2 = "index,t_begin_s,t_end_s,samples\n";
    for (std::size_t k = 0; k < result.intervals.size(); ++k)
      o2 += fmt::format("{},{:.3f},{:.3f},{}\n", k + 1, result.intervals[k].t_begin_s,
                        result.intervals[k].t_end_s,
                        result.intervals[k].end - result.intervals[k].begin);
    writeFileAtomically(out + "/static_intervals.csv", o2);
  }
}

}  // namespace graftnav
