// sin and cos (and versin = 1 − cos) from their Taylor polynomials, for the hot paths that know
// their angle is small or already reduced: the coefficients 1/n! once, and the evaluation
// schemes their callers need, each with the range where its first omitted term is below an ulp.
//   sinCosReduced      |x| ≤ π/2, one reflection      the exact flow's half angles (free_flow_psi.h,
//                                                     elliptic.h), the tree midpoint's
//   sinCosSmall        |x| ≤ 1/16 (1/256: shorter)    a tree joint's angle over one step
//   sinVersin{Fine,Small,Medium}, z = φ² ≤ 2⁻¹⁵, ≤ 1/1024, ≤ 1/4 (Estrin's scheme in z)
//                                                     cga2's axis rotations (splitting_flows.h)
// Each keeps its own order of operations: callers rely on their results to the last bit.
#pragma once

#include <cmath>

#include "cga_rigid_sim/math/constants.h"

namespace cga_rigid_sim {
namespace math {

#define CGA_MATH_ALWAYS_INLINE __attribute__((always_inline)) inline

/// 1/n!, each the double nearest (n! is exact in a double up to 18!).
constexpr double kInv2 = 1.0 / 2.0, kInv3 = 1.0 / 6.0, kInv4 = 1.0 / 24.0, kInv5 = 1.0 / 120.0,
                 kInv6 = 1.0 / 720.0, kInv7 = 1.0 / 5040.0, kInv8 = 1.0 / 40320.0,
                 kInv9 = 1.0 / 362880.0, kInv10 = 1.0 / 3628800.0, kInv11 = 1.0 / 39916800.0,
                 kInv12 = 1.0 / 479001600.0, kInv13 = 1.0 / 6227020800.0,
                 kInv14 = 1.0 / 87178291200.0, kInv15 = 1.0 / 1307674368000.0,
                 kInv16 = 1.0 / 20922789888000.0, kInv17 = 1.0 / 355687428096000.0,
                 kInv18 = 1.0 / 6402373705728000.0;

/// s = sin x, c = cos x for |x| ≤ π/2 (larger |x|: use std::sin, std::cos). The reduction is one
/// reflection, |x| > π/4 → π/2 − |x| (π/2 split in two doubles, so the reflection adds no error
/// beyond the rounding of the difference), and both functions are Taylor polynomials on
/// [−π/4, π/4] whose first omitted terms, (π/4)¹⁹/19! and (π/4)¹⁸/18!, are below 1e-17. Written
/// as y + y·z·P(z) and 1 − z/2 + z²·Q(z) (z = y², the rounding of 1 − z/2 carried along), the
/// leading terms are exact and the corrections small: each result is within 1 ulp of std::sin
/// and std::cos (test/math/sin_cos_test.cc). glibc's sincos first reduces its argument for any
/// double and costs about as much as the rest of a rotor.
inline void sinCosReduced(double x, double& s, double& c) {
  const double ax = std::abs(x);
  const bool reflect = ax > kQuarterPi;
  const double y = reflect ? (kHalfPi - ax) + kHalfPiLo : ax;
  const double z = y * y;
  // sin y = y + y z (−1/3! + z (1/5! − z (1/7! − …)))
  const double ps =
      -kInv3 +
      z * (kInv5 +
           z * (-kInv7 + z * (kInv9 + z * (-kInv11 + z * (kInv13 + z * (-kInv15 + z * kInv17))))));
  // cos y = 1 − z/2 + z² (1/4! − z (1/6! − …))
  const double pc =
      kInv4 +
      z * (-kInv6 +
           z * (kInv8 + z * (-kInv10 + z * (kInv12 + z * (-kInv14 + z * (kInv16 + z * -kInv18))))));
  const double sy = y + y * z * ps;
  const double half_z = 0.5 * z;
  const double hi = 1.0 - half_z;
  const double lo = (1.0 - hi) - half_z;  // the rounding of hi, exactly (|half_z| ≤ 1)
  const double cy = hi + (lo + z * z * pc);
  const double sa = reflect ? cy : sy;  // sin |x|
  c = reflect ? sy : cy;
  s = std::copysign(sa, x);
}

/// Below this |x|, sinCosSmall applies.
constexpr double kSinCosSmallLimit = 1.0 / 16.0;
/// s = sin x, c = cos x for |x| ≤ 1/16 from their Taylor polynomials (Horner in x²): the first
/// omitted terms, x¹¹/11! and x¹²/12!, are below 2e-20 |x| and 8e-24, far under an ulp (and so
/// is the rounding of the coefficients, which multiply terms below 7e-4 |x|). For |x| ≤ 1/256
/// (a joint below 16 rad/s at h = 1 ms) the polynomials stop earlier: x⁷/7! < 2e-20 |x| and
/// x⁸/8! < 1e-24. No divisions: they would lengthen the callers' dependent chains.
inline void sinCosSmall(double x, double& s, double& c) {
  constexpr double kTinyAngle = 1.0 / 256.0;
  const double x2 = x * x;
  if (std::abs(x) <= kTinyAngle) {
    s = x + x * x2 * (-kInv3 + x2 * kInv5);
    c = 1.0 + x2 * (-kInv2 + x2 * (kInv4 + x2 * -kInv6));
    return;
  }
  s = x + x * x2 * (-kInv3 + x2 * (kInv5 + x2 * (-kInv7 + x2 * kInv9)));
  c = 1.0 + x2 * (-kInv2 + x2 * (kInv4 + x2 * (-kInv6 + x2 * (kInv8 + x2 * -kInv10))));
}

// sin φ and versin φ = 1 − cos φ to full relative precision, from t = φ and z = φ² (versin
// instead of cos: a rotation applied as x + (sin·y − versin·x) perturbs its determinant only by
// O(ε φ²), so a rotation repeated a million times does not drift). The Taylor series are summed
// directly in z (Estrin's scheme, for a short dependency chain), coefficients written as
// products (a division by a constant is not turned into a multiplication without -ffast-math):
//   fine,   z ≤ 2⁻¹⁵ (|φ| ≤ 0.0055): through φ⁵ and φ⁶, as t + (t z)(z/5! − 1/3!) and
//           z/2 + z²(z/6! − 1/4!): two operations after z on the path to sin and versin instead
//           of three; the first omitted terms, φ⁷/7! and φ⁸/8!, are below 6e-18 relative to
//           sin φ ≈ φ and versin φ ≈ φ²/2, ε/40;
//   small,  |φ| ≤ 1/32: through φ⁷ and φ⁸; the first omitted terms, φ⁹/9! and φ¹⁰/10!, are
//           below 3e-18 relative;
//   medium, |φ| ≤ 1/2:  through φ¹³ and φ¹⁴; the first omitted terms, φ¹⁵/15! and φ¹⁶/16!,
//           are below ε/4 relative;
//   larger angles: sinVersinLibrary (the library functions).
constexpr double kSinVersinFineZ = 0x1p-15, kSinVersinSmallZ = 1.0 / 1024.0,
                 kSinVersinMediumZ = 0.25;

CGA_MATH_ALWAYS_INLINE void sinVersinFine(double t, double z, double& s, double& v) {
  s = t + (t * z) * (kInv5 * z - kInv3);
  v = 0.5 * z + (z * z) * (kInv6 * z - kInv4);
}
/// The fine series at φ and at φ/2 together, the half angle's coefficients scaled by powers of
/// two (sin(φ/2) = φ/2 − φ z/48 + φ z²/3840, versin(φ/2) = z/8 − z²/384 + z³/46080, z = φ²) so
/// that both share φ z and z²: the same roundings as sinVersinFine(φ/2, z/4) (every scaling is
/// exact), three operations fewer.
CGA_MATH_ALWAYS_INLINE void sinVersinFineWithHalf(double t, double z, double& s, double& v,
                                                  double& sh, double& vh) {
  const double tz = t * z, z2 = z * z;
  s = t + tz * (kInv5 * z - kInv3);
  v = 0.5 * z + z2 * (kInv6 * z - kInv4);
  sh = 0.5 * t + tz * ((kInv5 / 32.0) * z - kInv3 / 8.0);
  vh = 0.125 * z + z2 * ((kInv6 / 64.0) * z - kInv4 / 16.0);
}
CGA_MATH_ALWAYS_INLINE void sinVersinSmall(double t, double z, double& s, double& v) {
  // Grouped for a chain of four operations after z (the compiler keeps the order as written).
  const double z2 = z * z;
  s = (t - (kInv3 * t) * z) + (t * z2) * (kInv5 - kInv7 * z);
  v = (0.5 * z - kInv4 * z2) + (z2 * z) * (kInv6 - kInv8 * z);
}
CGA_MATH_ALWAYS_INLINE void sinVersinMedium(double t, double z, double& s, double& v) {
  const double z2 = z * z, z4 = z2 * z2;
  s = t *
      ((1.0 - kInv3 * z) + z2 * (kInv5 - kInv7 * z) + z4 * ((kInv9 - kInv11 * z) + kInv13 * z2));
  v = z *
      ((0.5 - kInv4 * z) + z2 * (kInv6 - kInv8 * z) + z4 * ((kInv10 - kInv12 * z) + kInv14 * z2));
}
inline void sinVersinLibrary(double t, double& s, double& v) {
  s = std::sin(t);
  const double c = std::cos(t);
  v = c > 0.0 ? s * s / (1.0 + c) : 1.0 - c;  // no cancellation in 1 − cos near 0
}

#undef CGA_MATH_ALWAYS_INLINE

}  // namespace math
}  // namespace cga_rigid_sim
