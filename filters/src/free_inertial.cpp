#include "graftnav/filters/free_inertial.h"

#include <stdexcept>
#include <string>

#include "graftnav/nav/mechanization.h"

namespace graftnav {

NavSolution runFreeInertial(const EstimationProblem& problem, int output_decimation,
                            const ProgressFn& progress) {
  if (output_decimation < 1) {
    throw std::invalid_argument("runFreeInertial: output_decimation must be >= 1, got " +
                                std::to_string(output_decimation));
  }
  NavSolution sol;
  sol.estimator = "free-inertial";
  sol.gnss_withheld = static_cast<int>(problem.gnss.size());
  Strapdown sd(problem.initial);
  const size_t n = problem.imu.size();
  sol.states.reserve(n / static_cast<size_t>(output_decimation) + 2);
  sol.states.push_back(problem.initial);
  double t_cur = problem.initial.t_s;
  size_t processed = 0;
  const size_t step = std::max<size_t>(1, n / 100);
  for (size_t j = 0; j < n; ++j) {
    const ImuSample& s = problem.imu[j];
    if (progress && j % step == 0) progress(static_cast<double>(j) / n);
    if (s.t_s <= t_cur + 1e-6) continue;
    sd.step(sliceImuSample(s, std::max(s.t_s - s.dt_s, t_cur), s.t_s));
    t_cur = s.t_s;
    if (++processed % static_cast<size_t>(output_decimation) == 0) {
      NavState st = sd.state();
      st.gnss_week = problem.initial.gnss_week;
      sol.states.push_back(st);
    }
  }
  if (processed == 0) {
    throw std::invalid_argument("runFreeInertial: no IMU sample after the initial time " +
                                std::to_string(problem.initial.t_s));
  }
  if (progress) progress(1.0);
  return sol;
}

}  // namespace graftnav
