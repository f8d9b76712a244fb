// Quantities derived from a body's state in curved space
// (doc/curved_space.md#conserved-quantities): the 4-d momentum in body and world, the energy, the
// Casimirs of so(4) / so(3,1), and the centre's place. Torque-free, the world momentum L_W = ψ L_B
// ψ̃ (six components) and the energy are conserved; as R → ∞, L_W's translation part divided by R is
// the linear momentum and its rotation part the angular momentum about the origin.
#pragma once

#include <Eigen/Core>

#include "cga_rigid_sim/curved/curved_body_state.h"
#include "cga_rigid_sim/curved/curved_inertia.h"
#include "cga_rigid_sim/curved/curved_space.h"

namespace cga_rigid_sim {
namespace dynamics {

/// L_B = I(Ω_B).
inline cga::Bivector4 curvedBodyMomentum(const CurvedInertia& I, const CurvedBodyState& s) {
  return I.momentum(s.omega_B);
}
/// L_W = ψ L_B ψ̃ (conserved without loads).
inline cga::Bivector4 curvedWorldMomentum(const CurvedInertia& I, const CurvedBodyState& s) {
  return cga::rotate(s.psi, I.momentum(s.omega_B), I.sigma());
}
/// T = ½ Σ k_ab ω_ab².
inline double curvedKineticEnergy(const CurvedInertia& I, const CurvedBodyState& s) {
  return I.kineticEnergy(s.omega_B);
}
/// The two Casimirs of the Lie algebra, unchanged by any rotation L ↦ ψ̃Lψ: ⟨L L⟩ and the
/// pseudoscalar coefficient of L∧L.
inline Eigen::Vector2d curvedCasimirs(const cga::Bivector4& L, int sigma) {
  return {cga::scalarProduct(L, L, sigma), cga::wedge4(L, L)};
}
/// The centre X = ψ O ψ̃ (4-d).
inline Eigen::Vector4d curvedCentre(const CurvedSpace& space, const CurvedBodyState& s) {
  return cga::rotate(s.psi, space.origin(), space.sigma());
}
/// The linear momentum of the Euclidean limit, the translation part of L_W over R (world axes
/// at the origin), kg m/s.
inline Eigen::Vector3d curvedLinearMomentum(const CurvedSpace& space, const cga::Bivector4& L_W) {
  return L_W.trans / space.radius();
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
