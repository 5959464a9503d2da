// The lab gates of the finder's selection: what the lab calibration's own uncertainty explains is
// not claimed (docs/mismatch-method.md, gates a, b, d).
#include <fmt/core.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "diagnosis_stages.h"
#include "graftnav/mismatch/term_spec.h"
#include "graftnav/mismatch/wander.h"

namespace graftnav::diagnosis_detail {

namespace {

// fitTerms on `model`, keeping the selection log of `sel`.
SelectionResult refitKeepingLog(const Eigen::MatrixXd& r, const std::vector<CandidateTerm>& terms,
                                const std::vector<int>& model, const SelectionOptions& options,
                                const SelectionResult& sel) {
  SelectionResult out = fitTerms(r, terms, model, options);
  out.log = sel.log;
  return out;
}

// The gates below decide what is claimed; they do not take the lab's calibration error out of
// the residual. Its signal (a scale or cross-axis error times the drive's rates and specific
// force) is still there, and a claimed term fitted without it takes up the part its regressor
// shares: under common random numbers a vibration-rectification coefficient came out 2-20 sigma
// off, by the same amount at 1x and 10x the injected coefficient, because the gated
// accelerometer scale and cross-axis terms had left the fit. So the claimed terms' parameters,
// uncertainties and evidence come from a fit with the gated terms in it as nuisance. A claimed
// term that no longer passes next to them is explained by the lab's own error: not claimed, and
// out of the model. The gated terms stay out of SG#3 (not missing physics; `sel.selected` does
// not hold them), so the constant bias is refitted to what the grafted terms leave.
SelectionResult withCalibrationErrorFitted(const Eigen::MatrixXd& r,
                                           const std::vector<CandidateTerm>& terms,
                                           const SelectionOptions& options, int max_passes,
                                           SelectionResult sel, const std::vector<int>& gated,
                                           std::vector<std::string>* notes) {
  if (gated.empty() || sel.selected.empty()) return sel;
  std::string gated_names;
  for (int t : gated) gated_names += (gated_names.empty() ? "" : ", ") + terms[t].key().text();
  for (int pass = 0; pass < max_passes; ++pass) {
    std::vector<int> model;
    for (const TermFit& tf : sel.selected) model.push_back(tf.term);
    for (int t : gated)
      if (std::find(model.begin(), model.end(), t) == model.end()) model.push_back(t);
    const SelectionResult full = fitTerms(r, terms, model, options);
    std::vector<int> kept;
    bool failed = false;
    for (TermFit& tf : sel.selected) {
      const auto it = std::find_if(full.selected.begin(), full.selected.end(),
                                   [&](const TermFit& f) { return f.term == tf.term; });
      if (it == full.selected.end()) continue;
      const bool claimed = tf.claimed;
      tf = *it;
      tf.claimed = claimed && it->claimed;
      if (claimed && !it->claimed) {
        failed = true;
        notes->push_back(fmt::format(
            "{} passed the selection but not next to the lab calibration error ({}) held in the "
            "fit (delta_bic {:.1f}, cv_gain {:.4f}): not claimed, the lab's own error explains it",
            terms[tf.term].key().text(), gated_names, it->delta_bic, it->cv_gain));
      } else if (claimed) {
        kept.push_back(tf.term);
      }
    }
    if (!failed) break;
    // Without the failed terms; the companions the kept ones require come back unclaimed.
    sel = refitKeepingLog(r, terms, kept, options, sel);
    for (TermFit& tf : sel.selected)
      if (std::find(kept.begin(), kept.end(), tf.term) == kept.end()) tf.claimed = false;
    if (sel.selected.empty()) return sel;
  }
  const Eigen::MatrixXd rest = r - predictSelection(sel, terms, static_cast<int>(r.rows()), false);
  sel.nuisance = fitTerms(rest, terms, {}, options).nuisance;
  notes->push_back(fmt::format(
      "the claimed terms are fitted with the lab calibration error ({}) in the model, so they do "
      "not take it up; it is not grafted into SG#3",
      gated_names));
  return sel;
}

// The column of the plain term (no regressor variant) of `kind` on `sensor` that acts on channel
// c over the whole grid (nullptr: no such term or column).
const Eigen::VectorXd* columnOn(const std::vector<CandidateTerm>& terms, TermKind kind,
                                Sensor sensor, int c) {
  for (const CandidateTerm& t : terms) {
    if (t.kind() != kind || t.sensor != scopeOf(sensor) || t.variant != TermVariant::none) continue;
    for (const RegressorColumn& col : t.columns)
      if (col.actsOn(c) && col.grid_rows == 0) return &col.channel[c];
  }
  return nullptr;
}

// How an error e of SG#2's lab quadratic (a residual e x^2) reads as an asymmetry d |x| beside
// the gain and the bias the asymmetry is fitted with: the |x| coefficient of x^2 regressed on
// 1, x, |x| over the drive's inputs (1/s or 1/(m/s^2) times e; per axis, 0 where x keeps one
// sign and |x| is the gain's column).
Eigen::Vector3d quadraticReadAsAsymmetry(const std::vector<CandidateTerm>& terms, Sensor sensor) {
  Eigen::Vector3d out = Eigen::Vector3d::Zero();
  for (int a = 0; a < 3; ++a) {
    const int c = firstChannel(sensor) + a;
    const Eigen::VectorXd* x = columnOn(terms, TermKind::scale_factor, sensor, c);
    const Eigen::VectorXd* x_abs = columnOn(terms, TermKind::scale_asymmetry, sensor, c);
    const Eigen::VectorXd* x_sq = columnOn(terms, TermKind::scale_nonlinearity, sensor, c);
    if (!x || !x_abs || !x_sq || x->size() != x_abs->size() || x->size() != x_sq->size()) continue;
    Eigen::MatrixXd X(x->size(), 3);
    X.col(0).setOnes();
    X.col(1) = *x;
    X.col(2) = *x_abs;
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X);
    if (qr.rank() < 3) continue;
    out(a) = qr.solve(*x_sq)(2);
  }
  return out;
}

// Why a gate holds a selected term back, and whether as the lab calibration's own error.
struct HoldBack {
  std::string note;
  bool calibration = true;
};

// The reference's mean rate and specific force over the record (the drive's operating point).
struct OperatingPoint {
  PerSensor<Eigen::Vector3d> mean_input{{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()}};
};

OperatingPoint driveOperatingPoint(const ImuSeries& reference) {
  OperatingPoint op;
  double duration_s = 0.0;
  for (const ImuSample& smp : reference) {
    op.mean_input[Sensor::gyro] += smp.dtheta_rad;
    op.mean_input[Sensor::accel] += smp.dvel_m_s;
    duration_s += smp.dt_s;
  }
  if (duration_s > 0.0)
    for (const Sensor s : kSensors) op.mean_input[s] /= duration_s;
  return op;
}

// What every gate of one pass reads.
struct GateContext {
  const std::vector<CandidateTerm>& terms;
  const DiagnosisInputs& in;
  const GridSpec& grid;
  const SelectionResult& sel;
  const OperatingPoint& drive;
  double gate_sigmas;  // FinderOptions::lab_gate_sigmas
};

// Gate (a): a scale_factor or non_orthogonality element must exceed 3 x sqrt(fit sigma^2 + lab
// sigma^2) (with the reference's scale and the lab quadratic's gain uncertainty for the scale).
std::optional<HoldBack> gateCalibrationMatrix(const GateContext& g, const TermFit& tf) {
  const CandidateTerm& t = g.terms[tf.term];
  const TermKind kind = t.kind();
  if (kind != TermKind::scale_factor && kind != TermKind::non_orthogonality) return std::nullopt;
  const bool scale = kind == TermKind::scale_factor;
  const Sensor sensor = t.triad();
  const SensorPriors& prior = g.in.priors[sensor];
  const std::optional<Eigen::Matrix3d>& Msig = prior.lab_M_sigma;
  if (!Msig) return std::nullopt;
  const std::optional<double>& ref_scale_sigma = prior.reference_scale_sigma;
  const std::optional<LabQuadratic>& quad = prior.lab_quadratic;
  const Eigen::Vector3d& mean_input = g.drive.mean_input[sensor];
  const Effect e = effectFromTerm(t, tf, g.grid.count);
  const EffectParameter& q = e.parameters[0];
  // With a mounting rotation in the model, that rotation is shared by both sensors and fitted
  // mostly from the better-determined one, so it carries that sensor's lab rotation error; this
  // sensor's cross-axis terms then take up the difference. Their lab budget adds the other
  // sensor's rotation uncertainty about the complementary axis.
  const std::optional<Eigen::Matrix3d>& other_Msig = g.in.priors[otherSensor(sensor)].lab_M_sigma;
  const bool shared_rotation = std::any_of(
      g.sel.selected.begin(), g.sel.selected.end(),
      [&](const TermFit& o) { return g.terms[o.term].kind() == TermKind::mounting_misalignment; });
  bool beyond = false;
  double worst_ratio = 0.0;  // largest |value| / limit, for the note
  std::size_t worst_k = 0;
  for (std::size_t k = 0; k < q.values.size(); ++k) {
    const int i = scale ? static_cast<int>(k) : static_cast<int>(k) / 3;
    const int j = scale ? static_cast<int>(k) : static_cast<int>(k) % 3;
    if (!scale && i == j) continue;
    double lab_sigma = (*Msig)(i, j);
    if (!scale && shared_rotation)
      lab_sigma = std::hypot(lab_sigma, labRotationSigma(other_Msig, 3 - i - j));
    if (scale && ref_scale_sigma) lab_sigma = std::hypot(lab_sigma, *ref_scale_sigma);
    // SG#2's gain at the drive's mean input x0 is c1 + 2 c2 x0: the lab's c2 uncertainty is a
    // gain uncertainty there (f_z ~ -g: 2 g sigma_c2; under common random numbers a c2_z 2 sigma
    // off was claimed as a -6.3e-4 z scale factor, random_14_22).
    if (scale && quad)
      lab_sigma = std::hypot(lab_sigma, 2.0 * std::abs(mean_input(i)) * quad->c2_sigma(i));
    const double lim = g.gate_sigmas * std::hypot(q.sigma[k], lab_sigma);
    beyond |= std::abs(q.values[k]) > lim;
    if (std::abs(q.values[k]) / lim > worst_ratio) {
      worst_ratio = std::abs(q.values[k]) / lim;
      worst_k = k;
    }
  }
  if (beyond) return std::nullopt;
  const bool with_ref = scale && ref_scale_sigma;
  const bool with_quad = scale && quad && (quad->c2_sigma.array() > 0.0).any();
  return HoldBack{fmt::format(
      "{} {} fitted but within {:g} sigma of the lab calibration's own uncertainty{}{}: not "
      "claimed (calibration error, not missing physics; largest element {}[{}] = {:.3g}, "
      "{:.2f} x its limit)",
      scopeName(t.sensor), t.name(), g.gate_sigmas,
      with_quad ? " (with its quadratic's at the drive's mean input)" : "",
      with_ref ? fmt::format(" and the reference IMU's scale uncertainty ({:.3g} ppm, "
                             "its profile)",
                             1e6 * *ref_scale_sigma)
               : "",
      q.key, worst_k, q.values[worst_k], worst_ratio)};
}

// Gate (b): the half-difference d of the gains per sign beyond 3 sigma of the fit and of the lab
// quadratic's uncertainty as it reads on |x|. A lab gain error moves both gains alike and the
// scale factor the asymmetry is fitted beside takes it up; an error of the lab's c2 (in SG#2
// where the lab kept it) is an even function, like |x|.
std::optional<HoldBack> gateAsymmetry(const GateContext& g, const TermFit& tf) {
  const CandidateTerm& t = g.terms[tf.term];
  if (t.kind() != TermKind::scale_asymmetry) return std::nullopt;
  const Sensor sensor = t.triad();
  if (!g.in.priors[sensor].lab_M_sigma) return std::nullopt;
  const std::optional<LabQuadratic>& quad = g.in.priors[sensor].lab_quadratic;
  const Effect e = effectFromTerm(t, tf, g.grid.count);
  const EffectParameter& d = e.parameters[0];
  const Eigen::Vector3d lab_c2_sigma = quad ? quad->c2_sigma : Eigen::Vector3d::Zero();
  const Eigen::Vector3d per_c2 =
      lab_c2_sigma.isZero() ? Eigen::Vector3d::Zero() : quadraticReadAsAsymmetry(g.terms, sensor);
  bool beyond = false;
  double worst_ratio = 0.0;
  int worst_a = 0;
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(d.sigma[a])) continue;
    const double lim = g.gate_sigmas * std::hypot(d.sigma[a], per_c2(a) * lab_c2_sigma(a));
    beyond |= std::abs(d.values[a]) > lim;
    if (std::abs(d.values[a]) / lim > worst_ratio) {
      worst_ratio = std::abs(d.values[a]) / lim;
      worst_a = a;
    }
  }
  if (beyond) return std::nullopt;
  return HoldBack{
      fmt::format("{} scale_asymmetry fitted but within {:g} sigma of the fit and of the lab "
                  "quadratic's uncertainty as it reads on |x|: not claimed (largest: axis {}, "
                  "d = {:.3g}, {:.2f} x its limit)",
                  scopeName(t.sensor), g.gate_sigmas, worst_a, d.values[worst_a], worst_ratio)};
}

