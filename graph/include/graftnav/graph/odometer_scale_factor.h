#pragma once
// The odometer scale factor s of each node (graftnav/estimation/vehicle_aiding.h) as a random
// walk between consecutive nodes, r = (s_j - s_i) / (q sqrt(T)), and its prior on the first
// node, r = (s - s0) / sigma0. Blocks: s_i[1], s_j[1]; and s[1].

#include <ceres/sized_cost_function.h>

namespace graftnav {

class OdometerScaleWalkFactor final : public ceres::SizedCostFunction<1, 1, 1> {
 public:
  // random_walk (fraction/sqrt(s)) > 0 and dt_s > 0.
  OdometerScaleWalkFactor(double random_walk_per_sqrt_s, double dt_s);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  double inv_sigma_;
};

class OdometerScalePriorFactor final : public ceres::SizedCostFunction<1, 1> {
 public:
  OdometerScalePriorFactor(double s0, double sigma0);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  double s0_, inv_sigma_;
};

}  // namespace graftnav
