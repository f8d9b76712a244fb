// The sin and cos polynomials of math/sin_cos.h against the C library's std::sin and std::cos
// (correctly rounded to within an ulp): sinCosReduced (the exact flow's reduced half angles),
// sinCosSmall (a tree joint's small angles) and the sinVersin series (cga2's axis rotations).
#include "cga_rigid_sim/math/sin_cos.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "common/ulps.h"

namespace cga_rigid_sim {
namespace math {
namespace sin_cos_test {

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

// Truth: std::sin and std::cos. Tolerance: 2 ulp — on |x| ≤ 1/16 the omitted terms are below
// 2e-20 |x| (1e-24 absolute for cos), far under an ulp, and Horner's scheme with a leading term
// that is exact (x, 1) rounds about once more. Points: a uniform sample of [−1/16, 1/16] and the
// edges of both branches (1/256, 1/16 and their neighbours), 0 and tiny arguments.
TEST(SinCosSmall, WithinTwoUlpOfTheLibrary) {
  std::vector<double> xs;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-kSinCosSmallLimit, kSinCosSmallLimit);
  for (int i = 0; i < 200000; ++i) xs.push_back(u(rng));
  for (double e : {1.0 / 256.0, kSinCosSmallLimit, 1e-300, 1e-8, 1e-3}) {
    for (double x : {e, std::nextafter(e, 0.0), std::nextafter(e, 1.0)}) {
      if (x > kSinCosSmallLimit) continue;
      xs.push_back(x);
      xs.push_back(-x);
    }
  }
  xs.push_back(0.0);
  double worst_s = 0, worst_c = 0;
  for (double x : xs) {
    double s, c;
    sinCosSmall(x, s, c);
    worst_s = std::max(worst_s, ulps(s, std::sin(x)));
    worst_c = std::max(worst_c, ulps(c, std::cos(x)));
  }
  EXPECT_LE(worst_s, 2.0);
  EXPECT_LE(worst_c, 2.0);
}

// Truth: std::sin, and 1 − cos as 2 sin²(φ/2) (no cancellation). Tolerance: 4 ulp — each series'
// omitted terms are below ε/4 relative in its range (the fine one below ε/40), Estrin's scheme
// rounds a few times, and the reference 2 sin²(φ/2) rounds three times itself. Points: a
// log-uniform sample of each range up to its limit, both signs.
TEST(SinVersinSeries, WithinFourUlpOfTheLibrary) {
  const auto versin = [](double t) {
    const double h = std::sin(0.5 * t);
    return 2.0 * h * h;
  };
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> e(-30.0, 0.0);
  double worst_s = 0, worst_v = 0;
  for (int i = 0; i < 100000; ++i) {
    const double t = (i % 2 ? -1.0 : 1.0) * 0.5 * std::exp2(e(rng));
    const double z = t * t;
    double s, v;
    if (z <= kSinVersinFineZ) {
      sinVersinFine(t, z, s, v);
    } else if (z <= kSinVersinSmallZ) {
      sinVersinSmall(t, z, s, v);
    } else {
      sinVersinMedium(t, z, s, v);
    }
    worst_s = std::max(worst_s, ulps(s, std::sin(t)));
    worst_v = std::max(worst_v, ulps(v, versin(t)));
  }
  EXPECT_LE(worst_s, 4.0);
  EXPECT_LE(worst_v, 4.0);
  std::printf("[ info ] sinVersin series: sin within %.2f ulp, versin within %.2f ulp\n", worst_s,
              worst_v);
}

}  // namespace sin_cos_test
}  // namespace math
}  // namespace cga_rigid_sim
