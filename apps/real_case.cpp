#include "real_case.h"

#include <fmt/core.h>

#include "graftnav/navigate/real_setup.h"

namespace graftnav::app {
RunMessages printedMessages() {
  RunMessages m;
  m.on_note = [](const std::string& line) { fmt::print(stderr, "{}\n", line); };
  m.on_warning = [](const std::string& w) { fmt::print(stderr, "warning: {}\n", w); };
  return m;
}

CaseInputs loadReal(const std::string& dir) { return loadRealCase(dir, {}, printedMessages()); }

ImuSelection loadImuReal(const CaseInputs& c, const std::string& which,
                         const std::string& profile) {
  return selectRealImu(c, which, profile, true, printedMessages());
}

EstimationProblem problemReal(const CaseInputs& c, const ImuSelection& imu, const RunConfig& rc,
                              const std::optional<OutageScheduleConfig>& outages, bool verbose,
                              std::vector<std::string>* notes) {
  return makeRealProblem(c, imu, rc, outages, verbose ? printedMessages() : RunMessages{}, notes);
}

}  // namespace graftnav::app
