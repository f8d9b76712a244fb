// CurvedBodyState: what changes as one rigid body moves in curved space, "1 up"
// (doc/curved_space.md#pose-and-velocity): its rotor ψ (a point moves as X = ψ X_B ψ̃) and its
// body velocity bivector Ω_B = −2 ψ̃ ψ̇ (so ψ̇ = −½ ψ Ω_B, the sign of doc/conventions.md (E5)),
// six coefficients (w, u): w the angular velocity (body axes), u = v/|R| on e_i∧e4, v the
// velocity of the centre.
#pragma once

#include "cga_rigid_sim/cga/bivector4.h"
#include "cga_rigid_sim/cga/rotor4.h"

namespace cga_rigid_sim {
namespace dynamics {

struct CurvedBodyState {
  cga::Rotor4 psi;
  cga::Bivector4 omega_B;

  bool allFinite() const { return psi.allFinite() && omega_B.allFinite(); }
};

}  // namespace dynamics
}  // namespace cga_rigid_sim
