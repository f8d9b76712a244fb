#include "cga_rigid_sim/dynamics/integrator_auto.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace {

// Whether an asymmetric body under torque takes cga4 instead of the exact flow with kicks.
constexpr bool kAsymmetricTorqueUsesCga4 = false;

const char* exactPath(InertiaClass c) {
  switch (c) {
    case InertiaClass::kSpherical:
      return "exact-spherical";
    case InertiaClass::kSymmetric:
      return "exact-symmetric";
    case InertiaClass::kAsymmetric:
      return "exact-asymmetric";
  }
  return "exact";
}

}  // namespace

void AutoIntegrator::step(const Inertia& inertia, const Loads& loads, double lambda, double h,
                          BodyState& state) {
  if (loads.empty() && state.omega_B.rot.isZero(0.0) && state.omega_B.trans.isZero(0.0)) {
    path_ = "at-rest";
    return;
  }
  if (!loads.hasTorque()) {
    path_ = exactPath(inertia.inertiaClass());
    exact_.step(inertia, loads, lambda, h, state);
    return;
  }
  if (kAsymmetricTorqueUsesCga4 && inertia.inertiaClass() == InertiaClass::kAsymmetric) {
    path_ = "cga4";
    cga4_.step(inertia, loads, lambda, h, state);
    return;
  }
  path_ = "exact+kicks";
  exact_.step(inertia, loads, lambda, h, state);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
