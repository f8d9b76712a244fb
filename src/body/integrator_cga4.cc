#include "cga_rigid_sim/body/integrator_cga4.h"

#include <cmath>

namespace cga_rigid_sim {
namespace dynamics {
namespace {

// Yoshida's triple jump: γ = (a, 1 − 2a, a), a = 1/(2 − 2^(1/3)). (Σγ = 1, Σγ³ = 0.)
const double kA = 1.0 / (2.0 - std::cbrt(2.0));
const double kGamma[3] = {kA, 1.0 - 2.0 * kA, kA};
constexpr int kStages = 3;

}  // namespace

Cga4Integrator::Cga4Integrator() : StrangCompositionIntegrator("cga4", kGamma, kStages) {}

}  // namespace dynamics
}  // namespace cga_rigid_sim
