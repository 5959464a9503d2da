#include "graftnav/eval/evaluation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "evaluation_accumulator.h"
#include "graftnav/nav/nav_interp.h"

namespace graftnav {
void EvaluationOptions::validate() const {
  if (!(nees_interval_s >= 0.0)) {
    throw std::invalid_argument("EvaluationOptions: nees_interval_s must be >= 0, got " +
                                std::to_string(nees_interval_s));
  }
  if (!(nees_band_probability > 0.0 && nees_band_probability < 1.0)) {
    throw std::invalid_argument("EvaluationOptions: nees_band_probability must be in (0,1), got " +
                                std::to_string(nees_band_probability));
  }
}

Evaluation evaluateSolution(const NavSolution& solution, const NavSeries& reference,
                            const std::vector<TimeWindow>& outages,
                            const EvaluationOptions& options) {
  options.validate();
  if (solution.states.empty() || reference.empty() ||
      solution.states.back().t_s < reference.front().t_s ||
      solution.states.front().t_s > reference.back().t_s) {
    throw std::invalid_argument("evaluateSolution: solution '" + solution.estimator +
                                "' and the reference do not overlap in time");
  }
  const std::vector<TimeWindow> windows = eval_detail::sortedWindows(outages);

  Evaluation ev;
  ev.epochs.reserve(solution.states.size());
  const bool has_sigma = solution.sigma.size() == solution.states.size();
  eval_detail::EvaluationAccumulator acc(windows, options, &ev,
                                         [&ev](const EpochError& e) { ev.epochs.push_back(e); });
  const NavSeries& sol = solution.states;
  const double sol_rate = eval_detail::seriesRate(sol.size(), sol.front().t_s, sol.back().t_s);
  const double ref_rate =
      eval_detail::seriesRate(reference.size(), reference.front().t_s, reference.back().t_s);
  const bool at_reference = options.epochs == EvaluationEpochs::kReference ||
                            (options.epochs == EvaluationEpochs::kAuto && ref_rate < sol_rate);
  if (!at_reference) {
    NavInterpolator ref_at(reference);
    for (size_t i = 0; i < sol.size(); ++i) {
      const auto ref = ref_at.at(sol[i].t_s);
      if (!ref) continue;
      acc.add(sol[i], has_sigma ? &solution.sigma[i] : nullptr, *ref);
    }
  } else {
    NavInterpolator sol_at(sol);
    size_t k = 0;  // sigma bracket
    for (const NavState& ref : reference) {
      const auto s = sol_at.at(ref.t_s);
      if (!s) continue;
      PvaSigma sg;
      if (has_sigma) {
        while (k + 1 < sol.size() && sol[k + 1].t_s <= ref.t_s) ++k;
        const size_t k1 = std::min(k + 1, sol.size() - 1);
        const double span = sol[k1].t_s - sol[k].t_s;
        const double u = span > 0 ? std::clamp((ref.t_s - sol[k].t_s) / span, 0.0, 1.0) : 0.0;
        sg = (1.0 - u) * solution.sigma[k] + u * solution.sigma[k1];
      }
      acc.add(*s, has_sigma ? &sg : nullptr, ref);
    }
  }
  if (ev.epochs.empty()) {
    throw std::invalid_argument("evaluateSolution: no solution epoch of '" + solution.estimator +
                                "' lies inside the reference span");
  }
  acc.finish();
  return ev;
}

}  // namespace graftnav
