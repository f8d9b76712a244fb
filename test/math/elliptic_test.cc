// The exact flow's elliptic kernels (include/cga_rigid_sim/math/elliptic.h): the AGM table behind
// Bulirsch's sn, cn, dn, and sn, cn, dn themselves.
#include "cga_rigid_sim/math/elliptic.h"

#include <gtest/gtest.h>

#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <cmath>
#include <limits>

namespace cga_rigid_sim {
namespace dynamics {
namespace elliptic_test {

// Truth: the AGM's own stopping rule, |a − b| ≤ √ε a, reached before the table's last level (a
// capped table would stop early and give wrong sn, cn, dn). Over k'² from the smallest double to
// nearly 1: the table has 16 levels, the deepest case needs 12.
TEST(EllipticAgm, ConvergesWithinItsLevelsForEveryModulus) {
  const double tol = std::sqrt(std::numeric_limits<double>::epsilon());
  int deepest = 0;
  for (double kp2 : {std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::min(),
                     1e-300, 1e-100, 1e-30, 1e-16, 1e-8, 1e-4, 0.1, 0.5, 0.9, 1.0 - 1e-16}) {
    FreeFlowCache c;
    elliptic::buildAgm(kp2, c);
    // The table keeps b_j; a_j follows by the AGM's mean from a_0 = 1.
    double a = 1.0;
    for (int j = 0; j + 1 < c.agm_levels; ++j) a = 0.5 * (a + c.agm_b[j]);
    const double b = c.agm_b[c.agm_levels - 1];
    EXPECT_LT(c.agm_levels, FreeFlowCache::kMaxAgm) << "k'^2 = " << kp2;
    EXPECT_LE(std::abs(a - b), tol * a) << "k'^2 = " << kp2;
    deepest = std::max(deepest, int{c.agm_levels});
  }
  std::printf("[ info ] deepest AGM table: %d of %d levels\n", deepest, FreeFlowCache::kMaxAgm);
}

// Truth: Boost.Math's jacobi_elliptic (an independent implementation) for sn and cn, and for dn
// the identity dn² = cn² + k'² sn² on Boost's sn and cn: Boost's own dn loses accuracy near
// u = ±K (6e-4 at u = K, k'² = 0.5, where dn = k' exactly). Tolerance: 4e-15 absolute —
// Bulirsch's recurrence is exact to a few ε on sn, cn and relatively on dn (the header's check
// against 50-digit values: sn, cn within 3.3e-16, dn within 8e-15 relative; dn ≤ 1 here), Boost's
// own error is of the same order, and |u| ≤ K carries the rounding of u into them with a
// derivative ≤ 1.
TEST(EllipticSnCnDn, AgreeWithBoostOverAQuarterPeriod) {
  double worst = 0;
  for (double kp2 : {0.95, 0.5, 0.1, 1e-2, 1e-4}) {
    const double k = std::sqrt(1.0 - kp2);
    FreeFlowCache c;
    elliptic::buildAgm(kp2, c);
    const double K = boost::math::ellint_1(k);
    for (int i = -50; i <= 50; ++i) {
      const double u = K * i / 50.0;
      double sn, cn, dn;
      elliptic::jacobiSnCnDn(u, c, sn, cn, dn);
      double bcn, bdn;
      const double bsn = boost::math::jacobi_elliptic(k, u, &bcn, &bdn);
      bdn = std::sqrt(bcn * bcn + kp2 * bsn * bsn);
      worst = std::max({worst, std::abs(sn - bsn), std::abs(cn - bcn), std::abs(dn - bdn)});
      EXPECT_NEAR(sn, bsn, 4e-15) << "k'^2 = " << kp2 << ", u = " << u;
      EXPECT_NEAR(cn, bcn, 4e-15) << "k'^2 = " << kp2 << ", u = " << u;
      EXPECT_NEAR(dn, bdn, 4e-15) << "k'^2 = " << kp2 << ", u = " << u;
    }
  }
  std::printf("[ info ] sn, cn, dn against Boost.Math over [−K, K]: worst %.1e\n", worst);
}

}  // namespace elliptic_test
}  // namespace dynamics
}  // namespace cga_rigid_sim
