// The candidate library of the mismatch finder (candidate_terms.h) as a registry: one builder per
// term, each appending its term (and the term's fixed parts or alternatives) to the library. The
// registry's order is the library's, and the library's order is the column order of every fit in
// the selection, so a new term goes at the end of its list.
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {
namespace {

const char* kSensorName[2] = {"gyro", "accel"};

// Column acting on channel (sensor*3 + axis) only.
RegressorColumn singleChannel(int channel, const Eigen::VectorXd& v) {
  RegressorColumn c;
  c.channel[channel] = v;
  return c;
}

Eigen::MatrixX3d inputOf(const BinnedImu& x, int sensor) {
  return sensor == 0 ? x.omega_rad_s : x.f_m_s2;
}

// What every builder reads: the regressor inputs, the options, the reference's bins.
struct LibraryContext {
  const RegressorInputs& in;
  const CandidateLibraryOptions& opt;
  const BinnedImu& x;
  int n = 0;          // bins
  double span_s = 0;  // n x bin length
};

// One sensor's input (0 gyro: omega, 1 accel: f) and its even functions.
struct SensorInputs {
  int s = 0;
  std::string sensor;
  Eigen::MatrixX3d u, u_abs, u_sq;
};

SensorInputs sensorInputs(const LibraryContext& ctx, int s) {
  const RegressorInputs& in = ctx.in;
  const BinnedImu& x = ctx.x;
  const int n = ctx.n;
  const Eigen::MatrixX3d u = inputOf(x, s);
  const std::string sensor = kSensorName[s];
  // The even functions per sample, bin-averaged (RegressorInputs::even_powers), else of the
  // bin means.
  const Eigen::MatrixX3d& abs_given =
      s == 0 ? in.even_powers.abs_omega_rad_s : in.even_powers.abs_f_m_s2;
  const Eigen::MatrixX3d& sq_given = s == 0 ? in.even_powers.sq_omega : in.even_powers.sq_f;
  const Eigen::MatrixX3d u_abs = abs_given.rows() == n ? abs_given : u.cwiseAbs().eval();
  const Eigen::MatrixX3d u_sq = sq_given.rows() == n ? sq_given : u.cwiseAbs2().eval();
  return SensorInputs{s, sensor, u, u_abs, u_sq};
}

// Slope of the tested accelerometer's lab-calibrated response at bin i's specific force.
Eigen::Matrix3d accelSlope(const RegressorInputs& in, const BinnedImu& x, int i) {
  Eigen::Matrix3d J = in.accel_response_M;
  for (int a = 0; a < 3; ++a) J(a, a) += 2.0 * in.accel_response_c2(a) * x.f_m_s2(i, a);
  return J;
}

// Nuisance: constant bias and linear drift per channel.
void addConstantBias(const LibraryContext& ctx, std::vector<CandidateTerm>* out) {
  const CandidateLibraryOptions& opt = ctx.opt;
  const int n = ctx.n;
  CandidateTerm t;
  t.name = "constant_bias";
  t.sensor = "both";
  t.nuisance = true;
  t.explanation =
      "turn-on bias of the field run differing from the lab, and its linear drift "
      "over the record (nuisance, not claimed)";
  for (int c = 0; c < kMismatchChannels; ++c)
    t.columns.push_back(singleChannel(c, Eigen::VectorXd::Ones(n)));
  if (opt.linear_drift_nuisance) {
    const Eigen::VectorXd ramp = Eigen::VectorXd::LinSpaced(n, -1.0, 1.0);
    for (int c = 0; c < kMismatchChannels; ++c) t.columns.push_back(singleChannel(c, ramp));
  }
  out->push_back(std::move(t));
}

void addBiasInstability(const LibraryContext& ctx, const SensorInputs& si,
                        std::vector<CandidateTerm>* out) {
  const CandidateLibraryOptions& opt = ctx.opt;
  const BinnedImu& x = ctx.x;
  const int n = ctx.n;
  const double span_s = ctx.span_s;
  const int s = si.s;
  // bias_instability: hat functions at knots 0, d, 2d, ... (the last knot at the end); interior
  // knots only.
  const double knot_s = std::max(opt.knot_spacing_s, span_s / (opt.max_knots - 1));
  const int knots = std::max(2, static_cast<int>(std::ceil(span_s / knot_s - 1e-9)) + 1);
  const double spacing = span_s / (knots - 1);
  CandidateTerm t;
  t.name = "bias_instability";
  t.sensor = kSensorName[s];
  t.knot_spacing_s = spacing;
  t.explanation = std::string("the ") + kSensorName[s] +
                  " bias wanders during the field run more than the lab record shows "
                  "(piecewise-linear bias, knots every " +
                  std::to_string(static_cast<int>(std::round(spacing))) + " s)";
  // The first knot is spanned by the nuisance constant, the last one too with a linear drift.
  const int last = opt.linear_drift_nuisance ? knots - 1 : knots;
  if (last <= 1) return;
  for (int axis = 0; axis < 3; ++axis) {
    for (int k = 1; k < last; ++k) {
      Eigen::VectorXd v(n);
      for (int i = 0; i < n; ++i) {
        const double u = (i + 0.5) * x.grid.bin_s / spacing - k;  // knot k at u = 0
        v(i) = std::max(0.0, 1.0 - std::abs(u));
      }
      t.columns.push_back(singleChannel(s * 3 + axis, v));
    }
  }
  out->push_back(std::move(t));
}

void addScaleFactor(const LibraryContext& /*ctx*/, const SensorInputs& si,
                    std::vector<CandidateTerm>* out) {
  const int s = si.s;
  const std::string& sensor = si.sensor;
  const Eigen::MatrixX3d& u = si.u;
  CandidateTerm t;
  t.name = "scale_factor";
  t.sensor = sensor;
  t.explanation = "the " + sensor + " gain differs from the simulated one (output = (1 + k) input)";
  for (int a = 0; a < 3; ++a) t.columns.push_back(singleChannel(s * 3 + a, u.col(a)));
  out->push_back(std::move(t));
}

void addNonOrthogonality(const LibraryContext& /*ctx*/, const SensorInputs& si,
                         std::vector<CandidateTerm>* out) {
  const int s = si.s;
  const std::string& sensor = si.sensor;
  const Eigen::MatrixX3d& u = si.u;
  CandidateTerm t;
  t.name = "non_orthogonality";
  t.sensor = sensor;
  t.explanation =
      "the " + sensor + " axes are not perpendicular: each axis picks up a fraction of the others";
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (i != j) t.columns.push_back(singleChannel(s * 3 + i, u.col(j)));
  out->push_back(std::move(t));
}

void addSymmetricNonOrthogonality(const LibraryContext& /*ctx*/, const SensorInputs& si,
                                  std::vector<CandidateTerm>* out) {
  const int s = si.s;
  const std::string& sensor = si.sensor;
  const Eigen::MatrixX3d& u = si.u;
  if (s != 1) return;
  // The gauge of the selection's last step (term_selection.h, step 4): both full
  // non-orthogonalities together span a rotation common to both triads, which is the
  // mounting's; re-expressed with a mounting_misalignment, the accelerometer triad keeps
  // its symmetric cross-axis part, N_ij = N_ji (it defines the body frame) and the gyro's
  // full N the rotation of the gyro triad relative to it. Never selected on its own.
  CandidateTerm t;
  t.name = "non_orthogonality";
  t.sensor = sensor;
  t.regressor = "symmetric";
  t.gauge_only = true;
  t.explanation =
      "the accelerometer axes are not perpendicular: symmetric cross-axis "
      "coupling (the rotation common to both triads is the mounting's)";
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j) {
      RegressorColumn col;
      col.channel[s * 3 + i] = u.col(j);
      col.channel[s * 3 + j] = u.col(i);
      t.columns.push_back(col);
    }
  out->push_back(std::move(t));
}

void addScaleAsymmetry(const LibraryContext& ctx, const SensorInputs& si,
                       std::vector<CandidateTerm>* out) {
  const RegressorInputs& in = ctx.in;
  const int s = si.s;
  const std::string& sensor = si.sensor;
  const Eigen::MatrixX3d& u_abs = si.u_abs;
  const Eigen::MatrixX3d& u_sq = si.u_sq;
  CandidateTerm t;
  // One parameter per axis, the half-difference d of the gains per sign (output = input +
  // d |input|, so k_pos - k_neg = 2 d); their mean is scale_factor's. With both gains as
  // parameters the term paid three extra parameters for the mean, which a lab-grafted
  // simulation already holds, and lost to scale_nonlinearity's x^2 (the other even
  // function) on random cases with an asymmetry 1.4-3x its detection limit.
  t.name = "scale_asymmetry";
  t.sensor = sensor;
  // Marginality, as for scale_nonlinearity: where the input keeps one sign (f_z ~ -g) |x| is
  // -x, a gain; measured without the scale factor the term claimed that gain past the scale
  // factor's lab gate (random_11_15: an accelerometer quadratic's slope at -g, 7 sigma on
  // k_neg z, named as an asymmetry).
  t.requires_terms = {"scale_factor:" + sensor};
  t.paid_requires = true;
  t.explanation = "the " + sensor + " gain differs for positive and negative inputs";
  t.shape_alternatives = {"scale_nonlinearity"};
  for (int a = 0; a < 3; ++a) t.columns.push_back(singleChannel(s * 3 + a, u_abs.col(a)));
  const Eigen::Vector3d& c2 = s == 0 ? in.gyro_response_c2 : in.accel_response_c2;
  if ((c2.array() != 0.0).any()) {
    // The alternative that replaces SG#2's lab quadratic (header).
    CandidateTerm part;
    part.name = "lab_quadratic_replaced";
    part.sensor = sensor;
    part.fixed = true;
    part.explanation =
        "SG#2's lab quadratic of the " + sensor + ", taken out where the asymmetry replaces it";
    RegressorColumn col;
    for (int a = 0; a < 3; ++a)
      if (c2(a) != 0.0) col.channel[s * 3 + a] = -c2(a) * u_sq.col(a);
    part.columns.push_back(col);
    CandidateTerm alt = t;
    alt.regressor = "replaces_lab_quadratic";
    alt.explanation +=
        "; the lab's quadratic in SG#2 is this asymmetry as the lab saw it "
        "(SG#3 takes it out)";
    part.part_of = alt.key();
    alt.requires_terms.push_back(part.key());
    alt.excludes = {t.key()};
    t.excludes = {alt.key()};
    out->push_back(std::move(t));
    out->push_back(std::move(alt));
    out->push_back(std::move(part));
  } else {
    out->push_back(std::move(t));
  }
}

void addScaleNonlinearity(const LibraryContext& /*ctx*/, const SensorInputs& si,
                          std::vector<CandidateTerm>* out) {
  const int s = si.s;
  const std::string& sensor = si.sensor;
  const Eigen::MatrixX3d& u_sq = si.u_sq;
  CandidateTerm t;
  t.name = "scale_nonlinearity";
  t.sensor = sensor;
  // Marginality: the quadratic is tested, and fitted, with the linear term of the same
  // sensor in the model. Without it x^2 stands in for a gain wherever the input keeps one
  // sign around a large mean (f_z ~ -g: x^2 = -2 g x - g^2 + (x + g)^2), and under common
  // random numbers an accelerometer k2 was claimed on the null case after backward
  // elimination had dropped the scale factor it was imitating.
  t.requires_terms = {"scale_factor:" + sensor};
  t.paid_requires = true;
  t.explanation = "the " + sensor + " input-output line bends: output = input + k2 input^2";
  t.shape_alternatives = {"scale_asymmetry"};
  for (int a = 0; a < 3; ++a) t.columns.push_back(singleChannel(s * 3 + a, u_sq.col(a)));
  out->push_back(std::move(t));
}

// temperature_bias and temperature_scale, when the tested temperature spans enough.
void addTemperatureTerms(const LibraryContext& ctx, const SensorInputs& si,
                         std::vector<CandidateTerm>* out) {
  const RegressorInputs& in = ctx.in;
  const CandidateLibraryOptions& opt = ctx.opt;
  const int n = ctx.n;
  const int s = si.s;
  const std::string& sensor = si.sensor;
  const Eigen::MatrixX3d& u = si.u;
  const Eigen::VectorXd& T = in.tested_temperature_degC;
  if (T.size() == n && T.allFinite() &&
      T.maxCoeff() - T.minCoeff() >= opt.min_temperature_span_degC) {
    const double t_ref = T.mean();
    const Eigen::VectorXd dT = T.array() - t_ref;
    const Eigen::VectorXd& Ts = in.simulated_temperature_degC;
    const bool sim_temp = Ts.size() == n && Ts.allFinite();
    const Eigen::VectorXd dT_bias = sim_temp ? (T - Ts).eval() : dT;
    CandidateTerm tb;
    tb.name = "temperature_bias";
    tb.sensor = sensor;
    // Against the simulation's temperature the model is per_degC (T - T_sim): the reference
    // temperature is the one behind the simulation's bias (its mean, when it varies).
    tb.t_ref_degC = sim_temp ? Ts.mean() : t_ref;
    tb.mean_is_physical = sim_temp;
    tb.explanation = "the " + sensor + " bias follows the sensor temperature";
    if (sim_temp)
      tb.explanation +=
          " (regressed on the tested minus the simulation's temperature; t_ref_degC "
          "is the simulation's, so the bias at the field's temperature differs "
          "from the simulation's by per_degC (T - t_ref_degC), grafted in full)";
    for (int a = 0; a < 3; ++a) tb.columns.push_back(singleChannel(s * 3 + a, dT_bias));
    out->push_back(std::move(tb));
    CandidateTerm ts;
    ts.name = "temperature_scale";
    ts.sensor = sensor;
    ts.t_ref_degC = t_ref;
    ts.explanation = "the " + sensor + " gain follows the sensor temperature";
    for (int a = 0; a < 3; ++a)
      ts.columns.push_back(singleChannel(s * 3 + a, dT.cwiseProduct(u.col(a))));
    out->push_back(std::move(ts));
  }
}

// vibration_rectification, one term per vibration level the sensor rectifies.
void addVibrationRectification(const LibraryContext& ctx, const SensorInputs& si,
                               std::vector<CandidateTerm>* out) {
  const RegressorInputs& in = ctx.in;
  const int n = ctx.n;
  const int s = si.s;
  const std::string& sensor = si.sensor;
  const std::array<std::pair<std::string, const Eigen::VectorXd*>, 2> vib = {
      std::make_pair(std::string("specific_force_hp_sq"), &in.vibration_f_hp_sq),
      std::make_pair(std::string("angular_rate_hp_sq"), &in.vibration_w_hp_sq)};
  for (int v = 0; v < 2; ++v) {
    if (vib[v].second->size() != n) continue;
    // The angular-rate level is offered to the gyro only (a gyro rectifies its own rate
    // vibration); both sensors rectify linear vibration.
    if (v == 1 && s == 1) continue;
    CandidateTerm t;
    t.name = "vibration_rectification";
    t.sensor = sensor;
    t.regressor = vib[v].first;
    if (s == 0) t.excludes = {"vibration_rectification:gyro:" + vib[1 - v].first};
    t.explanation = "vibration is rectified into a " + sensor + " bias proportional to the " +
                    (v == 0 ? "specific-force" : "angular-rate") + " vibration power";
    // A gain that differs by sign rectifies the rate vibration too; the part inside a sample
    // (vibration near the Nyquist frequency) is not in scale_asymmetry's bin-averaged |x|
    // (random_31_01 at 100 Hz named this term; at 400 Hz the asymmetry, docs/mismatch.md).
    if (v == 1)
      t.explanation +=
          " (a gyro scale_asymmetry rectifies rate vibration the samples do not "
          "resolve in the same way)";
    for (int a = 0; a < 3; ++a) t.columns.push_back(singleChannel(s * 3 + a, *vib[v].second));
    out->push_back(std::move(t));
  }
}

// g_sensitivity: gyro rows, specific force columns.
void addGSensitivity(const LibraryContext& ctx, std::vector<CandidateTerm>* out) {
  const RegressorInputs& in = ctx.in;
  const BinnedImu& x = ctx.x;
  const int n = ctx.n;
  CandidateTerm t;
  t.name = "g_sensitivity";
  t.sensor = "gyro";
  t.explanation = "the gyros read part of the specific force as rotation (proof-mass unbalance)";
  const Eigen::MatrixX3d& f =
      in.g_sensitivity_f_m_s2.rows() == n ? in.g_sensitivity_f_m_s2 : x.f_m_s2;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) t.columns.push_back(singleChannel(i, f.col(j)));
  out->push_back(std::move(t));
}

