// sinCosReduced (src/dynamics/sin_cos.h), the exact flow's sin and cos of a reduced half angle,
// against the C library's std::sin and std::cos (correctly rounded to within an ulp).
#include "../../src/dynamics/sin_cos.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "common/ulps.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace {

using testing::ulps;

// Truth: std::sin and std::cos. Tolerance: 2 ulp (measured: 1) — the polynomials' truncation is
// below 1e-17 and their evaluation rounds about once (sin: y + y z P(z), cos: 1 − z/2 + z² Q(z),
// both with a small correction to an exact leading term); the reflection π/2 − |x| is exact to
// ulp(π/2)/2 beyond the rounding of its result. Points: a dense uniform sample of [−π/2, π/2], the
// edges of the reflection (±π/4 and their neighbours), ±π/2, 0, −0, and tiny arguments.
TEST(SinCosReduced, WithinTwoUlpOfTheLibrary) {
  std::vector<double> xs;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-M_PI / 2, M_PI / 2);
  for (int i = 0; i < 1000000; ++i) xs.push_back(u(rng));
  for (double e : {M_PI / 4, M_PI / 2, 1e-300, 1e-8, 1e-3, 0.5, 1.0, 1.5}) {
    for (double x : {e, std::nextafter(e, 0.0), std::nextafter(e, 4.0)}) {
      xs.push_back(x);
      xs.push_back(-x);
    }
  }
  xs.push_back(0.0);
  xs.push_back(-0.0);
  double worst_s = 0, worst_c = 0;
  for (double x : xs) {
    double s, c;
    sinCosReduced(x, s, c);
    worst_s = std::max(worst_s, ulps(s, std::sin(x)));
    worst_c = std::max(worst_c, ulps(c, std::cos(x)));
  }
  EXPECT_LE(worst_s, 2.0);
  EXPECT_LE(worst_c, 2.0);
  double s, c;
  sinCosReduced(-0.0, s, c);
  EXPECT_TRUE(std::signbit(s));  // odd: sin(−0) = −0
  EXPECT_EQ(c, 1.0);
  std::printf("[ info ] %zu points in [−π/2, π/2]: sin within %.2f ulp, cos within %.2f ulp\n",
              xs.size(), worst_s, worst_c);
}

}  // namespace
}  // namespace dynamics
}  // namespace cga_rigid_sim
