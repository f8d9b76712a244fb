// CurvedInertia: the inertia of a rigid body in a space of constant curvature, "1 up"
// (doc/curved_space.md#inertia).
//
// In the body frame (centre at the origin O = −R e4, axes along the principal axes) the mass
// has the 4×4 second-moment matrix J = Σ m X_B X_Bᵀ = diag(S1, S2, S3, J4) of its 4-d points
// (the off-diagonal J_i4 vanish by the definition of the centre). The inertia map
// I(Ω) = Σ m X_B∧(X_B·Ω) is then diagonal on the basis bivectors,
//   I(e_a∧e_b) = (g_a J_a + g_b J_b) e_a∧e_b = g_a g_b k_ab e_a∧e_b,   k_ab = g_b J_a + g_a J_b,
// g = (1, 1, 1, σ) the metric, and the kinetic energy is T = −½⟨Ω I(Ω)⟩ = ½ Σ k_ab ω_ab² (the
// Manakov form of the free rigid body on so(4) or so(3,1)). The six moments k_ab, in
// Bivector4's order: rotation planes k23 = S2 + S3, k31 = S3 + S1, k12 = S1 + S2 (the Euclidean
// moments of inertia exactly), translation planes k_i4 = J4 + σ S_i.
//
// From a Euclidean body (mass m, principal moments I_i about the centre): S_i = ½ tr I − I_i,
// the spatial second moments, and J4 = Σ m X_4² = m R² − σ tr S (exact for point masses:
// X_4² = R² − σ|X_spatial|² on the space), so k_i4 = m R² − σ (tr S − S_i) → m R² (1 + O(1/R²)).
#pragma once

#include <Eigen/Core>
#include <string>

#include "cga_rigid_sim/body/inertia.h"
#include "cga_rigid_sim/cga/bivector4.h"
#include "cga_rigid_sim/curved/curved_space.h"
#include "cga_rigid_sim/result.h"

namespace cga_rigid_sim {
namespace dynamics {

class CurvedInertia {
 public:
  /// From the body-frame second moments J = (S1, S2, S3, J4) (kg m²). Refuses: mass not finite
  /// or ≤ 0; a moment not finite or negative; J4 ≤ 0 (the body is too large for the space); any
  /// plane moment k_ab ≤ 0 (e.g. two of S1, S2, S3 zero). Messages name `body` and the rule.
  static Result<CurvedInertia> fromSecondMoments(const std::string& body, double mass,
                                                 const Eigen::Vector4d& J,
                                                 const CurvedSpace& space);
  /// From a Euclidean body's mass and principal moments (B's axes), as above.
  static Result<CurvedInertia> fromEuclidean(const std::string& body, const Inertia& euclidean,
                                             const CurvedSpace& space);

  double mass() const { return mass_; }
  int sigma() const { return sigma_; }
  /// (S1, S2, S3, J4), kg m².
  const Eigen::Vector4d& secondMoments() const { return J_; }
  /// The plane moments k_ab > 0 in Bivector4's order (k23, k31, k12, k14, k24, k34), kg m².
  const cga::Bivector4& planeMoments() const { return k_; }
  /// True when S1 = S2 = S3 (within 1e-12 relative): the exact free flow applies.
  bool isotropic() const { return isotropic_; }

  /// L = I(Ω): coefficients k_ab ω_ab on the rotation planes, σ k_i4 ω_i4 on the translation ones.
  cga::Bivector4 momentum(const cga::Bivector4& omega) const;
  /// Ω = I⁻¹(L).
  cga::Bivector4 velocity(const cga::Bivector4& L) const;
  /// T = −½⟨Ω I(Ω)⟩ = ½ Σ k_ab ω_ab².
  double kineticEnergy(const cga::Bivector4& omega) const;

 private:
  double mass_ = 1.0;
  int sigma_ = 1;
  Eigen::Vector4d J_ = Eigen::Vector4d::Ones();
  cga::Bivector4 k_;
  bool isotropic_ = false;
};

}  // namespace dynamics
}  // namespace cga_rigid_sim
