// atanSeries (include/cga_rigid_sim/math/atan_series.h), the exact flow's atan of small per-step
// angles, against the C library's std::atan and std::atan2 (correctly rounded to within an ulp).
#include "cga_rigid_sim/math/atan_series.h"

#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <limits>
#include <random>
#include <vector>

#include "common/ulps.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace atan_series_test {

using testing::ulps;

// A uniform sample of n points of [−bound, bound], and each of `extra` with both signs.
std::vector<double> samplePoints(double bound, unsigned seed, std::initializer_list<double> extra) {
  std::vector<double> xs;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-bound, bound);
  for (int i = 0; i < 500000; ++i) xs.push_back(u(rng));
  for (double x : extra) {
    xs.push_back(x);
    xs.push_back(-x);
  }
  return xs;
}

// The largest distance in ulps of series(x) from std::atan(x) over xs.
double worstUlps(const std::vector<double>& xs, double (*series)(double)) {
  double worst = 0;
  for (double x : xs) worst = std::max(worst, ulps(series(x), std::atan(x)));
  return worst;
}

// Truth: std::atan. Tolerance: 2 ulp (measured: 1) — the series' truncation is below 1e-18
// relative and its evaluation, x + x z P(z), rounds a correction of at most z/3 ≤ 1/768 of x
// about once. Points: a uniform sample of [−1/16, 1/16], magnitudes spread over 1e-300 … 1/16
// (log-uniform), the bound and its neighbours, 0 and −0.
TEST(AtanSeries, WithinTwoUlpOfTheLibrary) {
  std::vector<double> xs = samplePoints(
      kAtanSeriesBound, 4, {kAtanSeriesBound, std::nextafter(kAtanSeriesBound, 0.0), 1e-8, 1e-3});
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> e(-690.0, -2.78);
  for (int i = 0; i < 500000; ++i) xs.push_back((i % 2 ? 1.0 : -1.0) * std::exp(e(rng)));
  const double worst = worstUlps(xs, atanSeries);
  EXPECT_LE(worst, 2.0);
  EXPECT_TRUE(std::signbit(atanSeries(-0.0)));
  EXPECT_EQ(atanSeries(0.0), 0.0);
  std::printf("[ info ] %zu points in [−1/16, 1/16]: within %.2f ulp of std::atan\n", xs.size(),
              worst);
}

// Truth: std::atan. The wider series, on (1/16, 1/8] where atanNearZero uses it. Tolerance: 2
// ulp (measured: 1), as above: truncation below 2⁻⁶⁰/21 relative, and the correction x z P(z)
// is at most z/3 ≤ 1/192 of x, rounded about once. Points: a uniform sample of [−1/8, 1/8], the
// bounds and their neighbours.
TEST(AtanSeries, WideSeriesWithinTwoUlpOfTheLibrary) {
  const std::vector<double> xs =
      samplePoints(kAtanSeriesWideBound, 5,
                   {kAtanSeriesWideBound, std::nextafter(kAtanSeriesWideBound, 0.0),
                    std::nextafter(kAtanSeriesBound, 1.0), 0.066, 1e-3});
  const double worst = worstUlps(xs, atanSeriesWide);
  EXPECT_LE(worst, 2.0);
  EXPECT_TRUE(std::signbit(atanSeriesWide(-0.0)));
  // The dispatcher: the short series up to 1/16, the wide one above it.
  EXPECT_EQ(atanNearZero(0.05), atanSeries(0.05));
  EXPECT_EQ(atanNearZero(-0.1), atanSeriesWide(-0.1));
  std::printf("[ info ] %zu points in [−1/8, 1/8]: within %.2f ulp of std::atan\n", xs.size(),
              worst);
}

// Truth: std::atan and std::atan2 where the series does not apply — the dispatchers must hand
// those arguments to the library unchanged (bit for bit), and use the series inside.
TEST(AtanSeries, DispatchersUseTheLibraryOutsideTheBound) {
  for (double x : {0.13, -0.5, 3.0, -1e10, std::nextafter(kAtanSeriesWideBound, 1.0)})
    EXPECT_EQ(atanNearZero(x), std::atan(x)) << x;
  // atan2 outside: x ≤ 0, or |y| > x/16.
  const double pairs[][2] = {{1.0, -1.0}, {0.1, 0.0}, {-0.2, 1.0}, {1.0, 2.0}, {0.0, -1.0}};
  for (const auto& p : pairs) EXPECT_EQ(atan2NearZero(p[0], p[1]), std::atan2(p[0], p[1]));
  // Inside: within 2 ulp of the library.
  EXPECT_LE(ulps(atan2NearZero(0.01, 1.0), std::atan2(0.01, 1.0)), 2.0);
  EXPECT_LE(ulps(atan2NearZero(-3e-5, 0.7), std::atan2(-3e-5, 0.7)), 2.0);
}

}  // namespace atan_series_test
}  // namespace dynamics
}  // namespace cga_rigid_sim