void addTimeOffset(const LibraryContext& ctx, std::vector<CandidateTerm>* out) {
  const RegressorInputs& in = ctx.in;
  const int n = ctx.n;
  if (in.time_offset_column.rows() == n && in.time_offset_column.cols() == kMismatchChannels) {
    CandidateTerm t;
    t.name = "time_offset";
    t.sensor = "both";
    t.explanation = "the tested IMU's time tags are shifted from the reference's";
    RegressorColumn col;
    for (int c = 0; c < kMismatchChannels; ++c) col.channel[c] = in.time_offset_column.col(c);
    t.columns.push_back(col);
    out->push_back(std::move(t));
  }
}

// lever_arm: accel rows.
void addLeverArm(const LibraryContext& ctx, std::vector<CandidateTerm>* out) {
  const RegressorInputs& in = ctx.in;
  const BinnedImu& x = ctx.x;
  const int n = ctx.n;
  Eigen::MatrixX3d wdot(n, 3);
  if (in.omega_dot_rad_s2.rows() == n) {
    wdot = in.omega_dot_rad_s2;
  } else {
    for (int i = 0; i < n; ++i) {
      const int a = std::max(0, i - 1), b = std::min(n - 1, i + 1);
      wdot.row(i) = (x.omega_rad_s.row(b) - x.omega_rad_s.row(a)) / ((b - a) * x.grid.bin_s);
    }
  }
  CandidateTerm t;
  t.name = "lever_arm";
  t.sensor = "accel";
  t.explanation =
      "the tested IMU sits away from the reference IMU and feels the tangential and "
      "centripetal acceleration of the turning vehicle";
  for (int j = 0; j < 3; ++j) {
    RegressorColumn col;
    Eigen::MatrixX3d v(n, 3);
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(j);
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector3d w = x.omega_rad_s.row(i).transpose();
      const Eigen::Vector3d wd = wdot.row(i).transpose();
      v.row(i) = (accelSlope(in, x, i) * (wd.cross(e) + w.cross(w.cross(e)))).transpose();
    }
    for (int a = 0; a < 3; ++a) col.channel[3 + a] = v.col(a);
    t.columns.push_back(col);
  }
  out->push_back(std::move(t));
}

