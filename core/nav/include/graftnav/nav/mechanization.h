#pragma once
// Strapdown mechanization in the local-level NED frame from angle and velocity increments.
// The one mechanization every estimator of graftnav uses (EKF, RTS, factor-graph output).
//
// Per step k (interval t_{k-1} -> t_k), with previous and current increments:
//  velocity: dv_fb = dv_k + 1/2 dtheta_k x dv_k + 1/6 dtheta_k x (dtheta_k x dv_k)
//            + 1/12 (dtheta_{k-1} x dv_k + dv_{k-1} x dtheta_k)
//            (rotation and two-sample sculling), rotated to n with the mid-interval n-frame
//            rotation (I - 1/2 zeta x), zeta = (omega_ie_n + omega_en_n) dt, plus gravity and
//            Coriolis evaluated at the extrapolated mid-interval state.
//  position: mid-point (trapezoidal) update of h, lat, lon with the mean velocity.
//  attitude: q_nb_k = exp(-zeta) q_nb_{k-1} exp(phi_k),
//            phi_k = dtheta_k + 1/12 dtheta_{k-1} x dtheta_k (two-sample coning),
//            zeta recomputed at the mid-interval position and velocity after the update.

#include "graftnav/nav/types.h"

namespace graftnav {

class Strapdown {
 public:
  explicit Strapdown(const NavState& initial);

  // Advances the state by one IMU sample. The first sample after construction or reset() uses
  // no coning/sculling memory (the previous increments are taken as equal to the current).
  void step(const ImuSample& imu);

  // Replaces the state (closed-loop feedback) keeping the increment memory.
  void setState(const NavState& s) { state_ = s; }
  // Replaces the state and forgets the increment memory.
  void reset(const NavState& s);

  const NavState& state() const { return state_; }
  // The last sample used (after bias/scale correction by the caller, if any).
  const ImuSample& lastSample() const { return prev_; }

 private:
  NavState state_;
  ImuSample prev_;
  bool has_prev_ = false;
};

// Pure-function form of one step, useful for tests and for preintegration cross-checks.
NavState strapdownStep(const NavState& s, const ImuSample& prev, const ImuSample& cur);

}  // namespace graftnav
