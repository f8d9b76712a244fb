// The at-rest rule: a moving body with no loads and Ω_B = 0 stays where it is under every
// integrator (the exact solution is M(t) = M), so it need not be stepped. The test is exact
// (zero, not small): a body that moves at all is stepped.
#pragma once

#include "cga_rigid_sim/body/loads.h"
#include "cga_rigid_sim/cga/bivelocity.h"

namespace cga_rigid_sim {
namespace dynamics {

/// `has_loads`: gravity or any applied load acts on the body.
inline bool isAtRest(bool has_loads, const cga::Bivelocity& omega_B) {
  return !has_loads && omega_B.rot.isZero(0.0) && omega_B.trans.isZero(0.0);
}

inline bool isAtRest(const Loads& loads, const cga::Bivelocity& omega_B) {
  return isAtRest(!loads.empty(), omega_B);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
