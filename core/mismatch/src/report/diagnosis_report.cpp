#include <cmath>
#include <fstream>
#include <stdexcept>
#include <utility>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "graftnav/io/atomic_file.h"
#include "graftnav/mismatch/diagnosis_report.h"
#include "graftnav/mismatch/term_spec.h"
#include "graftnav/nav/units.h"

namespace graftnav {
namespace {

using nlohmann::json;

json num(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json numList(const std::vector<double>& v) {
  json a = json::array();
  for (double x : v) a.push_back(num(x));
  return a;
}

json vec3(const Eigen::Vector3d& v) { return json::array({num(v(0)), num(v(1)), num(v(2))}); }

json rmsJson(const ChannelRms& r) {
  return json{{sensorName(Sensor::gyro), vec3(r.gyro)}, {sensorName(Sensor::accel), vec3(r.accel)}};
}

json keyTexts(const std::vector<TermKey>& keys) {
  json a = json::array();
  for (const TermKey& k : keys) a.push_back(k.text());
  return a;
}

json spanJson(const LocatedSpan& s) {
  return json{{"channel", mismatchChannelNames()[s.channel]},
              {"t_start", s.t_start},
              {"t_end", s.t_end},
              {"regime", s.regime},
              {"excess_rms", num(s.excess_rms)}};
}

json statsJson(const DriftStats& s, bool fraction) {
  const double k = fraction ? 1.0 : units::kRadToDeg;
  return json{{"horizontal_m", num(s.horizontal_m)},
              {"vertical_m", num(s.vertical_m)},
              {"roll_deg", num(s.roll_rad * k)},
              {"pitch_deg", num(s.pitch_rad * k)},
              {"heading_deg", num(s.heading_rad * k)}};
}

// An effect as diagnosis.json writes it: parameters and their 1-sigma keyed alike.
json effectJson(const Effect& e, json evidence) {
  json p = json::object(), u = json::object();
  for (const EffectParameter& q : e.parameters) {
    if (!q.text.empty()) {
      p[q.key] = q.text;
      continue;
    }
    if (q.scalar) {
      p[q.key] = num(q.values[0]);
      u[q.key] = num(q.sigma[0]);
    } else {
      p[q.key] = numList(q.values);
      u[q.key] = numList(q.sigma);
    }
  }
  return json{
      {"name", e.name()}, {"sensor", scopeName(e.sensor)},   {"parameters", p},
      {"uncertainty", u}, {"evidence", std::move(evidence)}, {"explanation", e.explanation}};
}

std::string fmtVec(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + fmt::format("{:.4g}", v[i]);
  return s + "]";
}

std::string fmt3(const Eigen::Vector3d& v, double k) {
  return fmt::format("{:.4g} / {:.4g} / {:.4g}", v(0) * k, v(1) * k, v(2) * k);
}

// Claimed, ambiguous and implausible effects.
void addClaimsJson(const DiagnosisResult& r, json* j) {
  (*j)["effects"] = json::array();
  for (const Effect& e : r.effects)
    (*j)["effects"].push_back(effectJson(e, {{"delta_bic", num(e.delta_bic)},
                                             {"cv_gain", num(e.cv_gain)},
                                             {"method", e.evidence_method}}));
  // Found and modelled in SG#3 under the shape the selection chose, not claimed (diagnosis.h).
  (*j)["ambiguous"] = json::array();
  for (const AmbiguousEffect& a : r.ambiguous) {
    json ja = effectJson(a.effect, {{"delta_bic", num(a.effect.delta_bic)},
                                    {"cv_gain", num(a.effect.cv_gain)},
                                    {"name_margin", num(a.name_margin)},
                                    {"method", a.effect.evidence_method}});
    ja["alternative"] = a.alternative ? a.alternative->name : "";
    (*j)["ambiguous"].push_back(std::move(ja));
  }
  // Fitted, modelled in SG#3, not claimed: outside the sensor class's plausible range.
  (*j)["implausible"] = json::array();
  for (const ImplausibleEffect& im : r.implausible) {
    json ji = effectJson(im.effect, {{"delta_bic", num(im.effect.delta_bic)},
                                     {"cv_gain", num(im.effect.cv_gain)},
                                     {"method", im.effect.evidence_method}});
    ji["range"] = {{"parameter", im.parameter},
                   {"max_abs_value", num(im.value)},
                   {"bound", num(im.bound)},
                   {"sensor_class", im.sensor_class}};
    ji["probably_absorbing"] = im.absorbing ? json(im.absorbing->text()) : json(nullptr);
    ji["correlation"] = num(im.correlation);
    ji["reason"] = im.reason;
    (*j)["implausible"].push_back(std::move(ji));
  }
}

// What was checked beside the claims: correlations, separation, ranges, value lattices.
void addChecksJson(const DiagnosisResult& r, json* j) {
  (*j)["term_correlations"] = json::array();
  for (const TermCorrelation& c : r.term_correlations)
    (*j)["term_correlations"].push_back(json{{"a", c.term_a.text()},
                                             {"b", c.term_b.text()},
                                             {"canonical_correlation", num(c.canonical)}});
  if (r.separation)
    (*j)["separation_needed"] = {
        {"roll_rate_s", num(r.separation->gyro_needed_s(0))},
        {"pitch_rate_s", num(r.separation->gyro_needed_s(1))},
        {"roll_rate_present_s", num(r.separation->gyro_present_s(0))},
        {"pitch_rate_present_s", num(r.separation->gyro_present_s(1))},
        {"rate_deg_s", num(r.separation->rate_rad_s * units::kRadToDeg)},
        {"roll_tilt_s", num(r.separation->accel_needed_s(0))},
        {"pitch_tilt_s", num(r.separation->accel_needed_s(1))},
        {"tilt_deg", num(r.separation->tilt_rad * units::kRadToDeg)},
        {"nonorthogonality_bound_deg", num(r.separation->bound_rad * units::kRadToDeg)}};
  if (r.plausible_ranges)
    (*j)["plausible_ranges"] = {{"sensor_class", r.plausible_ranges->sensor_class},
                                {"source", r.plausible_ranges->source}};
  (*j)["quantization_checks"] = json::array();
  for (const QuantizationCheck& q : r.quantization_checks)
    (*j)["quantization_checks"].push_back(
        json{{"sensor", sensorName(q.sensor)},
             {"step", vec3(q.step)},
             {"printed_resolution", vec3(q.printed_resolution)},
             {"white_noise_sd_per_sample", vec3(q.white_noise_sd)},
             {"noise_share", vec3(q.noise_share)},
             {"resolvable_share", num(q.resolvable_share)},
             {"detectable_step", vec3(q.detectable_step)},
             {"claimed", json::array({q.claimed[0], q.claimed[1], q.claimed[2]})}});
}

json detectionLimitsJson(const std::vector<Effect>& detection_limits) {
  json out = json::array();
  for (const Effect& e : detection_limits) {
    json lim = json::object();
    for (const EffectParameter& q : e.parameters) {
      if (!q.text.empty()) continue;
      lim[q.key] = q.scalar ? num(q.values[0]) : numList(q.values);
    }
    json entry{{"name", e.name()}, {"sensor", scopeName(e.sensor)}, {"limit", lim}};
    if (!e.explanation.empty()) entry["why"] = e.explanation;
    if (!e.parameters.empty() && !e.parameters.back().text.empty())
      entry["regressor"] = e.parameters.back().text;
    out.push_back(entry);
  }
  return out;
}

// Residual RMS, the held-out check and the navigation level.
json fitJson(const DiagnosisResult& r, const NavigationComparison* nav) {
  json fit;
  fit["signal_rms_before"] = rmsJson(r.rms_before);
  fit["signal_rms_after"] = rmsJson(r.rms_after);
  fit["signal_rms_raw"] = rmsJson(r.rms_raw);
  fit["diff_before"] = nav ? statsJson(nav->diff_before, true) : json(nullptr);
  fit["diff_after"] = nav ? statsJson(nav->diff_after, true) : json(nullptr);
  if (nav) {
    fit["estimator"] = nav->estimator;
    fit["err"] = {{"SG2", statsJson(nav->err_sg2, false)},
                  {"SG3", statsJson(nav->err_sg3, false)},
                  {"REAL", statsJson(nav->err_real, false)}};
    json outs = json::array();
    for (const auto& o : nav->outages)
      outs.push_back(json{{"t_start", o.window.start_s},
                          {"t_end", o.window.end_s},
                          {"sg2_horizontal_m", num(o.sg2_horizontal_m)},
                          {"sg3_horizontal_m", num(o.sg3_horizontal_m)},
                          {"real_horizontal_m", num(o.real_horizontal_m)},
                          {"share", num(o.share)}});
    fit["outages"] = outs;
  }
  if (r.has_holdout)
    fit["holdout"] = {{"split_t", r.holdout_split_s},
                      {"terms_first_half", keyTexts(r.holdout_terms)},
                      {"second_half_rms_before", rmsJson(r.holdout_before)},
                      {"second_half_rms_after", rmsJson(r.holdout_after)}};
  return fit;
}

// Parameters and their 1-sigma of one effect, as two table cells.
std::pair<std::string, std::string> cells(const Effect& e) {
  std::string p, s;
  for (const EffectParameter& q : e.parameters) {
    if (!q.text.empty()) {
      p += q.key + "=" + q.text + " ";
      continue;
    }
    p += q.key + "=" + (q.scalar ? fmt::format("{:.4g}", q.values[0]) : fmtVec(q.values)) + " ";
    s += q.key + "=" + (q.scalar ? fmt::format("{:.2g}", q.sigma[0]) : fmtVec(q.sigma)) + " ";
  }
  return std::make_pair(p, s);
}

// The effects found, and the ambiguous and implausible ones.
std::string effectsMarkdown(const DiagnosisResult& r) {
  std::string m;
  for (const Effect& e : r.effects) {
    const auto [p, s] = cells(e);
    m += fmt::format("| {} | {} | {} | {} | {:.1f} | {:.4f} |\n", e.name(), scopeName(e.sensor), p,
                     s, e.delta_bic, e.cv_gain);
  }
  if (r.effects.empty()) m += "| (none) | | | | | |\n";
  m += "\n";
  for (const Effect& e : r.effects)
    m += fmt::format("- **{}** ({}): {}\n", e.name(), scopeName(e.sensor), e.explanation);
  if (!r.ambiguous.empty()) {
    m += "\n## Found, shape not settled (modelled in SG#3, not claimed)\n\n"
         "| fitted as | or | sensor | parameters (SI) | 1-sigma | delta_bic | name margin |\n"
         "|---|---|---|---|---|---|---|\n";
    for (const AmbiguousEffect& a : r.ambiguous) {
      const auto [p, s] = cells(a.effect);
      m += fmt::format("| {} | {} | {} | {} | {} | {:.1f} | {:.1f} |\n", a.effect.name(),
                       a.alternative ? a.alternative->name : "", scopeName(a.effect.sensor), p, s,
                       a.effect.delta_bic, a.name_margin);
    }
  }
  if (!r.implausible.empty()) {
    m += "\n## Fitted, implausible for this sensor class (modelled in SG#3, not claimed)\n\n"
         "| term | sensor | parameters (SI) | 1-sigma | delta_bic | why not claimed |\n"
         "|---|---|---|---|---|---|\n";
    for (const ImplausibleEffect& im : r.implausible) {
      const auto [p, s] = cells(im.effect);
      m += fmt::format("| {} | {} | {} | {} | {:.1f} | {} |\n", im.effect.name(),
                       scopeName(im.effect.sensor), p, s, im.effect.delta_bic, im.reason);
    }
  }
  return m;
}

std::string checksMarkdown(const DiagnosisResult& r) {
  std::string m;
  if (!r.term_correlations.empty()) {
    m +=
        "\n## Correlation between fitted terms (largest canonical correlation of their columns)\n\n"
        "| term | term | correlation |\n|---|---|---|\n";
    for (const TermCorrelation& c : r.term_correlations)
      m += fmt::format("| {} | {} | {:.3f} |\n", c.term_a.text(), c.term_b.text(), c.canonical);
  }
  if (!r.quantization_checks.empty()) {
    m += "\n## Value lattice of the tested increments\n\n";
    for (const QuantizationCheck& q : r.quantization_checks) m += "- " + q.summary() + "\n";
  }
  if (!r.in_simulation.empty()) {
    m += "\n## Already in the simulation (measured in the lab, grafted into SG#2; not claimed)\n\n";
    for (const Effect& e : r.in_simulation)
      m += fmt::format("- **{}** ({}): {}\n", e.name(), scopeName(e.sensor), e.explanation);
  }
  return m;
}

// Residual RMS per channel, the held-out check and the navigation level.
std::string fitMarkdown(const DiagnosisResult& r, const NavigationComparison* nav) {
  const double d = units::kRadToDeg;
  std::string m;
  m += "\n## Signal residual RMS per channel (gyro deg/s x/y/z; accel m/s^2 x/y/z)\n\n"
       "| | gyro | accel |\n|---|---|---|\n";
  m += fmt::format("| raw (real - simulated) | {} | {} |\n", fmt3(r.rms_raw.gyro, d),
                   fmt3(r.rms_raw.accel, 1));
  m += fmt::format("| before (constant removed) | {} | {} |\n", fmt3(r.rms_before.gyro, d),
                   fmt3(r.rms_before.accel, 1));
  m += fmt::format("| after (model) | {} | {} |\n", fmt3(r.rms_after.gyro, d),
                   fmt3(r.rms_after.accel, 1));
  if (r.has_holdout) {
    m += fmt::format("| second half, before (fit on first half, split t = {:.2f}) | {} | {} |\n",
                     r.holdout_split_s, fmt3(r.holdout_before.gyro, d),
                     fmt3(r.holdout_before.accel, 1));
    m += fmt::format("| second half, after | {} | {} |\n", fmt3(r.holdout_after.gyro, d),
                     fmt3(r.holdout_after.accel, 1));
    m += "\nTerms selected on the first half: ";
    for (const TermKey& t : r.holdout_terms) m += t.text() + " ";
    m += "\n";
  }
  if (nav) {
    m += fmt::format(
        "\n## Navigation ({}; {} outages of {} s)\n\n| | horiz. m | vert. m | roll deg | pitch deg | heading deg |\n|---|---|---|---|---|---|\n",
        nav->estimator, nav->outage_count, nav->outage_length_s);
    auto row = [&](const std::string& name, const DriftStats& s, bool frac) {
      const double k = frac ? 100.0 : 1.0, ka = frac ? 100.0 : d;
      m += fmt::format("| {} | {:.3f} | {:.3f} | {:.3f} | {:.3f} | {:.3f} |\n", name,
                       s.horizontal_m * k, s.vertical_m * k, s.roll_rad * ka, s.pitch_rad * ka,
                       s.heading_rad * ka);
    };
    row("ERR_SG2", nav->err_sg2, false);
    row("ERR_SG3", nav->err_sg3, false);
    row("ERR_REAL", nav->err_real, false);
    row("DIFF before (SG2) %", nav->diff_before, true);
    row("DIFF after (SG3) %", nav->diff_after, true);
  }
  return m;
}

std::string detectionLimitsMarkdown(const std::vector<Effect>& detection_limits) {
  std::string m;
  if (!detection_limits.empty()) {
    m += "\n## Not claimed: detection limits (SI)\n\nThe size each parameter alone (the term's "
         "others zero) would need for its expected evidence over the final model to reach the "
         "claim threshold (about a 50 % detection probability).\n\n| term | sensor | limit |\n"
         "|---|---|---|\n";
    for (const Effect& e : detection_limits) {
      std::string lim;
      for (const EffectParameter& q : e.parameters) {
        if (!q.text.empty()) {
          lim += (lim.empty() ? "" : "; ") + q.key + " " + q.text;
          continue;
        }
        lim += (lim.empty() ? "" : "; ") + q.key + " ";
        for (std::size_t i = 0; i < q.values.size(); ++i)
          lim += fmt::format("{}{:.3g}", i ? " " : "", q.values[i]);
      }
      m += fmt::format("| {} | {} | {} |\n", e.name(), scopeName(e.sensor), lim);
    }
  }
  return m;
}

}  // namespace

std::string diagnosisJson(const DiagnosisResult& r, const NavigationComparison* nav) {
  json j;
  j["case"] = r.case_name;
  j["simulation"] = r.simulation_kind;
  j["located"] = json::array();
  for (const LocatedSpan& s : r.located) j["located"].push_back(spanJson(s));
  addClaimsJson(r, &j);
  addChecksJson(r, &j);
  j["modelled_in_simulation"] = json::array();
  for (const Effect& e : r.in_simulation)
    j["modelled_in_simulation"].push_back(effectJson(e, {{"method", e.evidence_method}}));
  j["unexplained"] = json::array();
  for (const LocatedSpan& s : r.unexplained) j["unexplained"].push_back(spanJson(s));
  j["detection_limits"] = detectionLimitsJson(r.detection_limits);
  j["masked_spans"] = json::array();
  for (const auto& [a, b] : r.masked_spans) j["masked_spans"].push_back(json::array({a, b}));
  j["wander"] = json::array();
  for (const WanderCheck& k : r.wander)
    j["wander"].push_back(json{{"channel", mismatchChannelNames()[k.channel]},
                               {"fitted_sd", num(k.fitted_sd)},
                               {"expected_sd", num(k.expected_sd)},
                               {"limit", num(k.limit)},
                               {"within_lab_noise", k.within}});
  j["fit"] = fitJson(r, nav);
  j["time_offset_xcorr"] = {{"tau_s", r.time_offset_xcorr.tau_s},
                            {"peak_correlation", r.time_offset_xcorr.peak_correlation},
                            {"reliable", r.time_offset_xcorr.reliable}};
  j["noise_model"] = {
      {"ar1_rho", numList(std::vector<double>(r.selection.rho.data(), r.selection.rho.data() + 6))},
      {"innovation_sigma",
       numList(std::vector<double>(r.selection.sigma.data(), r.selection.sigma.data() + 6))},
      {"variance_inflation", num(r.selection.inflation)},
      {"slow_noise_inflation", numList(std::vector<double>(r.selection.slow_inflation.data(),
                                                           r.selection.slow_inflation.data() + 6))},
      {"rows", r.selection.rows}};
  j[termName(TermKind::constant_bias)] =
      numList(std::vector<double>(r.nuisance_bias.data(), r.nuisance_bias.data() + 6));
  j["linear_drift"] =
      numList(std::vector<double>(r.nuisance_drift.data(), r.nuisance_drift.data() + 6));
  j["selection_log"] = r.selection.log;
  j["notes"] = r.notes;
  j["grid"] = {{"t_begin", r.grid.t_begin_s}, {"bin_s", r.grid.bin_s}, {"bins", r.grid.count}};
  return j.dump(2);
}

std::string diagnosisMarkdown(const DiagnosisResult& r, const NavigationComparison* nav) {
  std::string m = fmt::format(
      "# Mismatch diagnosis: {}\n\nSimulation: {}. Grid: {} bins of {} s "
      "from t = {:.3f} s.\n\n",
      r.case_name, r.simulation_kind, r.grid.count, r.grid.bin_s, r.grid.t_begin_s);
  m += fmt::format("Cross-correlation time offset: {:.4f} s (peak correlation {:.4f}, {}).\n\n",
                   r.time_offset_xcorr.tau_s, r.time_offset_xcorr.peak_correlation,
                   r.time_offset_xcorr.reliable ? "reliable" : "not reliable");
  m += "## Effects found\n\n| effect | sensor | parameters (SI) | 1-sigma | delta_bic | cv_gain |\n"
       "|---|---|---|---|---|---|\n";
  m += effectsMarkdown(r);
  m += checksMarkdown(r);
  m += fitMarkdown(r, nav);
  m +=
      "\n## Located (residual before modelling)\n\n| channel | t_start | t_end | regime | excess_rms |\n|---|---|---|---|---|\n";
  for (const LocatedSpan& s : r.located)
    m += fmt::format("| {} | {:.2f} | {:.2f} | {} | {:.4g} |\n", mismatchChannelNames()[s.channel],
                     s.t_start, s.t_end, s.regime, s.excess_rms);
  m +=
      "\n## Unexplained (still above noise after modelling)\n\n| channel | t_start | t_end | regime | excess_rms |\n|---|---|---|---|---|\n";
  for (const LocatedSpan& s : r.unexplained)
    m += fmt::format("| {} | {:.2f} | {:.2f} | {} | {:.4g} |\n", mismatchChannelNames()[s.channel],
                     s.t_start, s.t_end, s.regime, s.excess_rms);
  if (r.unexplained.empty()) m += "| (none) | | | | |\n";
  m += detectionLimitsMarkdown(r.detection_limits);
  if (!r.wander.empty()) {
    m +=
        "\n## Slow bias wander against the lab's noise figures (SI)\n\n"
        "Fitted: piecewise-linear bias of the modelled residual (sd about the mean). Expected: two "
        "independent realizations of the lab's bias instability and rate random walk, plus the "
        "white noise the knots pass. Within the limit it is treated as noise.\n\n"
        "| channel | fitted sd | expected sd | limit | verdict |\n|---|---|---|---|---|\n";
    for (const WanderCheck& k : r.wander)
      m += fmt::format("| {} | {:.4g} | {:.4g} | {:.4g} | {} |\n",
                       mismatchChannelNames()[k.channel], k.fitted_sd, k.expected_sd, k.limit,
                       k.within ? "noise" : "beyond the lab figures");
  }
  m += "\n## Selection log\n\n";
  for (const std::string& l : r.selection.log) m += "- " + l + "\n";
  m += fmt::format(
      "\nNoise model: AR(1) rho per channel [{:.3f}, {:.3f}, {:.3f}, {:.3f}, {:.3f}, {:.3f}], "
      "variance inflation {:.2f}, slow-noise inflation {:.3g} {:.3g} {:.3g} {:.3g} {:.3g} {:.3g}.\n",
      r.selection.rho(0), r.selection.rho(1), r.selection.rho(2), r.selection.rho(3),
      r.selection.rho(4), r.selection.rho(5), r.selection.inflation, r.selection.slow_inflation(0),
      r.selection.slow_inflation(1), r.selection.slow_inflation(2), r.selection.slow_inflation(3),
      r.selection.slow_inflation(4), r.selection.slow_inflation(5));
  if (!r.notes.empty()) {
    m += "\n## Notes\n\n";
    for (const std::string& n : r.notes) m += "- " + n + "\n";
  }
  return m;
}

void writeDiagnosisFiles(const std::string& out_dir, const DiagnosisResult& r,
                         const NavigationComparison* nav) {
  writeFileAtomically(out_dir + "/diagnosis.json", diagnosisJson(r, nav) + "\n");
  writeFileAtomically(out_dir + "/diagnosis.md", diagnosisMarkdown(r, nav));
  std::string csv =
      "t_s,r_gx,r_gy,r_gz,r_ax,r_ay,r_az,m_gx,m_gy,m_gz,m_ax,m_ay,m_az,c_gx,c_gy,c_gz,c_ax,c_ay,c_az,regime\n";
  csv.reserve(static_cast<std::size_t>(r.grid.count) * 260);
  for (int i = 0; i < r.grid.count; ++i) {
    csv += fmt::format("{:.4f}", r.grid.binMid(i));
    for (int c = 0; c < 6; ++c) csv += fmt::format(",{:.6e}", r.residual_before(i, c));
    for (int c = 0; c < 6; ++c) csv += fmt::format(",{:.6e}", r.model(i, c));
    for (int c = 0; c < 6; ++c) csv += fmt::format(",{:.6e}", r.nuisance(i, c));
    csv += "," + r.regimes[i] + "\n";
  }
  writeFileAtomically(out_dir + "/residual.csv", csv);
}

}  // namespace graftnav
