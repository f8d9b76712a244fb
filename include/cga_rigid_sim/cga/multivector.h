// Multivector: the reference algebra Cl(4,1), all 32 blade coefficients (the test oracle).
//
// Basis (orthonormal, doc/conventions.md#algebra): e1, e2, e3 (square +1), e4 = e (square +1),
// e5 = ē (square −1). A basis blade is named by a bitmask: bit 0 = e1, bit 1 = e2, bit 2 = e3,
// bit 3 = e, bit 4 = ē, with its factors in increasing order; e.g. mask 0b01001 = 9 is e1∧e
// (printed e1^e4), mask 0 is the scalar 1. The conformal null vectors are n = e + ē (infinity)
// and n̄ = e − ē (origin).
//
// The geometric product of two basis blades is ±(blade of a XOR b): the sign counts the swaps
// that put the concatenated factors in increasing order (distinct basis vectors anticommute)
// times the squares of the factors the blades share. The 32×32 table of signs is computed once
// from that rule at compile time (multivector.cc); every product below is the bilinear
// extension of that table, and every other product is a grade projection of the geometric one,
// written literally from its definition. Simple and slow on purpose: this type exists to check
// the hot-path types (Motor, Bivelocity, …) and never enters the simulation loop.
//
// Products (A_r, B_s are the grade-r, grade-s parts of A, B; ⟨·⟩_k is the grade-k projection):
//   geometric      A * B
//   outer          A ^ B = outer(A, B)  = Σ_{r,s} ⟨A_r B_s⟩_{r+s}
//   inner (Hestenes) inner(A, B)        = Σ_{r,s≥1} ⟨A_r B_s⟩_{|r−s|}  (zero if either is scalar)
//   left contraction leftContract(A, B) = Σ_{r≤s} ⟨A_r B_s⟩_{s−r}
//   commutator     commutator(A, B)     = ½(AB − BA)      (A × B of doc/conventions.md)
// For vectors a, b: inner(a, b) = leftContract(a, b) = ½(ab + ba), a ^ b = ½(ab − ba).
//
// Careful: C++ gives operator^ a lower precedence than + - == <<; always parenthesise `(a ^ b)`.
#pragma once

#include <array>
#include <iosfwd>

namespace cga_rigid_sim {
namespace cga {

class Multivector {
 public:
  /// Number of basis blades of Cl(4,1).
  static constexpr unsigned kNumBlades = 32;
  /// Bitmasks of the basis vectors; a blade's mask is the OR of its factors' masks.
  static constexpr unsigned kE1 = 1u << 0;
  static constexpr unsigned kE2 = 1u << 1;
  static constexpr unsigned kE3 = 1u << 2;
  static constexpr unsigned kE = 1u << 3;     ///< e = e4, square +1
  static constexpr unsigned kEbar = 1u << 4;  ///< ē = e5, square −1

  /// The zero multivector.
  Multivector();

  /// s (grade 0).
  static Multivector scalar(double s);
  /// coeff times the basis blade `mask` (mask < 32, factors in increasing order).
  static Multivector blade(unsigned mask, double coeff = 1.0);
  /// The vector e1*e1 + e2*e2 + e3*e3 + e*e + ebar*ē (arguments are coefficients).
  static Multivector vector(double e1, double e2, double e3, double e, double ebar);

  /// Basis vectors and the named elements of doc/conventions.md#algebra.
  static Multivector e1();
  static Multivector e2();
  static Multivector e3();
  static Multivector e();     ///< e4, square +1
  static Multivector ebar();  ///< e5 = ē, square −1
  static Multivector n();     ///< n = e + ē, point at infinity (n² = 0)
  static Multivector nbar();  ///< n̄ = e − ē, origin direction (n̄² = 0, n·n̄ = 2)
  static Multivector I3();    ///< pseudoscalar of 3-space e1e2e3 (I3² = −1)

  /// Coefficient of the basis blade `mask`; throws std::out_of_range if mask >= 32.
  double& operator[](unsigned mask);
  double operator[](unsigned mask) const;

  Multivector& operator+=(const Multivector& b);
  Multivector& operator-=(const Multivector& b);
  Multivector& operator*=(double s);
  Multivector& operator/=(double s);

  /// Reverse Ã: the order of the factors of each blade reversed, i.e. grade k gets the sign
  /// (−1)^(k(k−1)/2). (AB)~ = B̃ Ã.
  Multivector reverse() const;
  /// Grade involution Â: grade k gets the sign (−1)^k.
  Multivector gradeInvolution() const;
  /// Grade projection ⟨A⟩_k (zero for k outside 0..5).
  Multivector grade(int k) const;
  /// ⟨A⟩_0.
  double scalarPart() const;
  /// Euclidean 2-norm of the 32 coefficients, sqrt(Σ c²) (not squared, not an algebra norm);
  /// a magnitude for tolerances.
  double norm2() const;

  /// Grade of the basis blade `mask` (number of factors).
  static int bladeGrade(unsigned mask);

 private:
  std::array<double, kNumBlades> coeffs_;
};

/// Sign of the geometric product of basis blades: blade(a) * blade(b) = sign · blade(a ^ b),
/// sign ∈ {−1, +1} (from the precomputed table).
int basisProductSign(unsigned a, unsigned b);

Multivector operator+(const Multivector& a, const Multivector& b);
Multivector operator-(const Multivector& a, const Multivector& b);
Multivector operator-(const Multivector& a);
/// Mixed with a scalar s: s stands for s·1 (e.g. cos(θ/2) − sin(θ/2) * B).
Multivector operator+(double s, const Multivector& a);
Multivector operator+(const Multivector& a, double s);
Multivector operator-(double s, const Multivector& a);
Multivector operator-(const Multivector& a, double s);
Multivector operator*(double s, const Multivector& a);
Multivector operator*(const Multivector& a, double s);
Multivector operator/(const Multivector& a, double s);

/// Geometric product AB.
Multivector operator*(const Multivector& a, const Multivector& b);
/// Outer (wedge) product A ∧ B; same as outer(a, b). Mind the precedence of ^ (see top).
Multivector operator^(const Multivector& a, const Multivector& b);
/// Outer product Σ_{r,s} ⟨A_r B_s⟩_{r+s}.
Multivector outer(const Multivector& a, const Multivector& b);
/// Hestenes inner product Σ_{r,s≥1} ⟨A_r B_s⟩_{|r−s|}; zero when either side is a scalar.
Multivector inner(const Multivector& a, const Multivector& b);
/// Left contraction A ⌋ B = Σ_{r≤s} ⟨A_r B_s⟩_{s−r}.
Multivector leftContract(const Multivector& a, const Multivector& b);
/// Commutator product A × B = ½(AB − BA).
Multivector commutator(const Multivector& a, const Multivector& b);

/// max over blades of |a_i − b_i| (for comparisons in tests).
double maxAbsDiff(const Multivector& a, const Multivector& b);

/// Σ_{k=0}^{terms−1} A^k / k!: the plain Taylor series of exp (zero if terms < 1). No scaling
/// and squaring, so only for small arguments; tests use it as an independent opinion.
Multivector expSeries(const Multivector& a, int terms);

/// Prints the nonzero blades in the orthonormal basis, by grade then mask, e.g.
/// "1 + 0.5*e1^e4 - 2*e5" (e4 = e, e5 = ē); the zero multivector prints "0". Uses the
/// stream's floating-point format.
std::ostream& operator<<(std::ostream& os, const Multivector& a);

}  // namespace cga
}  // namespace cga_rigid_sim
