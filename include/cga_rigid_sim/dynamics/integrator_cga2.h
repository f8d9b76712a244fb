// cga2: the second-order symplectic splitting integrator written in motors (the workhorse).
//
// Order 2, symmetric (time-reversible) and symplectic (Lie–Poisson on the body variables).
// One step is the Strang splitting of H = T + V into the loads and the free motion,
//   S(h) = K(h/2) F(h) K(h/2),
// where the kick K(τ) adds τ (I∧n)⁻¹ T to Ω_B (T = applied + gravity moment at the current pose;
// skipped when the body has no loads), and the free flow of T = Σ L_i²/(2J_i) + p²/(2m) is
// itself split into pieces whose flows are exact motor exponentials:
//   D(τ):   the drift of p²/(2m): M ← M exp(−½ τ u∧n), u = v_B/λ — a straight line;
//   R_i(τ): the flow of L_i²/(2J_i): the body turns by φ = τ L_i/J_i about its principal axis
//           e_i, M ← M exp(−½ φ I3 e_i), and the body-axes L_B and v_B turn by −φ about e_i
//           (world L and world v are fixed by it);
// composed symmetrically as
//   F(h) = D(h/2) R1(h/2) R2(h/2) R3(h) R2(h/2) R1(h/2) D(h/2),
// the splitting of Touma & Wisdom (1994), McLachlan (1993, "Explicit Lie-Poisson integration and
// the Euler equations") and Dullweber, Leimkuhler & McLachlan (1997, J. Chem. Phys. 107, 5840),
// written as motors. Because the rotation pieces keep v_W fixed, the two drifts merge into one
// body translation by h v_B at the start of F (M T_B(a) R T_B(R̃ a R) = M T_B(2a) R): the drifts
// add up to h v_W exactly.
//
// Conserved exactly (to round-off): |L| (every piece turns L_B by an exact rotation), world L
// and p when there are no loads, M M̃ = 1; the energy has no drift (it stays within O(h²) of its
// initial value for exponentially long times). The centre of mass follows the exact ballistic
// motion (straight line, or parabola under uniform gravity: the kicks are exact for constant
// acceleration) to round-off, whatever the spin. Exact for a rotation about a principal axis.
#pragma once

#include <Eigen/Core>

#include "cga_rigid_sim/dynamics/integrator.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace splitting {

/// Per-body data of the splitting methods, recomputed when the principal moments change (checked
/// each step): the ratios J_k/J_j, J_j/J_k that turn w with L_B about each axis e_i
/// ((i, j, k) cyclic; ratio[2i], ratio[2i + 1]).
struct Cache {
  Eigen::Vector3d J = Eigen::Vector3d::Zero();
  double ratio[6] = {0, 0, 0, 0, 0, 0};
  Eigen::Vector3d inv_J = Eigen::Vector3d::Zero();  ///< 1/J_i, for the kicks' Δw = τ T/J
};

/// One step h of the symmetric composition S(γ_1 h) ∘ … ∘ S(γ_s h) of the Strang step S above
/// (γ_1 is applied first). Adjacent kicks are merged; when the body has no loads, all the free
/// flows merge into one drift by h v_B and one rotor (adjacent R1 pieces merge), so a composition
/// of s stages costs 4s + 1 axis rotations. cga2 is s = 1, γ = {1}; cga4 composes three stages
/// (s = 1 and 3 are merged; other s run stage by stage). Requires Σγ = 1 for the drift merge.
void composeStrang(const Inertia& inertia, const Loads& loads, double lambda, double h,
                   const double* gamma, int stages, Cache& cache, BodyState& state);

}  // namespace splitting

class Cga2Integrator : public Integrator {
 public:
  const char* name() const override { return "cga2"; }
  void step(const Inertia& inertia, const Loads& loads, double lambda, double h,
            BodyState& state) override;
  void reset() override { cache_ = splitting::Cache(); }

 private:
  splitting::Cache cache_;
};

}  // namespace dynamics
}  // namespace cga_rigid_sim
