#include "cga_rigid_sim/dynamics/curved_integrator.h"

#include <cmath>

namespace cga_rigid_sim {
namespace dynamics {
namespace {

cga::Bivector4 unitBlade(int k) {
  cga::Bivector4 e;
  e[k] = 1.0;
  return e;
}

// K(τ): L_B += τ (ψ̃ M_W ψ + M_B).
void kick(const CurvedInertia& I, const CurvedLoads& loads, double tau, CurvedBodyState& s) {
  const cga::Bivector4 M_B = cga::rotateBack(s.psi, loads.moment_W, I.sigma()) + loads.moment_B;
  s.omega_B = I.velocity(I.momentum(s.omega_B) + tau * M_B);
}

}  // namespace

// The piece of plane k: Ω = ω e_k, ω = g L_k / k_k (g = g_a g_b: 1 on rotation planes, σ on
// translation planes), θ = τ ω.
//   Rotor: ψ ← ψ exp(−½ θ e_k) = ψ − (v_h ψ + s_h ψ e_k), with s_h = sin(θ/2) (sinh) and
//     v_h = 1 − cos(θ/2) = 2 sin²(θ/4) (or 1 − cosh(θ/2) = −2 sinh²(θ/4)): written as an
//     increment, so its rounding perturbs ψψ̃ by O(ε θ²), not O(ε), and repeated steps do not
//     drift the norm.
//   Momentum: L ← e^{½θe_k} L e^{−½θe_k} = exp(θ ad_{e_k}) L. On the four planes that share one
//     index with e_k, ad_{e_k}² = e_k² (a scalar); it is zero on e_k and its complement. With
//     X = e_k × L and Y = e_k × X = e_k² L_V:
//       e_k² = −1 (a rotation): L ← L + sin θ X + versin θ Y,
//       e_k² = +1 (a boost):    L ← L + sinh θ X + 2 sinh²(θ/2) Y.
void curvedPlanePiece(const CurvedInertia& I, int k, double tau, cga::Rotor4& psi,
                      cga::Bivector4& L) {
  const int sigma = I.sigma();
  const double g = k < 3 ? 1.0 : static_cast<double>(sigma);
  const double theta = tau * g * L[k] / I.planeMoments()[k];
  if (theta == 0.0) return;
  const bool circular = cga::bladeSquare(k, sigma) < 0;
  double s, w, sh, vh;  // sin θ, versin-like term; sin(θ/2), 1 − cos(θ/2)
  if (circular) {
    s = std::sin(theta);
    const double sh2 = std::sin(0.5 * theta);
    w = 2.0 * sh2 * sh2;
    sh = sh2;
    const double q = std::sin(0.25 * theta);
    vh = 2.0 * q * q;
  } else {
    s = std::sinh(theta);
    const double sh2 = std::sinh(0.5 * theta);
    w = 2.0 * sh2 * sh2;
    sh = sh2;
    const double q = std::sinh(0.25 * theta);
    vh = -2.0 * q * q;
  }
  const cga::Bivector4 e = unitBlade(k);
  const cga::Bivector4 X = cga::commutator(e, L, sigma);
  const cga::Bivector4 Y = cga::commutator(e, X, sigma);
  for (int j = 0; j < 6; ++j) L[j] = L[j] + (s * X[j] + w * Y[j]);
  cga::Rotor4 eR;
  eR.c = {0, 0, 0, 0, 0, 0, 0, 0};
  eR.c[k + 1] = 1.0;
  const cga::Rotor4 pe = cga::multiply(psi, eR, sigma);
  for (int j = 0; j < 8; ++j) psi.c[j] = psi.c[j] - (vh * psi.c[j] + sh * pe.c[j]);
}

void CurvedSplittingIntegrator::step(const CurvedInertia& I, const CurvedLoads& loads, double h,
                                     CurvedBodyState& s) {
  const bool kicks = !loads.empty();
  if (kicks) kick(I, loads, 0.5 * h, s);
  cga::Bivector4 L = I.momentum(s.omega_B);
  const double h2 = 0.5 * h;
  // [T14 T24 T34](h/2) R23(h/2) R31(h/2) R12(h) R31(h/2) R23(h/2) [T34 T24 T14](h/2)
  static constexpr int kPlane[11] = {3, 4, 5, 0, 1, 2, 1, 0, 5, 4, 3};
  for (int i = 0; i < 11; ++i) curvedPlanePiece(I, kPlane[i], i == 5 ? h : h2, s.psi, L);
  s.omega_B = I.velocity(L);
  if (kicks) kick(I, loads, 0.5 * h, s);
}

void CurvedExactIntegrator::step(const CurvedInertia& I, const CurvedLoads& loads, double h,
                                 CurvedBodyState& s) {
  const bool kicks = !loads.empty();
  if (kicks) kick(I, loads, 0.5 * h, s);
  curvedExactFreeFlow(I, h, s, cache_);
  if (kicks) kick(I, loads, 0.5 * h, s);
}

Result<std::unique_ptr<CurvedIntegrator>> makeCurvedIntegrator(const std::string& name,
                                                               const CurvedInertia& inertia) {
  if (name == "curved2")
    return std::unique_ptr<CurvedIntegrator>(std::make_unique<CurvedSplittingIntegrator>());
  if (name == "curved_exact") {
    if (!inertia.isotropic())
      return Error("integrator", "curved_exact",
                   "needs an isotropic body (S1 = S2 = S3: a ball, a cube); the free asymmetric "
                   "body in curved space has no closed form here, use curved2");
    return std::unique_ptr<CurvedIntegrator>(std::make_unique<CurvedExactIntegrator>());
  }
  return Error("integrator", name, "unknown curved-space integrator (curved2, curved_exact)");
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
