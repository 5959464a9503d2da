#pragma once
// One navigation run of a case as `graftnav navigate` asks for it: the case, the output folder,
// the IMU, the estimator, the run config and the command-line overrides, with every path already
// resolved. prepareNavigate (navigate_setup.h) turns it into checked inputs, runNavigate
// (navigate_run.h) into the output files.
#include <functional>
#include <string>

#include "graftnav/case/outage_overrides.h"
#include "graftnav/case/run_config.h"

namespace graftnav {

struct NavigateRequest {
  std::string case_dir;
  std::string out_dir;
  std::string imu = "ref";   // "ref", "tested" or the path of an IMU file
  std::string profile_path;  // IMU profile YAML; empty: the one case.yaml names
  std::string estimator = "ekf";
  std::string run_config;             // run config YAML; empty: none
  bool run_config_from_case = false;  // run_config is CASE/run.yaml, picked by default
  OutageOverrides outage;             // over the run config's outages: section
  TimeRangeConfig time_range;         // over the run config's time_range: section
  int decimate = 1;                   // every N-th IMU epoch written
  bool lenient = false;               // real-data read policies (repair/warn instead of error)
};

// Where a run's warnings and notes go (the command prints them on stderr); unset: dropped.
struct RunMessages {
  std::function<void(const std::string&)> on_warning;
  std::function<void(const std::string&)> on_note;
  void warning(const std::string& text) const {
    if (on_warning) on_warning(text);
  }
  void note(const std::string& text) const {
    if (on_note) on_note(text);
  }
};

}  // namespace graftnav
