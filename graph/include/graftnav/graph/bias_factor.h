#pragma once
// First-order Gauss-Markov bias factor between consecutive nodes (docs/fgo.md, section 3):
//   r_g = (bg_j - phi_g bg_i) / sigma_gd,   phi_g = exp(-T/tau_g),
//   sigma_gd = sigma_g sqrt(1 - phi_g^2)    (exact discretization of the continuous process)
// and the same for the accelerometer. tau = 0 or infinity selects a random walk with
// sigma_d = sigma sqrt(T) (sigma then in units per sqrt(s)). Blocks: bg_i, ba_i, bg_j, ba_j.

#include <ceres/sized_cost_function.h>

namespace graftnav {

struct BiasProcess {
  double sigma = 0.0;  // steady-state 1-sigma (GM) or random-walk density (per sqrt(s))
  double tau_s = 0.0;  // correlation time; <= 0 or inf: random walk
  // Transition phi and driving-noise 1-sigma over an interval T.
  void discretize(double T_s, double* phi, double* sigma_d) const;
};

class BiasFactor final : public ceres::SizedCostFunction<6, 3, 3, 3, 3> {
 public:
  BiasFactor(const BiasProcess& gyro, const BiasProcess& accel, double dt_s);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  double phi_g_, inv_sigma_g_, phi_a_, inv_sigma_a_;
};

}  // namespace graftnav