// Gate (d): for either sensor a rotation is indistinguishable from the antisymmetric part of its
// cross-axis calibration error (labRotationSigma). A mounting rotation is claimed only beyond
// 3 sigma of the fit and of the less certain sensor's lab rotation uncertainty combined.
std::optional<HoldBack> gateMisalignment(const GateContext& g, const TermFit& tf) {
  const CandidateTerm& t = g.terms[tf.term];
  if (!(t.kind() == TermKind::mounting_misalignment && anyLabCalibration(g.in)))
    return std::nullopt;
  const Effect e = effectFromTerm(t, tf, g.grid.count);
  const EffectParameter& q = e.parameters[0];
  bool beyond = false;
  for (int a = 0; a < 3; ++a)
    beyond |= std::abs(q.values[a]) >
              g.gate_sigmas * std::hypot(q.sigma[a], sharedRotationLabSigma(g.in, a));
  if (beyond) return std::nullopt;
  return HoldBack{
      fmt::format("mounting_misalignment fitted but within {:g} sigma of the lab "
                  "calibration's rotation uncertainty (antisymmetric cross-axis "
                  "terms): not claimed (calibration error, not missing physics)",
                  g.gate_sigmas)};
}

// A bias_instability is claimed only when some axis wanders beyond what two independent
// realizations of the lab's bias instability and rate random walk give (99.9 % quantile).
std::optional<HoldBack> gateBiasWander(const GateContext& g, const TermFit& tf) {
  const CandidateTerm& t = g.terms[tf.term];
  if (t.kind() != TermKind::bias_instability) return std::nullopt;
  const std::optional<LabNoiseFigures>& lab = g.in.priors[t.triad()].lab_noise;
  if (!lab) return std::nullopt;
  const Effect e = effectFromTerm(t, tf, g.grid.count);
  const Eigen::Vector3d expected = expectedWanderSd(*lab, g.grid.count * g.grid.bin_s);
  bool beyond = false;
  for (int a = 0; a < 3; ++a)
    beyond |= e.parameters[0].values[a] > kWanderSdQuantile999 * expected(a);
  if (beyond) return std::nullopt;
  return HoldBack{
      fmt::format("{} bias wander [{:.3g} {:.3g} {:.3g}] is within {} x the wander the lab's bias "
                  "instability and rate random walk predict for two realizations [{:.3g} {:.3g} "
                  "{:.3g}]: not claimed (the graft already carries it)",
                  scopeName(t.sensor), e.parameters[0].values[0], e.parameters[0].values[1],
                  e.parameters[0].values[2], kWanderSdQuantile999, expected(0), expected(1),
                  expected(2)),
      false};
}

