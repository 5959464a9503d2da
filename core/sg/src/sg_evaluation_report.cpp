#include "graftnav/sg/sg_evaluation_report.h"

#include <utility>

namespace graftnav {

const SgSolutionErrors* SgEvaluationReport::find(const std::string& label) const {
  for (const auto& s : solutions)
    if (s.label == label) return &s;
  return nullptr;
}

std::optional<DriftStats> SgEvaluationReport::diff(const std::string& label) const {
  const auto* x = find(label);
  const auto* real = find("REAL");
  if (!x || !real) return std::nullopt;
  return relativeDifference(x->err_rms, real->err_rms);
}

SgSolutionErrors SgSolutionErrors::single(const std::string& label, const std::string& imu_file,
                                          Evaluation e) {
  SgSolutionErrors s;
  s.label = label;
  s.imu_file = imu_file;
  s.err_rms = e.outage_rms;
  s.err_max_rms = e.outage_max_rms;
  s.evaluation = std::move(e);
  return s;
}

}  // namespace graftnav
