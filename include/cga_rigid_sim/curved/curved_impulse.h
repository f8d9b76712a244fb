// Forces, moments and impulses in curved space, "1 up" (doc/curved_space.md#forces-and-impulses).
//
// A force F (a 4-d vector) acting at the point X of the body has the moment X∧F, a bivector (the
// same element carries the torque and the force, as the 2-up trivector does). Only the part of F
// tangent to the space at X acts: X∧X = 0, so the normal part, F's component along X, drops out
// exactly (the analogue of α in F = f + αn). The body momentum changes by the moment carried
// back into the body, ΔL_B = ψ̃ (X∧F) ψ for an impulse (the pose does not jump), and
// L̇_B = Ω_B × L_B + ψ̃ (X∧F) ψ under a force.
#pragma once

#include <Eigen/Core>

#include "cga_rigid_sim/curved/curved_body_state.h"
#include "cga_rigid_sim/curved/curved_inertia.h"
#include "cga_rigid_sim/curved/curved_space.h"

namespace cga_rigid_sim {
namespace dynamics {

/// The moment X∧F of the force F at the point X (both in the same frame).
inline cga::Bivector4 curvedMomentOfForce(const Eigen::Vector4d& X, const Eigen::Vector4d& F) {
  return cga::wedge(X, F);
}

/// The 4-d point of the body at the body-frame offset s_B (geodesic normal coordinates about the
/// centre: distance |s_B| from the centre along s_B).
inline Eigen::Vector4d curvedBodyPoint(const CurvedSpace& space, const Eigen::Vector3d& s_B) {
  return cga::rotate(space.translator(s_B), space.origin(), space.sigma());
}

/// The tangent vector at the body point X_B of the body-axes direction f_B (the parallel
/// transport of f_B from the centre along the geodesic to X_B): T(s_B) f_B T̃(s_B).
inline Eigen::Vector4d curvedBodyVector(const CurvedSpace& space, const Eigen::Vector3d& s_B,
                                        const Eigen::Vector3d& f_B) {
  Eigen::Vector4d f;
  f << f_B, 0.0;
  return cga::rotate(space.translator(s_B), f, space.sigma());
}

/// An impulse J_W (N s, 4-d, world) at the world point X_W: L_B += ψ̃ (X_W∧J_W) ψ, Ω_B follows.
inline void applyCurvedImpulse_W(const CurvedInertia& I, const Eigen::Vector4d& X_W,
                                 const Eigen::Vector4d& J_W, CurvedBodyState& s) {
  const cga::Bivector4 L_B =
      I.momentum(s.omega_B) + cga::rotateBack(s.psi, curvedMomentOfForce(X_W, J_W), I.sigma());
  s.omega_B = I.velocity(L_B);
}

/// An impulse J_B at the body point X_B, both in body axes: L_B += X_B∧J_B.
inline void applyCurvedImpulse_B(const CurvedInertia& I, const Eigen::Vector4d& X_B,
                                 const Eigen::Vector4d& J_B, CurvedBodyState& s) {
  s.omega_B = I.velocity(I.momentum(s.omega_B) + curvedMomentOfForce(X_B, J_B));
}

/// Loads held over a step: a moment fixed in the world (a force at a fixed world point, or its
/// sum), and one fixed in the body (a thruster), both bivectors X∧F.
struct CurvedLoads {
  cga::Bivector4 moment_W;
  cga::Bivector4 moment_B;
  bool empty() const {
    return moment_W.coefficientNorm() == 0.0 && moment_B.coefficientNorm() == 0.0;
  }
};

}  // namespace dynamics
}  // namespace cga_rigid_sim
