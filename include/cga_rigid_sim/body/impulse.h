// Impulses: a trivector impulse T_imp makes Ω_B jump by ΔΩ_B = (I∧n)⁻¹(T_imp); the motor (the
// pose) does not jump (doc/conventions.md (E17), the impulsive form of (E15)).
#pragma once

#include <Eigen/Core>

#include "cga_rigid_sim/body/body_state.h"
#include "cga_rigid_sim/body/inertia.h"
#include "cga_rigid_sim/cga/force.h"

namespace cga_rigid_sim {
namespace dynamics {

/// Applies a body trivector impulse T_imp_B (coefficients as cga::Moment, in N s and N m s).
inline void applyImpulse(const Inertia& I, const cga::Moment& T_imp_B, double lambda,
                         BodyState& s) {
  s.omega_B += I.solve(T_imp_B, lambda);
}

/// The body trivector of an impulse given in world axes: linear impulse J (as a CGA force
/// vector J + αn, N s) applied at the world point p_W, plus an angular impulse (N m s).
inline cga::Moment impulseMoment_B(const BodyState& s, const cga::Force& J_W,
                                   const Eigen::Vector3d& p_W, const Eigen::Vector3d& angular_W,
                                   double lambda) {
  const Eigen::Quaterniond R_BW = s.M_WB.rotation().conjugate();
  const Eigen::Vector3d r_B = R_BW * (p_W - s.M_WB.translation(lambda));
  return cga::Moment::ofForceAt(R_BW * J_W.f, r_B, lambda) + cga::Moment::couple(R_BW * angular_W);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
