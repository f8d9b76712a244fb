#include "cga_rigid_sim/curved/curved_integrator.h"

#include <cmath>

namespace cga_rigid_sim {
namespace dynamics {
namespace {

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
// Every trigonometric value comes from the quarter angle (one sin and one cos):
//   s_h = 2 sin(θ/4) cos(θ/4), cos(θ/2) = 1 − 2 sin²(θ/4), sin θ = 2 s_h cos(θ/2),
//   versin θ = 2 s_h²  (and the same with sinh, cosh and 1 + 2 sinh²(θ/4)).
// The products with e_k are the signed permutations of cga::bladeAction.
namespace {

struct Pieces {
  double L[6];
  double psi[8];
};

inline void planePiece(const cga::BladeAction& a, bool circular, double moment, double g, int k,
                       double tau, Pieces& p) {
  const double theta = tau * g * p.L[k] / moment;
  if (theta == 0.0) return;
  const double q4 = circular ? std::sin(0.25 * theta) : std::sinh(0.25 * theta);
  const double c4 = circular ? std::cos(0.25 * theta) : std::cosh(0.25 * theta);
  const double sh = 2.0 * q4 * c4;                              // sin(θ/2) or sinh(θ/2)
  const double vh = circular ? 2.0 * q4 * q4 : -2.0 * q4 * q4;  // 1 − cos(θ/2) or 1 − cosh
  const double s = 2.0 * sh * (1.0 - vh), w = 2.0 * sh * sh;    // sin θ, versin θ (sinh …)
  double X[6];
  for (int m = 0; m < 6; ++m) X[m] = a.bracketSign[m] * p.L[a.bracketIndex[m]];
  for (int m = 0; m < 6; ++m) p.L[m] += s * X[m] + w * (a.bracketSign[m] * X[a.bracketIndex[m]]);
  double pe[8];
  for (int m = 0; m < 8; ++m) pe[m] = a.rightSign[m] * p.psi[a.rightIndex[m]];
  for (int m = 0; m < 8; ++m) p.psi[m] -= vh * p.psi[m] + sh * pe[m];
}

}  // namespace

void curvedPlanePiece(const CurvedInertia& I, int k, double tau, cga::Rotor4& psi,
                      cga::Bivector4& L) {
  const int sigma = I.sigma();
  Pieces p;
  for (int m = 0; m < 6; ++m) p.L[m] = L[m];
  for (int m = 0; m < 8; ++m) p.psi[m] = psi.c[m];
  planePiece(cga::bladeAction(k, sigma), cga::bladeSquare(k, sigma) < 0, I.planeMoments()[k],
             k < 3 ? 1.0 : sigma, k, tau, p);
  for (int m = 0; m < 6; ++m) L[m] = p.L[m];
  for (int m = 0; m < 8; ++m) psi.c[m] = p.psi[m];
}

void CurvedSplittingIntegrator::step(const CurvedInertia& I, const CurvedLoads& loads, double h,
                                     CurvedBodyState& s) {
  const bool kicks = !loads.empty();
  if (kicks) kick(I, loads, 0.5 * h, s);
  const int sigma = I.sigma();
  const cga::Bivector4 L0 = I.momentum(s.omega_B);
  Pieces p;
  for (int m = 0; m < 6; ++m) p.L[m] = L0[m];
  for (int m = 0; m < 8; ++m) p.psi[m] = s.psi.c[m];
  const cga::Bivector4& moments = I.planeMoments();
  // [T14 T24 T34](h/2) R23(h/2) R31(h/2) R12(h) R31(h/2) R23(h/2) [T34 T24 T14](h/2)
  static constexpr int kPlane[11] = {3, 4, 5, 0, 1, 2, 1, 0, 5, 4, 3};
  const double h2 = 0.5 * h;
  for (int i = 0; i < 11; ++i) {
    const int k = kPlane[i];
    planePiece(cga::bladeAction(k, sigma), cga::bladeSquare(k, sigma) < 0, moments[k],
               k < 3 ? 1.0 : sigma, k, i == 5 ? h : h2, p);
  }
  cga::Bivector4 L;
  for (int m = 0; m < 6; ++m) L[m] = p.L[m];
  for (int m = 0; m < 8; ++m) s.psi.c[m] = p.psi[m];
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
