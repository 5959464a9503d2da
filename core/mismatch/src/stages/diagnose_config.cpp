#include "graftnav/mismatch/diagnose_config.h"

#include <functional>
#include <map>
#include <stdexcept>

#include "graftnav/io/yaml_fields.h"
#include "graftnav/nav/units.h"

namespace graftnav {
namespace {

namespace yf = yaml_fields;
using Setter = std::function<void(const yf::Context&, const YAML::Node&, const std::string&)>;

Setter number(double* field, double scale = 1.0) {
  return [field, scale](const yf::Context& ctx, const YAML::Node& n, const std::string& key) {
    *field = yf::asDouble(ctx, n, key) * scale;
  };
}
Setter integer(int* field) {
  return [field](const yf::Context& ctx, const YAML::Node& n, const std::string& key) {
    *field = yf::asInt(ctx, n, key);
  };
}
Setter flag(bool* field) {
  return [field](const yf::Context& ctx, const YAML::Node& n, const std::string& key) {
    *field = yf::asBool(ctx, n, key);
  };
}

// Every key of the file and the option it sets, in the order of configs/diagnose.yaml.
std::map<std::string, Setter> keyTable(DiagnoseOptions* o) {
  FinderOptions& f = o->finder;
  return {
      {"bin_s", number(&o->bin_s)},
      {"margin_s", number(&o->margin_s)},
      {"window_s", number(&o->locate.window_s)},
      {"locate_false_alarm", number(&o->locate.false_alarm)},
      {"knot_spacing_s", number(&o->library.knot_spacing_s)},
      {"max_knots", integer(&o->library.max_knots)},
      {"min_delta_bic", number(&o->selection.min_delta_bic)},
      {"min_name_margin", number(&o->selection.min_name_margin)},
      {"min_cv_gain", number(&o->selection.min_cv_gain)},
      {"folds", integer(&o->selection.folds)},
      {"max_terms", integer(&o->selection.max_terms)},
      {"max_time_offset_s", number(&o->time_offset.max_offset_s)},
      {"coarse_max_time_offset_s", number(&o->time_offset.coarse_max_offset_s)},
      {"realign_offset_s", number(&o->realign_offset_s)},
      {"holdout", flag(&o->holdout)},
      {"detect_quantization", flag(&o->detect_quantization)},
      {"random_walk_sandwich", flag(&o->selection.random_walk_sandwich)},
      {"quantization_min_step_over_resolution", number(&o->quantization.min_step_over_resolution)},
      {"quantization_resolvable_sigmas", number(&o->quantization.resolvable_sigmas)},
      {"max_claim_correlation", number(&o->max_claim_correlation)},
      {"lab_gate_sigmas", number(&f.lab_gate_sigmas)},
      {"max_gate_passes", integer(&f.max_gate_passes)},
      {"max_calibration_refit_passes", integer(&f.max_calibration_refit_passes)},
      {"max_rotation_passes", integer(&f.max_rotation_passes)},
      {"rotation_second_order_min", number(&f.rotation_second_order_min)},
      {"rotation_rel_change", number(&f.rotation_rel_change)},
      {"pivot_tolerance_s", number(&f.pivot_tolerance_s)},
      {"min_pivot_bins", number(&f.min_pivot_bins)},
      {"pivot_margin_s", number(&f.pivot_margin_s)},
      {"min_grid_bins", integer(&f.min_grid_bins)},
      {"min_slow_blocks", integer(&f.min_slow_blocks)},
      {"min_holdout_bins", integer(&f.min_holdout_bins)},
      {"reference_scale_share_limit", number(&f.reference_scale_share_limit)},
      {"separation_rate_deg_s",
       number(&o->linear_response.excitation_rate_rad_s, units::kDegToRad)},
      {"separation_tilt_deg", number(&o->linear_response.excitation_tilt_rad, units::kDegToRad)},
  };
}

}  // namespace

DiagnoseOptions loadDiagnoseConfig(const std::string& path, std::vector<std::string>* warnings) {
  DiagnoseOptions o;
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  const yf::Context ctx{path, warnings};
  if (!yf::present(root)) return o;  // an empty file: the defaults
  yf::requireMap(ctx, root, "(top level)", root);
  const std::map<std::string, Setter> table = keyTable(&o);
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    const auto it = table.find(key);
    if (it == table.end()) {
      if (warnings)
        warnings->push_back(yf::where(ctx, kv.first) + ": unknown key '" + key + "' ignored");
      continue;
    }
    it->second(ctx, kv.second, key);
  }
  try {
    o.validate();
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  return o;
}

}  // namespace graftnav
