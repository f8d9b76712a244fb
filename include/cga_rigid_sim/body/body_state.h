// BodyState: what changes as one rigid body moves — its motor and its body bivelocity.
// M_WB maps the reference body B (origin at the centre of mass, principal axes) to the world;
// omega_B is Ω_B = −2 M̃ Ṁ (doc/conventions.md (E5)), in B.
#pragma once

#include "cga_rigid_sim/cga/bivelocity.h"
#include "cga_rigid_sim/cga/motor.h"

namespace cga_rigid_sim {
namespace dynamics {

struct BodyState {
  cga::Motor M_WB;
  cga::Bivelocity omega_B;

  bool allFinite() const { return M_WB.allFinite() && omega_B.allFinite(); }
};

}  // namespace dynamics
}  // namespace cga_rigid_sim
