#include "cga_rigid_sim/body/integrator_auto.h"

#include "cga_rigid_sim/body/at_rest.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace {

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
  if (isAtRest(loads, state.omega_B)) {
    path_ = "at-rest";
    return;
  }
  if (!loads.hasTorque()) {
    path_ = exactPath(inertia.inertiaClass());
    exact_.step(inertia, loads, lambda, h, state);
    return;
  }
  // Torques: the Strang splitting with the exact flow, for every inertia class. Its error is set
  // by the torque alone (none from the spin), so it degrades gracefully with h and with fast
  // spins, where cga4's grows like (h|w|)⁴; it costs more than cga4 for an asymmetric body (the
  // elliptic cache is rebuilt after every kick), and that trade is measured in doc/decisions.md.
  path_ = "exact+kicks";
  exact_.step(inertia, loads, lambda, h, state);
}

void AutoIntegrator::coast(const Inertia& inertia, const Loads& loads, double lambda, double h,
                           double steps, const BodyState& from, BodyState& out) {
  path_ = isAtRest(loads, from.omega_B) ? "at-rest" : exactPath(inertia.inertiaClass());
  exact_.coast(inertia, loads, lambda, h, steps, from, out);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