// The terms one pass keeps in the model, and which of them stay only as companions.
struct GatePass {
  std::vector<int> keep, companions;
  bool gated = false;
};

// Holds a term back: out of the model, or kept as an unclaimed companion when another selected
// term requires it (scale_factor next to scale_nonlinearity).
void holdBack(const GateContext& g, const TermFit& tf, const HoldBack& why, GatePass* pass,
              std::vector<std::string>* notes, std::vector<int>* calibration_gated) {
  std::string by;
  for (const TermFit& o : g.sel.selected)
    for (const TermKey& req : g.terms[o.term].requires_terms)
      if (req == g.terms[tf.term].key()) by = g.terms[o.term].key().text();
  if (!by.empty()) {
    pass->keep.push_back(tf.term);
    pass->companions.push_back(tf.term);
    const std::string kept = why.note + "; kept in the model as the companion " + by + " requires";
    if (std::find(notes->begin(), notes->end(), kept) == notes->end()) notes->push_back(kept);
    return;
  }
  pass->gated = true;
  if (why.calibration && std::find(calibration_gated->begin(), calibration_gated->end(), tf.term) ==
                             calibration_gated->end())
    calibration_gated->push_back(tf.term);
  notes->push_back(why.note);
}

}  // namespace

// Gates against claiming what the lab calibration's own uncertainty explains
// (docs/mismatch-method.md, gates a, b, d). A gated term leaves the model, the rest is refitted, and the gates run
// again on the refit (a term fitted to compensate the gated one, e.g. a gyro non-orthogonality
// cancelling a misalignment's gyro part, then shrinks and may be gated in turn).
SelectionResult applyLabGates(const Eigen::MatrixXd& r, const std::vector<CandidateTerm>& terms,
                              const DiagnosisInputs& in, const DiagnoseOptions& opt,
                              const GridSpec& grid, SelectionResult sel,
                              std::vector<std::string>* notes,
                              std::vector<int>* calibration_gated) {
  const SelectionOptions& options = opt.selection;
  const OperatingPoint drive = driveOperatingPoint(in.reference);
  GatePass pass;
  for (int gate_pass = 0; gate_pass < opt.finder.max_gate_passes; ++gate_pass) {
    const GateContext g{terms, in, grid, sel, drive, opt.finder.lab_gate_sigmas};
    pass = GatePass{};
    for (const TermFit& tf : sel.selected) {
      std::optional<HoldBack> why = gateCalibrationMatrix(g, tf);
      if (!why) why = gateAsymmetry(g, tf);
      if (!why) why = gateMisalignment(g, tf);
      if (!why) why = gateBiasWander(g, tf);
      if (why)
        holdBack(g, tf, *why, &pass, notes, calibration_gated);
      else
        pass.keep.push_back(tf.term);
    }
    if (!pass.gated) break;
    sel = refitKeepingLog(r, terms, pass.keep, options, sel);
  }
  for (TermFit& tf : sel.selected)
    if (std::find(pass.companions.begin(), pass.companions.end(), tf.term) != pass.companions.end())
      tf.claimed = false;
  return withCalibrationErrorFitted(r, terms, options, opt.finder.max_calibration_refit_passes,
                                    std::move(sel), *calibration_gated, notes);
}

}  // namespace graftnav::diagnosis_detail
