// Inertia: mass and principal moments of one rigid body, and the map Ω ↦ I(Ω)∧n
// (doc/conventions.md (E11)).
//
// In the reference body B (origin at the centre of mass, axes along the principal axes) the
// map is diagonal on the blade coefficients of Bivelocity and Moment:
//   I(Ω)∧n ↔ diag(J1, J2, J3, mλ², mλ², mλ²),
// because wedging with n removes every term of I(Ω) = λ² ∫ρ X∧(X·Ω) that involves third
// moments of the mass (doc/conventions.md#inertia-map-and-kinetic-energy; checked against the
// reference algebra in test/body).
//
// Axis order of B (a free choice, doc/conventions.md#body-frame): spherical — the input axes;
// symmetric — the distinct axis is e3; asymmetric — J1 < J2 < J3. Always right-handed.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

#include "cga_rigid_sim/cga/bivelocity.h"
#include "cga_rigid_sim/cga/moment.h"
#include "cga_rigid_sim/result.h"

namespace cga_rigid_sim {
namespace dynamics {

enum class InertiaClass { kSpherical, kSymmetric, kAsymmetric };
const char* toString(InertiaClass c);

/// What to do with a tensor that breaks the triangle inequality (I1 + I2 ≥ I3).
enum class TrianglePolicy {
  kRefuse,           ///< return an error (default)
  kNearestPhysical,  ///< project the principal moments onto the nearest physical ones, warn
};

/// Principal moments closer than this (relative) are treated as equal: the difference is the
/// round-off of the diagonalisation, and the exact symmetric/spherical paths need equality.
constexpr double kEqualMomentsRelTol = 1e-12;
/// Slack of the triangle inequality check (relative).
constexpr double kTriangleRelSlack = 1e-9;
/// The smallest principal moment must be at least this fraction of the largest. About the
/// thinnest axis ω = L/J turns the round-off of any moment (≈ ε|L|) into a spin of ε|L|/J_min:
/// at this ratio round-off spins it at most ~1e-4 of the body's other rates; a subnormal moment
/// (the URDF fuzz target's 2e-309 kg m²) made it infinite. A solid rod this thin has a
/// radius 4e-7 of its length (J_axial/J_transverse = 6 r²/ℓ²).
constexpr double kMinMomentRatio = 1e-12;

class Inertia {
 public:
  /// Validates and diagonalises. `J_F` is the inertia tensor about the centre of mass in some
  /// frame F (full tensor, off-diagonal terms included). Refuses: mass not finite or ≤ 0; a
  /// tensor with non-finite entries, not symmetric, not positive definite, or breaking the
  /// triangle inequality (unless `policy` relaxes it; then `warning` says what was changed).
  /// Every message names `body` and the rule.
  static Result<Inertia> fromTensor(const std::string& body, double mass,
                                    const Eigen::Matrix3d& J_F,
                                    TrianglePolicy policy = TrianglePolicy::kRefuse,
                                    std::string* warning = nullptr);
  /// Convenience: principal moments along F's axes (a diagonal tensor).
  static Result<Inertia> fromPrincipal(const std::string& body, double mass,
                                       const Eigen::Vector3d& moments);

  /// Mass 1 kg, moments 1 kg m² (a placeholder to be assigned; always valid).
  static Inertia unit() { return Inertia(); }

  double mass() const { return mass_; }
  /// (J1, J2, J3) along B's axes, kg m².
  const Eigen::Vector3d& principalMoments() const { return J_; }
  /// R_FB: x_F = R_FB x_B (B's axes expressed in the input frame F).
  const Eigen::Quaterniond& rotationFromPrincipal() const { return R_FB_; }
  InertiaClass inertiaClass() const { return class_; }

  /// I(Ω)∧n: the momentum trivector (J w, λ m v) of a body bivelocity.
  cga::Moment apply(const cga::Bivelocity& omega_B, double lambda) const {
    return {J_.cwiseProduct(omega_B.rot), (mass_ * lambda * lambda) * omega_B.trans};
  }
  /// (I∧n)⁻¹: the bivelocity change produced by a body trivector (doc/conventions.md (E15)).
  cga::Bivelocity solve(const cga::Moment& T_B, double lambda) const {
    return {T_B.rot.cwiseQuotient(J_), T_B.trans / (mass_ * lambda * lambda)};
  }
  /// (Ω × I(Ω))∧n, the velocity-dependent term of the equation of motion
  /// I(Ω̇)∧n = (Ω × I(Ω))∧n + T: in Euclidean form (J w × w, m v × w).
  cga::Moment gyroscopic(const cga::Bivelocity& omega_B, double lambda) const {
    const Eigen::Vector3d& w = omega_B.rot;
    return {J_.cwiseProduct(w).cross(w), (mass_ * lambda * lambda) * omega_B.trans.cross(w)};
  }
  /// T = −½ Ω·I(Ω) = ½ w·Jw + ½ m v².
  double kineticEnergy(const cga::Bivelocity& omega_B, double lambda) const {
    return 0.5 * (omega_B.rot.dot(J_.cwiseProduct(omega_B.rot)) +
                  mass_ * lambda * lambda * omega_B.trans.squaredNorm());
  }

 private:
  Inertia() = default;
  double mass_ = 1.0;
  Eigen::Vector3d J_ = Eigen::Vector3d::Ones();
  Eigen::Quaterniond R_FB_ = Eigen::Quaterniond::Identity();
  InertiaClass class_ = InertiaClass::kSpherical;
};

}  // namespace dynamics
}  // namespace cga_rigid_sim
