#include "cga_rigid_sim/curved/curved_free_flow.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace {

bool sameState(const CurvedBodyState& a, const CurvedBodyState& b) {
  return a.psi.c == b.psi.c && a.omega_B.rot == b.omega_B.rot && a.omega_B.trans == b.omega_B.trans;
}

}  // namespace

CurvedBodyState curvedIsotropicFlow(const CurvedInertia& inertia, const CurvedBodyState& start,
                                    double t) {
  const int sigma = inertia.sigma();
  // a, b: the means of the (equal) rotation and translation plane moments.
  const double a = inertia.planeMoments().rot.mean();
  const double b = inertia.planeMoments().trans.mean();
  const double mu = 1.0 - sigma * a / b;
  const cga::Bivector4& W0 = start.omega_B;
  const cga::Bivector4 Wr(W0.rot, Eigen::Vector3d::Zero());
  const cga::Rotor4 A = cga::exp((-0.5 * t) * (W0 - mu * Wr), sigma);
  const cga::Rotor4 B = cga::exp((-0.5 * t * mu) * Wr, sigma);
  CurvedBodyState s;
  s.psi = cga::multiply(cga::multiply(start.psi, A, sigma), B, sigma);
  s.omega_B = cga::rotateBack(B, W0, sigma);
  s.omega_B.rot = W0.rot;  // exactly constant (B fixes Ω_r; keep it bit for bit)
  return s;
}

void curvedExactFreeFlow(const CurvedInertia& inertia, double h, CurvedBodyState& state,
                         CurvedFreeFlowCache& cache) {
  if (!cache.valid || cache.h != h || !sameState(cache.last, state)) {
    cache.valid = true;
    cache.anchor = state;
    cache.h = h;
    cache.steps = 0.0;
  }
  cache.steps += 1.0;
  state = curvedIsotropicFlow(inertia, cache.anchor, cache.steps * h);
  cache.last = state;
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
