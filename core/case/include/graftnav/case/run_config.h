#pragma once
// The run config (`--run-config FILE` of navigate, compare, evaluate, diagnose, real, real-sg;
// configs/navigate.yaml), parsed in ONE place into typed option structs. Each top-level section
// maps to one struct:
//
//   outages:              # GNSS outage schedule (OutageScheduleConfig)
//     length_s: 60
//     period_s: 180
//     start_s: 300        # first outage start after the first IMU epoch (warm-up)
//     end_margin_s: 10
//     windows: [[456700, 456760], ...]   # optional explicit list (s of week), overrides the above
//     enabled: true
//   ekf:                  # EkfOptions + alignment
//     covariance_interval_s: 0.05
//     record_interval_s: 1.0
//     gate_probability: 0.999
//     max_consecutive_rejections: 5
//     gnss_std_scale: 1.0
//     gnss_std_floor_m: 0.005
//     gnss_default_std_m: 0.05
//     init_pos_std_m: 0.5
//     init_vel_std_m_s: 0.1
//     init_roll_pitch_std_deg: 0.1
//     init_heading_std_deg: 0.5
//     alignment: given    # given | static | motion
//     static_alignment_s: 60
//     motion_min_speed_m_s: 3.0
//     motion_max_std_m: 0.5   # in-motion alignment only from epochs this precise (default: all)
//   fgo:                  # FgoOptions (graftnav/estimation/fgo_options.h, docs/fgo.md)
//     earth_rotation: true
//     max_node_spacing_s: 1.0
//     robust_loss: huber  # huber | cauchy | none
//     robust_loss_scale: 3.0
//     chi2_threshold: 16.27
//     window_nodes: 10
//     window_fixed_lag_output: false
//     compute_covariance: false
//     (and the other FgoOptions fields by their names)
//   gnss:                 # GnssSelectionOptions (eval/gnss_selection.h), applied by makeProblem
//     fix_types: [1, 4, 5]          # accepted fix types (empty/absent: all)
//     max_horizontal_std_m: 5.0     # reject epochs with max(std_N, std_E) above this
//     max_vertical_std_m: 20.0
//     latency_s: 0.0                # time-tag latency (t = t_tag - latency) of other fix types
//     latency_s_by_fix_type: {4: 0.4, 5: 0.4}
//     checkpoint_fix_types: [4]     # withheld epochs of these types = outage check points
//     min_spacing_s: 0.05           # of two epochs closer than this keep the more precise one
//   grafting:             # evaluate, real-sg, diagnose (GraftingConfig)
//     start_offset_s: -1
//     realizations: 20
//     outage_shifts: 1
//   time_range:           # optional: navigate only [start_s, end_s] (s of week; either may be absent;
//                         # navigate, compare and real apply it, every other command and
//                         # real's latency study refuse it)
//     start_s: 456300
//     end_s: 457000
//   evaluation:
//     nees_interval_s: 1.0
//     csv_rate_hz: 10     # per-epoch error CSV rate (statistics always use every epoch)
//   odometer:             # vehicle aiding (AidingConfig, aiding_config.h, docs/aiding.md)
//     enabled: true
//   nhc:
//     enabled: true
//
// The same schema is read from a file, from YAML text or a YAML node (a batch manifest's option
// axis, the Python module's options={...}), and as overrides given by dotted keys
// ("ekf.gate_probability" -> 0.99) applied over a config: the same validation and the same
// messages naming the source, line and dotted key. A wrong type or invalid value throws
// std::runtime_error; an unknown key is reported (RunConfigReport), never silently dropped.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "graftnav/case/aiding_config.h"
#include "graftnav/estimation/alignment.h"
#include "graftnav/estimation/estimator_registry.h"
#include "graftnav/eval/evaluation.h"
#include "graftnav/eval/gnss_selection.h"
#include "graftnav/eval/outage_schedule.h"

