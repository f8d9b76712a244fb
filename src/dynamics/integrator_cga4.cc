#include "cga_rigid_sim/dynamics/integrator_cga4.h"

#include <cmath>

namespace cga_rigid_sim {
namespace dynamics {
namespace {

#ifndef CGA4_SUZUKI
// Yoshida's triple jump: γ = (a, 1 − 2a, a), a = 1/(2 − 2^(1/3)).
const double kA = 1.0 / (2.0 - std::cbrt(2.0));
const double kGamma[3] = {kA, 1.0 - 2.0 * kA, kA};
constexpr int kStages = 3;
#else
// Suzuki's fractal: γ = (p, p, 1 − 4p, p, p), p = 1/(4 − 4^(1/3)).
const double kP = 1.0 / (4.0 - std::cbrt(4.0));
const double kGamma[5] = {kP, kP, 1.0 - 4.0 * kP, kP, kP};
constexpr int kStages = 5;
#endif

}  // namespace

void Cga4Integrator::step(const Inertia& inertia, const Loads& loads, double lambda, double h,
                          BodyState& state) {
  splitting::composeStrang(inertia, loads, lambda, h, kGamma, kStages, cache_, state);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
