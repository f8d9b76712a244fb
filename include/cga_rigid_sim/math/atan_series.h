// atan near zero, for the exact flow's per-step angle increments (free_flow_phase.h;
// doc/conventions.md (E32)): the third-kind integral's addition-theorem term and the turn of Θ
// are the atan of quantities of the order of the phase step, which is small at small h. There,
// the Taylor series x − x³/3 + x⁵/5 − …, written as x + x z P(z) (z = x²): a small correction to
// an exact leading term, rounded about once. Two lengths:
// - through x¹³ for |x| ≤ 1/16: the first omitted term x¹⁵/15 is below 2⁻⁵⁶/15 ≈ 1e-18
//   relative to x;
// - through x¹⁹ for |x| ≤ 1/8: the first omitted term x²¹/21 is below 2⁻⁶⁰/21 relative to x.
//   The wider bound covers the addition-theorem term at the largest benchmarked steps (the
//   tennis racket at h = 0.1 s reaches 0.066), which otherwise paid the library's atan.
// glibc's atan takes any argument, and costs about twice as much.
#pragma once

#include <cmath>

namespace cga_rigid_sim {
namespace dynamics {

/// Where atanSeries holds: |x| ≤ kAtanSeriesBound.
constexpr double kAtanSeriesBound = 1.0 / 16.0;
/// Where atanSeriesWide holds: |x| ≤ kAtanSeriesWideBound.
constexpr double kAtanSeriesWideBound = 1.0 / 8.0;

/// atan x for |x| ≤ kAtanSeriesBound.
inline double atanSeries(double x) {
  const double z = x * x, z2 = z * z;
  // P(z) = −1/3 + z/5 − z²/7 + z³/9 − z⁴/11 + z⁵/13, in pairs for a short chain.
  const double p = (-1.0 / 3.0 + z * (1.0 / 5.0)) +
                   z2 * ((-1.0 / 7.0 + z * (1.0 / 9.0)) + z2 * (-1.0 / 11.0 + z * (1.0 / 13.0)));
  return std::copysign(x + x * z * p, x);  // odd: atan(−0) = −0 (the sum alone gives +0)
}

/// atan x for |x| ≤ kAtanSeriesWideBound.
inline double atanSeriesWide(double x) {
  const double z = x * x, z2 = z * z, z4 = z2 * z2;
  // P(z) = −1/3 + z/5 − … + z⁸/19 (nine terms), in pairs and quadruples for a short chain.
  const double p =
      ((-1.0 / 3.0 + z * (1.0 / 5.0)) + z2 * (-1.0 / 7.0 + z * (1.0 / 9.0))) +
      z4 * (((-1.0 / 11.0 + z * (1.0 / 13.0)) + z2 * (-1.0 / 15.0 + z * (1.0 / 17.0))) +
            z4 * (-1.0 / 19.0));
  return std::copysign(x + x * z * p, x);
}

/// atan x: a series near zero, the library elsewhere.
inline double atanNearZero(double x) {
  const double a = std::abs(x);
  if (a <= kAtanSeriesBound) return atanSeries(x);
  return a <= kAtanSeriesWideBound ? atanSeriesWide(x) : std::atan(x);
}

/// atan2(y, x): the series when x > 0 and |y| ≤ x/16 (one division), the library elsewhere.
inline double atan2NearZero(double y, double x) {
  return x > 0.0 && std::abs(y) <= kAtanSeriesBound * x ? atanSeries(y / x) : std::atan2(y, x);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
