// The finder's selection stage: the candidate library at a time_offset pivot, forward selection,
// the second pass of the derivative regressor, the lab gates and the joint fit; then the passes
// the first explanation calls for (time pivot, mounting rotation, lever arm), each a named step.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "diagnosis_stages.h"
#include "graftnav/imu/imu_error_model.h"
#include "graftnav/mismatch/joint_fit.h"
#include "graftnav/mismatch/term_spec.h"

namespace graftnav::diagnosis_detail {

namespace {

int indexOfTerm(const std::vector<CandidateTerm>& terms, TermKind kind) {
  int idx = -1;
  for (std::size_t t = 0; t < terms.size(); ++t)
    if (terms[t].kind() == kind) idx = static_cast<int>(t);
  return idx;
}

std::vector<CandidateTerm> maskedLibrary(const RegressorInputs& ri, const ExplainInputs& ex) {
  std::vector<CandidateTerm> terms = buildCandidateLibrary(ri, ex.opt.library);
  zeroMaskedRows(ex.masked, &terms);
  return terms;
}

// Second pass, at pivot 0 only (the derivative regressor): the tested IMU's signal is shifted as
// a whole, so the time-offset regressor is the derivative of the modelled tested signal x +
// (other selected terms), not of x alone; a lever arm or misalignment would otherwise bias tau by
// their share of the signal. At a pivot pv != 0 the other terms are already built at t - pv,
// which is exact there.
void derivativeSecondPass(const ExplainInputs& ex, double pv, RegressorInputs* ri, Explanation* e) {
  const int n = ex.bins.n();
  const int to_idx = indexOfTerm(e->terms, TermKind::time_offset);
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(n, kMismatchChannels);
  bool has_to = false, has_other = false;
  for (const TermFit& tf : e->sel.selected) {
    if (tf.term == to_idx) {
      has_to = true;
    } else if (e->terms[tf.term].kind() != TermKind::bias_instability) {
      C += termContribution(e->terms[tf.term], tf.theta, n);
      has_other = true;
    }
  }
  if (!(has_to && has_other && pv == 0.0)) return;
  for (int i = 0; i < n; ++i) {
    const int a = std::max(0, i - 1), b = std::min(n - 1, i + 1);
    ri->time_offset_column.row(i) -= (C.row(b) - C.row(a)) / ((b - a) * ex.bins.grid.bin_s);
  }
  std::vector<CandidateTerm>().swap(e->terms);  // not held next to the library built again
  e->terms = maskedLibrary(*ri, ex);
  std::vector<std::string> log = e->sel.log;
  e->sel = selectTerms(ex.bins.r, e->terms, ex.opt.selection);
  log.push_back("second pass: time_offset regressor rebuilt from the modelled tested signal");
  log.insert(log.end(), e->sel.log.begin(), e->sel.log.end());
  e->sel.log = log;
}

// Joint fit with Ceres: the time offset as a non-linear parameter with everything else selected
// (joint_fit.h); the linear solution is its start. Evidence stays that of the selection.
void jointFitTimeOffset(const ExplainInputs& ex, double pv, const ImuSampleMap& response,
                        Explanation* e) {
  int to_idx = -1;
  for (const TermFit& tf : e->sel.selected)
    if (e->terms[tf.term].kind() == TermKind::time_offset) to_idx = tf.term;
  if (to_idx < 0) return;
  const JointFitResult jf =
      jointFitWithTimeOffset(ex.bins.r, ex.in.reference, ex.bins.grid, e->terms, e->sel, to_idx, pv,
                             ex.opt.joint_fit, response);
  e->sel.log.push_back(jf.summary);
  if (jf.converged && std::abs(jf.tau_s - pv) <= ex.opt.finder.pivot_tolerance_s) {
    // At its own pivot the linear model is exact in tau, and its terms were fitted by GLS
    // (term_selection.h step 3), which weighs a slow regressor against the bias wander of its
    // time scales; the joint fit whitens AR(1) only. A speed-driven vibration level next to a
    // 1-ms offset came out 5-16 sigma off from the joint fit (within 2 sigma from the linear
    // one). So the time offset is the joint fit's, the rest stays linear.
    const auto joint_to = std::find_if(jf.terms.begin(), jf.terms.end(),
                                       [&](const TermFit& f) { return f.term == to_idx; });
    for (TermFit& tf : e->sel.selected)
      if (tf.term == to_idx && joint_to != jf.terms.end()) tf = *joint_to;
    e->tau_joint_s = jf.tau_s;
    e->notes.push_back(jf.summary + "; at the pivot: the other terms keep their GLS fit");
  } else if (jf.converged) {
    e->sel.nuisance = jf.nuisance;
    e->sel.selected = jf.terms;
    e->joint_model = jf.model;
    e->tau_joint_s = jf.tau_s;
    e->notes.push_back(jf.summary);
  } else {
    e->notes.push_back(jf.summary + "; the linear fit is reported");
  }
}

// The explanation again at pivot pv, keeping the earlier selection log and the reason. The
// earlier explanation is released first: its candidate library (tens of MB on an hour of data)
// is not held next to the new one.
Explanation explainAgain(const ExplainInputs& ex, double pv, Explanation* before,
                         const std::string& why, RegressorState* reg,
                         std::vector<std::string>* report_notes,
                         std::vector<std::string>* repeat_notes) {
  std::vector<std::string> log = std::move(before->sel.log);
  *before = Explanation{};
  Explanation e = explainAt(ex, pv, reg, report_notes);
  log.push_back(why);
  log.insert(log.end(), e.sel.log.begin(), e.sel.log.end());
  e.sel.log = std::move(log);
  repeat_notes->push_back(why);
  return e;
}

// The chord regressor is exact only at its pivot: with road vibration (20-40 Hz) a pivot 0.1 ms
// from the offset leaves a residual that terms like scale_factor take up (three random cases with
// 1.4-17 ms offsets). When the joint fit moved tau by more than pivot_tolerance_s (10 us), the
// selection runs again around the joint fit's tau. Returns the reason, or nothing.
std::optional<std::string> timePivotMoved(const Explanation& e, double pivot_s,
                                          const FinderOptions& fo) {
  if (!(std::isfinite(e.tau_joint_s) && std::abs(e.tau_joint_s - pivot_s) > fo.pivot_tolerance_s))
    return std::nullopt;
  return fmt::format(
      "selection repeated with the time_offset pivot at the joint fit's tau ({:.6f} s, "
      "{:.6f} s before)",
      e.tau_joint_s, pivot_s);
}

// A mounting rotation of phi rad leaves second-order terms of |phi|^2 / 2 under the library's
// first-order columns (a gyro "scale factor" of -0.4 % at 4 deg; -11 ppm on x for the concealed
// misalignment case, beyond the fit's 1 ppm under common random numbers). When that exceeds
// 1 ppm the selection runs again with the rotation linearized at the fitted one (candidate
// library: mounting_rotation_pivot_rad) until the rotation moves by < 1 % (FinderOptions).
// Returns the new pivot.
std::optional<Eigen::Vector3d> rotationPivotMoved(const Explanation& e,
                                                  const Eigen::Vector3d& pivot_rad,
                                                  const FinderOptions& fo) {
  const TermFit* rot = nullptr;
  for (const TermFit& tf : e.sel.selected)
    if (e.terms[tf.term].kind() == TermKind::mounting_misalignment) rot = &tf;
  if (rot == nullptr || rot->theta.size() != 3) return std::nullopt;
  const Eigen::Vector3d phi = rot->theta;
  if (!phi.allFinite() || 0.5 * phi.squaredNorm() < fo.rotation_second_order_min ||
      (phi - pivot_rad).norm() < fo.rotation_rel_change * phi.norm())
    return std::nullopt;
  return phi;
}

// A tested accelerometer r away from the reference feels the road's angular vibration as
// omega_dot x r + omega x (omega x r) on top of the reference's specific force (0.5 m/s^2 at
// 40 Hz for 1 deg/s and 0.1 m), and rectifies that too: measured on the reference's vibration
// alone, a vibration coefficient came out 23 % (6 sigma) large next to a 0.1-m lever arm
// (random_20_15). Its gyros' g-sensitivity reads that specific force too: read from the
// reference's, the difference G (omega_dot x r + omega x (omega x r)), even in the yaw rate, was
// claimed under common random numbers as a 9-ppm gyro z asymmetry at 8.6 sigma and a 3-us time
// offset (random_38_23; neither without the lever arm or without G). With a lever arm and either
// term selected, returns the fitted lever arm, for one more pass with the reference moved to
// the tested IMU by it for both.
std::optional<Eigen::Vector3d> leverArmToMoveForce(const Explanation& e) {
  const TermFit* lever = nullptr;
  bool reads_f = false;
  for (const TermFit& tf : e.sel.selected) {
    const CandidateTerm& t = e.terms[tf.term];
    const TermKind kind = t.kind();
    if (kind == TermKind::lever_arm) lever = &tf;
    reads_f |= (kind == TermKind::vibration_rectification &&
                t.variant == TermVariant::specific_force_hp_sq) ||
               kind == TermKind::g_sensitivity;
  }
  if (lever != nullptr && reads_f && lever->theta.size() == 3 && lever->theta.allFinite())
    return Eigen::Vector3d(lever->theta);
  return std::nullopt;
}

}  // namespace

// Explain at a pivot of the time_offset regressor: library, selection (the selection also
// measures the noise left by the largest candidate model), second pass, lab gates, joint fit.
Explanation explainAt(const ExplainInputs& ex, double pv, RegressorState* reg,
                      std::vector<std::string>* report_notes) {
  Explanation e;
  reg->ri.time_offset_column =
      timeOffsetRegressor(ex.in.reference, ex.bins.grid, pv, reg->lab_response);
  buildMotionRegressors(ex.in, ex.bins, pv, reg, report_notes);
  e.terms = maskedLibrary(reg->ri, ex);
  e.sel = selectTerms(ex.bins.r, e.terms, ex.opt.selection);
  derivativeSecondPass(ex, pv, &reg->ri, &e);
  e.sel = applyLabGates(ex.bins.r, e.terms, ex.in, ex.opt, ex.bins.grid, std::move(e.sel), &e.notes,
                        &e.calibration_gated);
  if (ex.opt.ceres_joint_fit) jointFitTimeOffset(ex, pv, reg->lab_response, &e);
  return e;
}

SelectionPasses runSelectionPasses(const ExplainInputs& ex, double pivot_s, RegressorState* reg,
                                   std::vector<std::string>* report_notes) {
  SelectionPasses p;
  p.pivot_s = pivot_s;
  p.explanation = explainAt(ex, p.pivot_s, reg, report_notes);
  if (const auto why = timePivotMoved(p.explanation, p.pivot_s, ex.opt.finder)) {
    p.pivot_s = p.explanation.tau_joint_s;
    p.explanation =
        explainAgain(ex, p.pivot_s, &p.explanation, *why, reg, report_notes, &p.repeat_notes);
  }
  for (int rot_pass = 0; rot_pass < ex.opt.finder.max_rotation_passes; ++rot_pass) {
    const auto phi =
        rotationPivotMoved(p.explanation, reg->ri.mounting_rotation_pivot_rad, ex.opt.finder);
    if (!phi) break;
    reg->ri.mounting_rotation_pivot_rad = *phi;
    const std::string why = fmt::format(
        "selection repeated with mounting_misalignment linearized at the fitted rotation [{:.5f} "
        "{:.5f} {:.5f}] rad (its second order, up to {:.2g}, is then modelled)",
        (*phi)(0), (*phi)(1), (*phi)(2), 0.5 * phi->squaredNorm());
    p.explanation =
        explainAgain(ex, p.pivot_s, &p.explanation, why, reg, report_notes, &p.repeat_notes);
  }
  if (const auto r = leverArmToMoveForce(p.explanation)) {
    ImuErrorModel moved;
    moved.lever_arm.r_m = *r;
    try {
      reg->at_tested_imu = applyGeometry(ex.in.reference, moved);
    } catch (const std::invalid_argument& err) {  // a reference with gaps cannot be moved
      p.repeat_notes.push_back(std::string("vibration level left at the reference: ") + err.what());
      return p;
    }
    reg->motion_pivot_s = kNaN;  // rebuild the motion regressors with it
    const std::string why = fmt::format(
        "selection repeated with the specific force of the vibration level and of "
        "g_sensitivity moved to the tested IMU by the fitted lever arm [{:.4f} {:.4f} "
        "{:.4f}] m",
        (*r)(0), (*r)(1), (*r)(2));
    p.explanation =
        explainAgain(ex, p.pivot_s, &p.explanation, why, reg, report_notes, &p.repeat_notes);
  }
  return p;
}

}  // namespace graftnav::diagnosis_detail