// mounting_misalignment: the tested output C_tb(phi) x, C_tb = exp(-[phi x]), linearized at
// the pivot phi0: C_tb(phi0) x + D0 (phi - phi0), D0 = [(C_tb(phi0) x) x] Jr(phi0) (x omega
// x phi at phi0 = 0). The columns are D0; a non-zero pivot adds the fixed remainder
// (C_tb(phi0) - I) x - D0 phi0 as a part of the term, so theta stays the rotation vector and
// the model is exact to first order about phi0 (a 4-deg rotation's second order is a
// -0.4 % "scale factor" and 0.2 % "cross-axis" terms under the first-order model).
void addMountingMisalignment(const LibraryContext& ctx, std::vector<CandidateTerm>* out) {
  const RegressorInputs& in = ctx.in;
  const BinnedImu& x = ctx.x;
  const int n = ctx.n;
  const Eigen::Vector3d& phi0 = in.mounting_rotation_pivot_rad;
  const bool pivoted = phi0.squaredNorm() > 0.0;
  const Eigen::Matrix3d C0 = dcmFromRotationVector(phi0).transpose();
  const Eigen::Matrix3d Jr0 = rightJacobianSO3(phi0);
  std::array<Eigen::MatrixX3d, 3> vg, va;  // per column j: n x 3 (gyro rows, accel rows)
  Eigen::MatrixX3d rg(n, 3), ra(n, 3);     // the remainder (pivoted only)
  for (int j = 0; j < 3; ++j) {
    vg[j].resize(n, 3);
    va[j].resize(n, 3);
  }
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d w = x.omega_rad_s.row(i).transpose();
    const Eigen::Vector3d f = x.f_m_s2.row(i).transpose();
    const Eigen::Matrix3d Dg = skew(C0 * w) * Jr0;
    const Eigen::Matrix3d J = accelSlope(in, x, i);
    const Eigen::Matrix3d Da = J * skew(C0 * f) * Jr0;
    for (int j = 0; j < 3; ++j) {
      vg[j].row(i) = Dg.col(j).transpose();
      va[j].row(i) = Da.col(j).transpose();
    }
    if (pivoted) {
      rg.row(i) = (C0 * w - w - Dg * phi0).transpose();
      ra.row(i) = (J * (C0 * f - f) - Da * phi0).transpose();
    }
  }
  CandidateTerm t;
  t.name = "mounting_misalignment";
  t.sensor = "both";
  t.explanation = "the tested IMU is mounted slightly rotated relative to the reference IMU";
  for (int j = 0; j < 3; ++j) {
    RegressorColumn col;
    for (int a = 0; a < 3; ++a) {
      col.channel[a] = vg[j].col(a);
      col.channel[3 + a] = va[j].col(a);
    }
    t.columns.push_back(col);
  }
  if (pivoted) {
    CandidateTerm rem;
    rem.name = "mounting_rotation_remainder";
    rem.sensor = "both";
    rem.fixed = true;
    rem.part_of = t.key();
    rem.explanation = "the mounting rotation's departure from its linearization at the pivot";
    RegressorColumn col;
    for (int a = 0; a < 3; ++a) {
      col.channel[a] = rg.col(a);
      col.channel[3 + a] = ra.col(a);
    }
    rem.columns.push_back(col);
    t.requires_terms = {rem.key()};
    out->push_back(std::move(t));
    out->push_back(std::move(rem));
  } else {
    out->push_back(std::move(t));
  }
}

