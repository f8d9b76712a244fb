// cga2: the second-order symplectic splitting integrator written in motors (the workhorse).
//
// Order 2, symmetric (time-reversible) and symplectic (Lie–Poisson on the body variables).
// One step is the Strang splitting of H = T + V into the loads and the free motion,
//   S(h) = K(h/2) F(h) K(h/2),
// where the kick K(τ) adds τ (I∧n)⁻¹ T to Ω_B (T = applied + gravity moment at the current pose;
// skipped when the body has no loads). The free flow's rotational energy is split about the
// middle principal moment J_r = J2 (axes sorted J1 ≤ J2 ≤ J3), κ_i = 1 − J_i/J_r:
//   Σ L_i²/(2J_i) = |L|²/(2J_r) + κ1 L1²/(2J1) + κ3 L3²/(2J3),
// and every part's flow is an exact motor exponential:
//   D(τ):   the drift of p²/(2m): M ← M exp(−½ τ u∧n), u = v_B/λ — a straight line;
//   C(τ):   the flow of |L|²/(2J_r), a Casimir of the body variables: L_B stays, the body turns by
//           θ = τ |L|/J_r about L_B, M ← M exp(−½ θ I3 L_B/|L|), and v_B turns by −θ about L_B;
//   R_i(τ): the flow of κ_i L_i²/(2J_i): the body turns by φ = τ κ_i L_i/J_i about its principal
//           axis e_i, M ← M exp(−½ φ I3 e_i), and L_B and v_B turn by −φ about e_i
//           (world L and world v are fixed by every part);
// composed symmetrically as
//   F(h) = D(h/2) C(h) R1(h/2) R3(h) R1(h/2) D(h/2).
// C commutes with every R_i (|L|² Poisson-commutes with all body functions), so it needs no
// symmetric placement, and the splitting error comes from R1 and R3 alone, whose coefficients
// 1/J1 − 1/J2 and 1/J2 − 1/J3 are the body's departures from a sphere: a symmetric body (J1 = J2
// or J2 = J3) is integrated exactly, and a nearly symmetric one nearly so. (Fassò 2003, "Comparison
// of splitting algorithms for the rigid body", J. Comput. Phys. 189, compares such second-order
// splittings by their energy error; the three-axis split it replaced: doc/decisions.md, "the split
// about the middle moment".) Because the rotational parts keep v_W fixed, the
// two drifts merge into one body translation by h v_B at the start of F (M T_B(a) R T_B(R̃ a R) = M
// T_B(2a) R): the drifts add up to h v_W exactly.
//
// Conserved exactly (to round-off): |L| (every part turns L_B by an exact rotation or leaves it),
// world L and p when there are no loads, M M̃ = 1; the energy has no drift (it stays within
// O(h²) of its initial value for exponentially long times). The centre of mass follows the exact
// ballistic motion (straight line, or parabola under uniform gravity: the kicks are exact for
// constant acceleration) to round-off, whatever the spin. Exact for a rotation about a principal
// axis and for every torque-free symmetric body.
#pragma once

#include <Eigen/Core>

#include "cga_rigid_sim/body/integrator.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace splitting {

/// Per-body data of the splitting methods, recomputed when the principal moments change (checked
/// each step): the ratios J_k/J_j, J_j/J_k that turn w with L_B about each axis e_i
/// ((i, j, k) cyclic; ratio[2i], ratio[2i + 1]), κ_i = 1 − J_i/J2 and g_i = J_i/J2 (L_B/J2 = g w).
struct Cache {
  Eigen::Vector3d J = Eigen::Vector3d::Zero();
  double ratio[6] = {0, 0, 0, 0, 0, 0};
  Eigen::Vector3d inv_J = Eigen::Vector3d::Zero();  ///< 1/J_i, for the kicks' Δw = τ T/J
  double kappa[3] = {0, 0, 0};  ///< κ_i = 1 − J_i/J2: R_i turns by τ κ_i w_i
  double g[3] = {0, 0, 0};      ///< J_i/J2: C turns about ½ τ g w = ½ τ L_B/J2
  /// A world couple carried in body axes from one step to the next (composeStrang): the couple
  /// turned into the axes the last step ended in, and the numbers the next step's rotations need,
  /// with what they were formed for. Used only when the world couple, the rotor and w are
  /// bitwise those the last step left, and for at most kMaxSteps steps after a turn from the
  /// world; otherwise the couple is turned from the world afresh.
  struct CarriedCouple {
    static constexpr int kMaxSteps = 1024;
    double c_B[3] = {0, 0, 0};       ///< R̃ c_W, turned with the body
    double LL = 0, Lc = 0, cc = 0;   ///< |L_B|², L_B·c_B, |c|², L_B = J w
    double c_W[3] = {0, 0, 0};       ///< the world couple
    double rotor[4] = {0, 0, 0, 0};  ///< the rotor (Eigen's x, y, z, w); no rotor is 0
    double w[3] = {0, 0, 0};
    int age = kMaxSteps;  ///< steps since the turn from the world; kMaxSteps: not valid
  };
  CarriedCouple couple;
};

/// One step h of the symmetric composition S(γ_1 h) ∘ … ∘ S(γ_s h) of the Strang step S above
/// (γ_1 is applied first). Adjacent kicks are merged; when the body has no loads, all the free
/// flows merge into one drift by h v_B, one C(h) (C commutes with the axis parts) and one rotor
/// (adjacent R1 pieces merge), so a composition of s stages costs 2s + 1 axis rotations and one
/// rotation about L_B. When every load is a world-axes load at the centre of mass (gravity,
/// pushes through the centre, couples: Loads::worldSums), the centre's motion does not depend on
/// the turning and is done once per step in closed form (the composition's drifts add up to the
/// exact parabola for any γ with Σγ = 1); without a couple the turning is then the free one
/// (merged as above), with one the stages' flows and kicks alternate with the couple carried in
/// body axes, from stage to stage and from step to step (Cache::CarriedCouple), and the motor
/// updated once per step. cga2 is s = 1, γ = {1}; cga4 composes three stages (s = 1 and 3 are
/// merged; other s run stage by stage). Requires Σγ = 1 for the drift merge.
void composeStrang(const Inertia& inertia, const Loads& loads, double lambda, double h,
                   const double* gamma, int stages, Cache& cache, BodyState& state);

}  // namespace splitting

/// A free-body integrator that steps by splitting::composeStrang with one set of coefficients γ:
/// cga2 below (γ = {1}) and cga4 (integrator_cga4.h) are this one class with their own γ.
class StrangCompositionIntegrator : public Integrator {
 public:
  /// `name` and `gamma` (`stages` numbers, Σγ = 1) must outlive the integrator.
  StrangCompositionIntegrator(const char* name, const double* gamma, int stages)
      : name_(name), gamma_(gamma), stages_(stages) {}
  const char* name() const override { return name_; }
  void step(const Inertia& inertia, const Loads& loads, double lambda, double h,
            BodyState& state) override;
  void reset() override { cache_ = splitting::Cache(); }

 private:
  const char* name_;
  const double* gamma_;
  int stages_;
  splitting::Cache cache_;
};

/// cga2: one Strang step per step (γ = {1}).
class Cga2Integrator : public StrangCompositionIntegrator {
 public:
  Cga2Integrator();
};

}  // namespace dynamics
}  // namespace cga_rigid_sim
