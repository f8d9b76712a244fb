// Rotor4: an element of the even subalgebra of the "1 up" algebra on e1, e2, e3, e4 with
// e4² = σ (σ = +1: Cl(4,0), the sphere; σ = −1: Cl(3,1), the hyperboloid; doc/curved_space.md).
// A body's pose in curved space is a unit rotor ψ (ψψ̃ = 1) and a point moves as X = ψ X_B ψ̃.
//
// Stored as eight coefficients in the order
//   1, e23, e31, e12, e14, e24, e34, e1234
// (scalar, the bivectors in cga::Bivector4's order, the pseudoscalar I = e1234, I² = σ).
//
// Every operation that depends on the metric takes σ explicitly. The products are the bilinear
// extension of the basis-blade rule (sign of the reordering times the squares of the shared
// factors, e4² = σ), tabulated once per signature (rotor4.cc); tests check them against the
// reference algebra cga::Multivector with e4 ↦ e (σ = +1) or e4 ↦ ē (σ = −1).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>

#include "cga_rigid_sim/cga/bivector4.h"

namespace cga_rigid_sim {
namespace cga {

struct Rotor4 {
  std::array<double, 8> c = {1, 0, 0, 0, 0, 0, 0, 0};

  static Rotor4 identity() { return Rotor4(); }
  static Rotor4 fromCoefficients(const std::array<double, 8>& coeffs) {
    Rotor4 r;
    r.c = coeffs;
    return r;
  }
  double scalar() const { return c[0]; }
  /// The bivector part (coefficients 1..6).
  Bivector4 bivector() const { return Bivector4({c[1], c[2], c[3]}, {c[4], c[5], c[6]}); }
  double pseudoscalar() const { return c[7]; }
  bool allFinite() const {
    for (double x : c)
      if (!std::isfinite(x)) return false;
    return true;
  }
};

/// The signature σ = e4² of a curvature radius R: +1 for R > 0 (sphere), −1 for R < 0.
inline int signatureOfRadius(double R) { return R > 0 ? 1 : -1; }

/// Geometric product ab of two even elements (even again).
Rotor4 multiply(const Rotor4& a, const Rotor4& b, int sigma);
/// Reverse ψ̃: the bivector part changes sign, scalar and pseudoscalar stay.
Rotor4 reverse(const Rotor4& a);
/// ψψ̃ − 1 as a magnitude: max |coefficient| of ψψ̃ − 1 (its bivector part is zero identically).
double unitDrift(const Rotor4& a, int sigma);
/// ψ / sqrt(⟨ψψ̃⟩): a guard only (a unit rotor composed of exact factors needs none).
Rotor4 normalized(const Rotor4& a, int sigma);

/// exp(B) of a bivector, in closed form: with B² = α + βI (scalar plus pseudoscalar; I is
/// central in the even subalgebra), exp(B) = C(B²) + S(B²) B where C(z) = Σ zᵏ/(2k)! = cosh √z
/// and S(z) = Σ zᵏ/(2k+1)! = sinh √z / √z, evaluated on the two real eigenvalues α ± β of the
/// split-complex number z (σ = +1, I² = +1) or on the complex number α + iβ (σ = −1, I² = −1).
/// No invariant decomposition of B is needed; both branches are exact at every B (series only
/// near z = 0).
Rotor4 exp(const Bivector4& B, int sigma);
/// exp(B) for B = θ e_ab a multiple of one basis blade k (storage index 0..5 of Bivector4):
/// cos θ + sin θ e_ab if e_ab² = −1, cosh θ + sinh θ e_ab if e_ab² = +1.
Rotor4 expBlade(int k, double theta, int sigma);
/// e_ab² for the basis bivector of storage index k (0..5): −1, except e_i4² = −σ.
inline int bladeSquare(int k, int sigma) { return k < 3 ? -1 : -sigma; }

/// The actions of one basis bivector e_k (storage index k of Bivector4) as signed permutations,
/// for the hot path of the splitting integrator (derived from the product table):
///   right product:  (ψ e_k).c[m] = rightSign[m] · ψ.c[rightIndex[m]]  (m = 0..7);
///   commutator:     (e_k × L)[m] = bracketSign[m] · L[bracketIndex[m]] (m = 0..5; sign 0 on the
///                   components that commute with e_k: e_k itself and its complementary plane).
struct BladeAction {
  int rightIndex[8];
  double rightSign[8];
  int bracketIndex[6];
  double bracketSign[6];
};
const BladeAction& bladeAction(int k, int sigma);

/// The commutator product A × B = ½(AB − BA) of two bivectors (the Lie bracket of so(4) or
/// so(3,1); again a bivector).
Bivector4 commutator(const Bivector4& A, const Bivector4& B, int sigma);
/// ⟨AB⟩, the scalar part of the product of two bivectors.
double scalarProduct(const Bivector4& A, const Bivector4& B, int sigma);
/// The pseudoscalar coefficient of A∧B (so A∧B = wedge4(A, B) I).
double wedge4(const Bivector4& A, const Bivector4& B);

/// ψ B ψ̃ for a bivector B (a bivector again when ψ is a rotor).
Bivector4 rotate(const Rotor4& psi, const Bivector4& B, int sigma);
/// ψ̃ B ψ (the inverse rotation of a bivector).
Bivector4 rotateBack(const Rotor4& psi, const Bivector4& B, int sigma);
/// ψ v ψ̃ for a vector v (coefficients on e1, e2, e3, e4).
Eigen::Vector4d rotate(const Rotor4& psi, const Eigen::Vector4d& v, int sigma);
/// The 4×4 matrix of v ↦ ψ v ψ̃ (column a = ψ e_a ψ̃).
Eigen::Matrix4d toMatrix(const Rotor4& psi, int sigma);

/// The metric inner product a·b = a1b1 + a2b2 + a3b3 + σ a4b4.
inline double dot(const Eigen::Vector4d& a, const Eigen::Vector4d& b, int sigma) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + sigma * a[3] * b[3];
}
/// The vector v·B (Hestenes' inner product of a vector with a bivector).
Eigen::Vector4d dot(const Eigen::Vector4d& v, const Bivector4& B, int sigma);

}  // namespace cga
}  // namespace cga_rigid_sim
