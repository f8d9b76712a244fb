// Integrators of one rigid body in curved space, "1 up" (doc/curved_space.md#integrators).
//
// curved2: the second-order symmetric splitting, built like cga2 (integrator_cga2.h). The
//   kinetic energy T = Σ L_ab²/(2 k_ab) is split into its six plane pieces; the flow of one piece
//   is exact: Ω = ω e_ab with ω = g_a g_b L_ab/k_ab constant, the body turns (or boosts) in that
//   plane, ψ ← ψ exp(−½ τ ω e_ab), and L_B ← exp(½τΩ) L_B exp(−½τΩ) (world L_W = ψ L_B ψ̃ fixed).
//   One step is the Strang composition
//     K(h/2) [T14 T24 T34](h/2) R23(h/2) R31(h/2) R12(h) R31(h/2) R23(h/2) [T34 T24 T14](h/2)
//     K(h/2)
//   (the rotation pieces in cga2's order; the translation pieces outermost, as cga2's drift), K
//   the kick L_B += τ (ψ̃ M_W ψ + M_B) of the loads (skipped without loads). Order 2, symmetric,
//   Lie–Poisson: the Casimirs ⟨L L⟩, L∧L and, without loads, the world momentum L_W are kept to
//   round-off; ψψ̃ = 1 to round-off; the energy has no drift (O(h²) bounded). Exact for a body
//   turning in one plane. As R → ∞ it becomes cga2 (the translation pieces become its drift).
// curved_exact: the closed-form flow of an isotropic body (curved_free_flow.h), with the same
//   kicks K(h/2) · K(h/2) around it when there are loads. Refused for other bodies: the free
//   asymmetric body in so(4) is Manakov's top, whose solution needs theta functions of genus 2;
//   curved2 is the integrator for it.
#pragma once

#include <memory>
#include <string>

#include "cga_rigid_sim/curved/curved_body_state.h"
#include "cga_rigid_sim/curved/curved_free_flow.h"
#include "cga_rigid_sim/curved/curved_impulse.h"
#include "cga_rigid_sim/curved/curved_inertia.h"
#include "cga_rigid_sim/result.h"

namespace cga_rigid_sim {
namespace dynamics {

class CurvedIntegrator {
 public:
  virtual ~CurvedIntegrator() = default;
  virtual const char* name() const = 0;
  /// Advances ψ and Ω_B by h under the loads.
  virtual void step(const CurvedInertia& inertia, const CurvedLoads& loads, double h,
                    CurvedBodyState& state) = 0;
};

class CurvedSplittingIntegrator : public CurvedIntegrator {
 public:
  const char* name() const override { return "curved2"; }
  void step(const CurvedInertia& inertia, const CurvedLoads& loads, double h,
            CurvedBodyState& state) override;
};

class CurvedExactIntegrator : public CurvedIntegrator {
 public:
  const char* name() const override { return "curved_exact"; }
  /// Requires inertia.isotropic() (makeCurvedIntegrator checks it).
  void step(const CurvedInertia& inertia, const CurvedLoads& loads, double h,
            CurvedBodyState& state) override;

 private:
  CurvedFreeFlowCache cache_;
};

/// "curved2" or "curved_exact" (the latter only for an isotropic body). Refusals name the
/// integrator and the rule.
Result<std::unique_ptr<CurvedIntegrator>> makeCurvedIntegrator(const std::string& name,
                                                               const CurvedInertia& inertia);

/// The exact flow of one plane piece of the splitting (exposed for tests): plane k (Bivector4
/// storage index), duration τ, on (ψ, L_B).
void curvedPlanePiece(const CurvedInertia& inertia, int k, double tau, cga::Rotor4& psi,
                      cga::Bivector4& L_B);

}  // namespace dynamics
}  // namespace cga_rigid_sim
