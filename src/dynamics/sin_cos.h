// sin and cos of an angle already reduced to [−π/2, π/2], for the hot path of the exact flow
// (free_flow.cc builds a rotor from a half angle ψ/2, ψ ∈ [−π, π], every step). glibc's sincos
// first reduces its argument for any double and costs about as much as the rest of the rotor;
// here the reduction is one reflection, |x| > π/4 → π/2 − |x| (π/2 split in two doubles, so the
// reflection adds no error beyond the rounding of the difference), and both functions are
// Taylor polynomials on [−π/4, π/4] whose first omitted terms, (π/4)¹⁹/19! and (π/4)¹⁸/18!, are
// below 1e-17. Written as y + y·z·P(z) and 1 − z/2 + z²·Q(z) (z = y², the rounding of 1 − z/2
// carried along), the leading terms are exact and the corrections small: each result is within
// 1 ulp of std::sin and std::cos on a million points (test/dynamics/sin_cos_test.cc).
#pragma once

#include <cmath>

namespace cga_rigid_sim {
namespace dynamics {

/// s = sin x, c = cos x for |x| ≤ π/2 (larger |x|: use std::sin, std::cos).
inline void sinCosReduced(double x, double& s, double& c) {
  constexpr double kPiOver2Hi = 1.5707963267948966;
  constexpr double kPiOver2Lo = 6.123233995736766e-17;
  constexpr double kPiOver4 = 0.7853981633974483;
  const double ax = std::abs(x);
  const bool reflect = ax > kPiOver4;
  const double y = reflect ? (kPiOver2Hi - ax) + kPiOver2Lo : ax;
  const double z = y * y;
  // sin y = y + y z (−1/3! + z (1/5! − z (1/7! − …)))
  const double ps =
      -1.0 / 6.0 +
      z * (1.0 / 120.0 +
           z * (-1.0 / 5040.0 +
                z * (1.0 / 362880.0 +
                     z * (-1.0 / 39916800.0 +
                          z * (1.0 / 6227020800.0 +
                               z * (-1.0 / 1307674368000.0 + z * (1.0 / 355687428096000.0)))))));
  // cos y = 1 − z/2 + z² (1/4! − z (1/6! − …))
  const double pc =
      1.0 / 24.0 +
      z * (-1.0 / 720.0 +
           z * (1.0 / 40320.0 +
                z * (-1.0 / 3628800.0 +
                     z * (1.0 / 479001600.0 +
                          z * (-1.0 / 87178291200.0 +
                               z * (1.0 / 20922789888000.0 + z * (-1.0 / 6402373705728000.0)))))));
  const double sy = y + y * z * ps;
  const double half_z = 0.5 * z;
  const double hi = 1.0 - half_z;
  const double lo = (1.0 - hi) - half_z;  // the rounding of hi, exactly (|half_z| ≤ 1)
  const double cy = hi + (lo + z * z * pc);
  const double sa = reflect ? cy : sy;  // sin |x|
  c = reflect ? sy : cy;
  s = std::copysign(sa, x);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