namespace graftnav {

// Where the filter's initial attitude comes from (run config `ekf.alignment`): the truth or
// case.yaml's initial_state (given), a static span at the start of the IMU record (static), or
// the GNSS velocity once the vehicle moves (motion).
enum class AlignmentMode { kGiven, kStatic, kMotion };
// The run config's word for a mode: "given", "static" or "motion".
const char* alignmentModeName(AlignmentMode mode);
// Sets *out from its run-config word; false for any other text.
bool parseAlignmentMode(const std::string& text, AlignmentMode* out);

struct AlignmentConfig {
  AlignmentMode mode = AlignmentMode::kGiven;
  double static_duration_s = 60.0;
  MotionAlignmentOptions motion;
  // In-motion alignment uses only GNSS epochs with max(std_N, std_E) <= this (single-point fixes
  // at 10 Hz with metre noise fake speeds of tens of m/s at rest).
  double motion_max_std_m = 1e9;
};

struct EvaluationConfig {
  EvaluationOptions options;
  double csv_rate_hz = 10.0;
};

struct GnssConfig {
  bool given = false;  // a gnss: section was present
  GnssSelectionOptions selection;
  std::vector<int> checkpoint_fix_types;  // empty: no check point evaluation
};

struct GraftingConfig {
  // Where the field test starts in the tiled lab static record (s); negative: drawn from the
  // grafting seed. 0 pairs field sample k with lab static sample k, for common-random-number
  // experiments whose lab record shares the field noise (sim key lab.common_random_numbers).
  double start_offset_s = -1.0;
  // Grafted realizations per strategy (K) and outage-schedule shifts (N) of `evaluate`; the
  // command-line flags override them. sg/realization.h says what a realization varies.
  int realizations = 20;
  int outage_shifts = 1;
};

// The part of the data to navigate (GNSS seconds of week); absent bounds mean the data's own.
struct TimeRangeConfig {
  std::optional<double> start_s, end_s;
  bool empty() const { return !start_s && !end_s; }
  double startS() const { return start_s.value_or(-1e300); }
  double endS() const { return end_s.value_or(1e300); }
  // An IMU sample is kept when its interval [t_s - dt_s, t_s] lies in the range (its start within
  // 1 us of the range's start); a GNSS epoch when its time does.
  bool keepsImuSample(double t_s, double dt_s) const {
    return t_s - dt_s >= startS() - 1e-6 && t_s <= endS();
  }
  bool keepsGnssEpoch(double t_s) const { return t_s >= startS() && t_s <= endS(); }
};
// Command-line bounds override the run config's; throws std::runtime_error when the end is not
// after the start.
TimeRangeConfig mergeTimeRange(const TimeRangeConfig& from_config, const TimeRangeConfig& from_cli);
// For a command that does not apply a run config's time_range (every command but navigate,
// compare and real without a latency study): throws std::runtime_error when `range` sets a
// bound, naming the key, the command ("graftnav evaluate") and the run config `source` (its
// file), so that the command fails before it starts instead of running the whole recording.
void requireTimeRangeUnset(const TimeRangeConfig& range, const std::string& source,
                           const std::string& command);

// The estimators' own sections (ekf:, fgo:) are its EstimatorOptions base, so a run config is
// handed to any estimator of the registry as it is.
struct RunConfig : EstimatorOptions {
  TimeRangeConfig time_range;
  OutageScheduleConfig outages;
  bool outages_given = false;  // an outages: section was present
  AlignmentConfig alignment;
  EvaluationConfig evaluation;
  GnssConfig gnss;
  GraftingConfig grafting;
  AidingConfig aiding;  // odometer and NHC, off unless enabled (makeProblem hands them on)
};

// What parsing found besides the values: printable warnings ("source:line: unknown key 'ekf.x'
// ignored") and the unknown keys themselves, dotted ("ekf.x"), so that a caller can refuse them.
struct RunConfigReport {
  std::vector<std::string> warnings;
  std::vector<std::string> unknown_keys;
};

// Loads the file. Unknown keys are appended to *warnings.
RunConfig loadRunConfig(const std::string& path, std::vector<std::string>* warnings = nullptr);

// The sections of `root` (a YAML map, or null for an empty config) read over `base`: a key not
// given keeps base's value. `source` names the origin in messages (a file path, "manifest.yaml
// options", "options").
RunConfig parseRunConfig(const YAML::Node& root, const std::string& source,
                         RunConfigReport* report = nullptr, const RunConfig& base = {});
// The same from YAML text; a syntax error names source and line.
RunConfig parseRunConfigText(const std::string& yaml_text, const std::string& source,
                             RunConfigReport* report = nullptr, const RunConfig& base = {});

// Overrides by dotted key over `base`: {"ekf.gate_probability", 0.99} sets that key,
// {"outages", {length_s: 30}} a section's keys. Each value is a YAML node (its line is kept in
// messages when it comes from a file) or YAML text ("0.99", "[1, 4]", "{length_s: 30}").
using RunConfigOverride = std::pair<std::string, YAML::Node>;
RunConfig applyRunConfigOverrides(const RunConfig& base,
                                  const std::vector<RunConfigOverride>& overrides,
                                  const std::string& source, RunConfigReport* report = nullptr);
RunConfig applyRunConfigOverrides(const RunConfig& base,
                                  const std::vector<std::pair<std::string, std::string>>& overrides,
                                  const std::string& source, RunConfigReport* report = nullptr);

// The top-level sections and, per section, its keys (for documentation and completion).
const std::vector<std::pair<std::string, std::vector<std::string>>>& runConfigSchema();

}  // namespace graftnav
