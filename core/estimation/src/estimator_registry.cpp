#include "graftnav/estimation/estimator_registry.h"

#include <algorithm>
#include <stdexcept>

namespace graftnav {

void EstimatorRegistry::add(EstimatorEntry entry) {
  if (entry.name.empty()) throw std::invalid_argument("EstimatorRegistry: empty estimator name");
  if (!entry.run)
    throw std::invalid_argument("EstimatorRegistry: estimator '" + entry.name + "' has no run");
  if (contains(entry.name))
    throw std::invalid_argument("EstimatorRegistry: estimator '" + entry.name +
                                "' is registered twice");
  entries_.push_back(std::move(entry));
}

std::vector<std::string> EstimatorRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& e : entries_) out.push_back(e.name);
  return out;
}

bool EstimatorRegistry::contains(const std::string& name) const {
  return std::any_of(entries_.begin(), entries_.end(),
                     [&](const EstimatorEntry& e) { return e.name == name; });
}

std::string EstimatorRegistry::namesText() const {
  std::string text;
  for (const auto& e : entries_) text += (text.empty() ? "" : ", ") + e.name;
  return text;
}

const EstimatorEntry& EstimatorRegistry::find(const std::string& name) const {
  for (const auto& e : entries_)
    if (e.name == name) return e;
  throw std::invalid_argument("unknown estimator '" + name + "' (known: " + namesText() + ")");
}

NavSolution EstimatorRegistry::run(const std::string& name, const EstimationProblem& problem,
                                   const EstimatorOptions& options,
                                   const ProgressFn& progress) const {
  return find(name).run(problem, options, progress);
}

bool EstimatorRegistry::canStream(const std::string& name) const {
  return static_cast<bool>(find(name).stream);
}

NavSolution EstimatorRegistry::runStreaming(const std::string& name,
                                            const EstimationProblem& problem, const ImuPassFn& imu,
                                            const EstimatorOptions& options,
                                            SolutionSink& sink) const {
  const EstimatorEntry& e = find(name);
  if (!e.stream) throw std::invalid_argument("estimator '" + name + "' has no streamed form");
  return e.stream(problem, imu, options, sink);
}

}  // namespace graftnav
