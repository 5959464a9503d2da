#include "real_case.h"

#include <fmt/core.h>

#include <cmath>

#include "graftnav/nav/rotation.h"

namespace graftnav::app {

void printLines(const std::string& prefix, const std::string& text) {
  if (text.empty()) return;
  std::size_t a = 0;
  while (a < text.size()) {
    std::size_t b = text.find('\n', a);
    if (b == std::string::npos) b = text.size();
    fmt::print(stderr, "{}{}\n", prefix, text.substr(a, b - a));
    a = b + 1;
  }
}

// Loads the case (real read policies) and prints every reader condition.
CaseInputs loadReal(const std::string& dir) {
  CaseLoadOptions lo;
  lo.lenient = true;
  CaseInputs c = loadCaseInputs(dir, lo);
  fmt::print(stderr, "read {} (real read policies): {} GNSS epochs, reference {} ({} epochs)\n",
             dir, c.gnss.size(), c.reference_name.empty() ? "none" : c.reference_name,
             c.reference.size());
  if (c.warnings.empty()) fmt::print(stderr, "  readers: no repair and no warning\n");
  for (const auto& w : c.warnings) printLines("  reader/case: ", w);
  return c;
}

ImuSelection loadImuReal(const CaseInputs& c, const std::string& which,
                         const std::string& profile) {
  ImuSelection s = selectImu(c, which, profile, true);
  fmt::print(stderr, "IMU '{}' {}: {} samples, profile '{}'\n", which, s.path, s.imu.size(),
             s.label);
  if (s.read_summary.empty()) {
    fmt::print(stderr, "  reader: no repair and no warning\n");
  } else {
    printLines("  reader: ", s.read_summary);
  }
  return s;
}

EstimationProblem problemReal(const CaseInputs& c, const ImuSelection& imu, const RunConfig& rc,
                              const std::optional<OutageScheduleConfig>& outages, bool verbose,
                              std::vector<std::string>* notes_out) {
  std::vector<std::string> notes;
  EstimationProblem pr = makeProblem(c, imu, rc, outages, &notes);
  startAtInitialState(&pr, &notes);
  if (verbose) {
    for (const auto& n : notes) fmt::print(stderr, "  note: {}\n", n);
    if (rc.alignment.mode == "static" && c.config.initial_state) {
      const double yaw_case = eulerFromQuat(c.config.initial_state->q_nb).z() * kRadToDeg;
      const double yaw_used = eulerFromQuat(pr.initial.q_nb).z() * kRadToDeg;
      const double d = std::remainder(yaw_used - yaw_case, 360.0);
      fmt::print(
          stderr,
          "  {}: {} alignment from the data: yaw {:.1f} deg at t={:.3f} (case.yaml initial_state: "
          "{:.1f} deg at t={:.3f}; difference {:.1f} deg{})\n",
          std::abs(d) > 5.0 ? "WARNING" : "note", rc.alignment.mode, yaw_used, pr.initial.t_s,
          yaw_case, c.config.initial_state->t_s, d,
          std::abs(d) > 5.0 ? ": the case's initial heading is NOT used" : "");
    }
  }
  if (notes_out) notes_out->insert(notes_out->end(), notes.begin(), notes.end());
  return pr;
}

}  // namespace graftnav::app
