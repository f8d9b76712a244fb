// atan near zero, for the exact flow's per-step angle increments (free_flow.cc, point 7): the
// third-kind integral's addition-theorem term and the turn of Θ are the atan of quantities of
// the order of the phase step, which is small at small h. There, the Taylor series through x¹³,
// x − x³/3 + … + x¹³/13, whose first omitted term x¹⁵/15 is below 2⁻⁵⁶/15 ≈ 1e-18 relative to
// x for |x| ≤ 1/16, is written as x + x z P(z) (z = x²): a small correction to an exact leading
// term, rounded about once. glibc's atan takes any argument, and costs about twice as much.
#pragma once

#include <cmath>

namespace cga_rigid_sim {
namespace dynamics {

/// Where atanSeries holds: |x| ≤ 1/16.
constexpr double kAtanSeriesBound = 1.0 / 16.0;

/// atan x for |x| ≤ kAtanSeriesBound.
inline double atanSeries(double x) {
  const double z = x * x, z2 = z * z;
  // P(z) = −1/3 + z/5 − z²/7 + z³/9 − z⁴/11 + z⁵/13, in pairs for a short chain.
  const double p = (-1.0 / 3.0 + z * (1.0 / 5.0)) +
                   z2 * ((-1.0 / 7.0 + z * (1.0 / 9.0)) + z2 * (-1.0 / 11.0 + z * (1.0 / 13.0)));
  return std::copysign(x + x * z * p, x);  // odd: atan(−0) = −0 (the sum alone gives +0)
}

/// atan x: the series near zero, the library elsewhere.
inline double atanNearZero(double x) {
  return std::abs(x) <= kAtanSeriesBound ? atanSeries(x) : std::atan(x);
}

/// atan2(y, x): the series when x > 0 and |y| ≤ x/16 (one division), the library elsewhere.
inline double atan2NearZero(double y, double x) {
  return x > 0.0 && std::abs(y) <= kAtanSeriesBound * x ? atanSeries(y / x) : std::atan2(y, x);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