void addEarthRotationOmitted(const LibraryContext& ctx, std::vector<CandidateTerm>* out) {
  const RegressorInputs& in = ctx.in;
  const int n = ctx.n;
  if (static_cast<int>(in.C_bn.size()) != n) return;
  CandidateTerm t;
  t.name = "earth_rotation_omitted";
  t.sensor = "gyro";
  t.fixed = true;
  t.requires_terms = {"bias_instability:gyro"};
  t.explanation = "the simulation leaves out the Earth's rotation, which every real gyro senses";
  RegressorColumn col;
  Eigen::MatrixX3d v(n, 3);
  for (int i = 0; i < n; ++i) v.row(i) = (in.C_bn[i] * in.omega_ie_n).transpose();
  for (int a = 0; a < 3; ++a) col.channel[a] = v.col(a);
  t.columns.push_back(col);
  out->push_back(std::move(t));
}

void addGravityModel(const LibraryContext& ctx, std::vector<CandidateTerm>* out) {
  const RegressorInputs& in = ctx.in;
  const int n = ctx.n;
  if (static_cast<int>(in.C_bn.size()) != n) return;
  CandidateTerm t;
  t.name = "gravity_model";
  t.sensor = "accel";
  t.requires_terms = {"bias_instability:accel"};
  t.explanation = "the simulation's gravity magnitude differs from the true local gravity";
  RegressorColumn col;
  Eigen::MatrixX3d v(n, 3);
  for (int i = 0; i < n; ++i) v.row(i) = (-in.C_bn[i].col(2)).transpose();
  for (int a = 0; a < 3; ++a) col.channel[3 + a] = v.col(a);
  t.columns.push_back(col);
  out->push_back(std::move(t));
}

