#include "graftnav/eval/solution_spool.h"

#include <algorithm>
#include <stdexcept>

#include "graftnav/io/record_spool.h"

namespace graftnav {
namespace {
constexpr std::size_t kSigmaDoubles = 9;
constexpr std::size_t kBlock = 2048;
}  // namespace

SolutionSpool::SolutionSpool(const std::string& directory)
    : states_(directory), sigma_(std::make_shared<RecordSpool>(kSigmaDoubles, directory)) {}

void SolutionSpool::add(const NavState& state, const PvaSigma* sigma,
                        const ImuErrorEstimate& /*sensors*/) {
  add(state, sigma);
}

void SolutionSpool::add(const NavState& state, const PvaSigma* sigma) {
  if (size() == 0) with_sigma_ = sigma != nullptr;
  if ((sigma != nullptr) != with_sigma_)
    throw std::invalid_argument("SolutionSpool: a sigma at some epochs only");
  states_.add(state);
  if (sigma) sigma_->append(sigma->data());
}

void SolutionSpool::finish() {
  states_.finish();
  sigma_->finish();
}

SolutionSpool::SigmaPass::SigmaPass(std::shared_ptr<const RecordSpool> spool)
    : pass_(std::move(spool), kBlock) {}

bool SolutionSpool::SigmaPass::next(PvaSigma* sigma) {
  const double* r = pass_.next();
  if (r == nullptr) return false;
  *sigma = Eigen::Map<const PvaSigma>(r);
  return true;
}

void spoolSolution(const NavSolution& solution, SolutionSpool* spool) {
  const bool with_sigma = solution.sigma.size() == solution.states.size();
  for (std::size_t k = 0; k < solution.states.size(); ++k)
    spool->add(solution.states[k], with_sigma ? &solution.sigma[k] : nullptr);
  spool->finish();
}

}  // namespace graftnav