using SensorTermBuilder = void (*)(const LibraryContext&, const SensorInputs&,
                                   std::vector<CandidateTerm>*);
using TermBuilder = void (*)(const LibraryContext&, std::vector<CandidateTerm>*);
struct SensorTermEntry {
  const char* name;
  SensorTermBuilder add;
};
struct TermEntry {
  const char* name;
  TermBuilder add;
};

// The terms of one sensor, built for the gyro, then for the accelerometer.
constexpr std::array<SensorTermEntry, 7> kSensorTerms = {{
    {"scale_factor", addScaleFactor},
    {"non_orthogonality", addNonOrthogonality},
    {"non_orthogonality:accel:symmetric", addSymmetricNonOrthogonality},
    {"scale_asymmetry", addScaleAsymmetry},
    {"scale_nonlinearity", addScaleNonlinearity},
    {"temperature_bias, temperature_scale", addTemperatureTerms},
    {"vibration_rectification", addVibrationRectification},
}};

// The terms of the pair of IMUs (motion, geometry, the simulation's own omissions).
constexpr std::array<TermEntry, 6> kPairTerms = {{
    {"g_sensitivity", addGSensitivity},
    {"time_offset", addTimeOffset},
    {"lever_arm", addLeverArm},
    {"mounting_misalignment", addMountingMisalignment},
    {"earth_rotation_omitted", addEarthRotationOmitted},
    {"gravity_model", addGravityModel},
}};

}  // namespace

std::vector<CandidateTerm> buildCandidateLibrary(const RegressorInputs& in,
                                                 const CandidateLibraryOptions& opt) {
  opt.validate();
  const BinnedImu& x = in.reference;
  const int n = x.size();
  if (n < 10) throw std::invalid_argument("buildCandidateLibrary: fewer than 10 bins");
  const LibraryContext ctx{in, opt, x, n, n * x.grid.bin_s};
  const std::array<SensorInputs, 2> sensors = {sensorInputs(ctx, 0), sensorInputs(ctx, 1)};
  std::vector<CandidateTerm> terms;
  addConstantBias(ctx, &terms);
  for (const SensorInputs& si : sensors) addBiasInstability(ctx, si, &terms);
  for (const SensorInputs& si : sensors)
    for (const SensorTermEntry& e : kSensorTerms) e.add(ctx, si, &terms);
  for (const TermEntry& e : kPairTerms) e.add(ctx, &terms);
  return terms;
}

}  // namespace graftnav
