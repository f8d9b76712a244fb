// Tests of the curved space, its chart and the 1-up inertia (curved/curved_space.h,
// curved/curved_inertia.h).
//
// Truths: a cloud of point masses on the space, whose kinetic energy ½ Σ m Ẋ² and moment
// Σ m X∧(X·Ω) are summed in the reference algebra (Ẋ = X·Ω, doc/curved_space.md); the geodesic
// distance from the metric (R acos / |R| acosh of X·O/(σR²)); the chart's metric factor from a
// central difference of the embedding. Tolerances are stated at each check.
#include "cga_rigid_sim/curved/curved_inertia.h"

#include <gtest/gtest.h>

#include <cmath>

#include "cga_rigid_sim/curved/curved_impulse.h"
#include "cga_rigid_sim/curved/curved_space.h"
#include "common/cga_embedding.h"
#include "common/curved_embedding.h"
#include "common/dynamics_fixtures.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace curved_inertia_test {

using cga::Bivector4;
using cga::Multivector;
using testing::Rng;

class CurvedInertiaTest : public ::testing::TestWithParam<double> {
 protected:
  CurvedSpace space() const { return CurvedSpace::fromRadius(GetParam()).value(); }
};
INSTANTIATE_TEST_SUITE_P(SphereAndHyperbolic, CurvedInertiaTest, ::testing::Values(2.5, -2.5),
                         [](const ::testing::TestParamInfo<double>& i) {
                           return i.param > 0 ? std::string("sphere") : std::string("hyperbolic");
                         });

// Point masses in pairs ±s along the body axes (so the centre is at O and J is diagonal), at
// geodesic distances comparable to R (a strongly curved case).
struct Cloud {
  std::vector<double> m;
  std::vector<Eigen::Vector4d> X;
};
Cloud makeCloud(const CurvedSpace& space) {
  Cloud c;
  const double d[3] = {0.9, 0.5, 0.3}, mass[3] = {1.0, 2.0, 0.5};
  for (int a = 0; a < 3; ++a)
    for (double sgn : {1.0, -1.0}) {
      c.m.push_back(mass[a]);
      c.X.push_back(curvedBodyPoint(space, sgn * d[a] * Eigen::Vector3d::Unit(a)));
    }
  return c;
}

TEST_P(CurvedInertiaTest, PlaneMomentsReproduceThePointCloud) {
  const CurvedSpace S = space();
  const int sigma = S.sigma();
  const Cloud c = makeCloud(S);
  Eigen::Matrix4d J = Eigen::Matrix4d::Zero();
  double mass = 0;
  for (size_t i = 0; i < c.m.size(); ++i) {
    J += c.m[i] * c.X[i] * c.X[i].transpose();
    mass += c.m[i];
    // Each point lies on the space, X·X = σR² (to round-off of R² = 6.25).
    EXPECT_NEAR(cga::dot(c.X[i], c.X[i], sigma), sigma * S.radius() * S.radius(), 1e-13);
  }
  // The centre condition and principal axes: J is diagonal (pairs ±s cancel exactly).
  EXPECT_LE((J - Eigen::Matrix4d(J.diagonal().asDiagonal())).cwiseAbs().maxCoeff(), 1e-14);
  const CurvedInertia I = CurvedInertia::fromSecondMoments("cloud", mass, J.diagonal(), S).value();
  // J4 = m R² − σ tr S for point masses on the space (exact identity, 1e-13 of m R² ≈ 40).
  EXPECT_NEAR(J(3, 3), mass * S.radius() * S.radius() - sigma * J.diagonal().head<3>().sum(),
              1e-13);

  Rng rng(21);
  for (int t = 0; t < 20; ++t) {
    const Bivector4 W(rng.vec(1.0), rng.vec(1.0));
    const Multivector w = testing::toMV(W, sigma);
    Multivector Iref;
    double Tref = 0;
    for (size_t i = 0; i < c.m.size(); ++i) {
      const Multivector x = testing::vectorMV(c.X[i], sigma);
      const Multivector xdot = cga::inner(x, w);  // Ẋ = X·Ω (body frame)
      Iref += c.m[i] * (x ^ xdot);
      Tref += 0.5 * c.m[i] * (xdot * xdot).scalarPart();
    }
    // Sums of ~20 products of size ≤ 40: 1e-12 absolute is ~100 ε relative.
    EXPECT_LE(maxAbsDiff(testing::toMV(I.momentum(W), sigma), Iref), 1e-12);
    EXPECT_NEAR(I.kineticEnergy(W), Tref, 1e-12);
    // T = −½⟨Ω I(Ω)⟩ (the lecture's Lagrangian term) and the inverse map.
    EXPECT_NEAR(-0.5 * cga::scalarProduct(W, I.momentum(W), sigma), Tref, 1e-12);
    EXPECT_LE((I.velocity(I.momentum(W)) - W).coefficientNorm(), 1e-14);
  }
}

TEST_P(CurvedInertiaTest, FromEuclideanKeepsTheRotationalMomentsExactly) {
  const CurvedSpace S = space();
  const Eigen::Vector3d Ic(0.3, 0.5, 0.7);
  const Inertia E = testing::principal(Ic, 2.0);
  const CurvedInertia I = CurvedInertia::fromEuclidean("box", E, S).value();
  // k23 = S2 + S3 = I1 and so on: the Euclidean moments (to the rounding of ½ tr I − I_i).
  EXPECT_LE((I.planeMoments().rot - Ic).cwiseAbs().maxCoeff(), 1e-15);
  // k_i4 = m R² − σ (tr S − S_i): here tr S = ½ tr I = 0.75.
  const double mR2 = 2.0 * S.radius() * S.radius();
  const Eigen::Vector3d Sdiag = Eigen::Vector3d::Constant(0.75) - Ic;
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(I.planeMoments().trans[i], mR2 - S.sigma() * (0.75 - Sdiag[i]), 1e-14);
  EXPECT_FALSE(I.isotropic());
  EXPECT_TRUE(CurvedInertia::fromEuclidean("cube", testing::principal({0.2, 0.2, 0.2}), S)
                  .value()
                  .isotropic());
}

TEST(CurvedInertiaRefusals, NameTheBodyAndTheRule) {
  const CurvedSpace sphere = CurvedSpace::fromRadius(0.5).value();
  // A 1 kg body with tr S = ½ tr I = 0.3 kg m² does not fit a sphere of radius 0.5 m
  // (m R² = 0.25 < tr S).
  const auto big =
      CurvedInertia::fromEuclidean("boulder", testing::principal({0.2, 0.2, 0.2}), sphere);
  ASSERT_FALSE(big.ok());
  EXPECT_NE(big.error().find("boulder"), std::string::npos) << big.error();
  EXPECT_NE(big.error().find("too large for the space"), std::string::npos) << big.error();
  // The same body fits any hyperbolic space (J4 = m R² + tr S).
  EXPECT_TRUE(CurvedInertia::fromEuclidean("boulder", testing::principal({0.2, 0.2, 0.2}),
                                           CurvedSpace::fromRadius(-0.5).value())
                  .ok());
  const auto line = CurvedInertia::fromSecondMoments("needle", 1.0, {1.0, 0.0, 0.0, 1.0}, sphere);
  ASSERT_FALSE(line.ok());
  EXPECT_NE(line.error().find("e23"), std::string::npos) << line.error();
  EXPECT_FALSE(CurvedInertia::fromSecondMoments("x", -1.0, {1, 1, 1, 1}, sphere).ok());
  EXPECT_FALSE(CurvedInertia::fromSecondMoments("x", 1.0, {1, NAN, 1, 1}, sphere).ok());
  const auto flat = CurvedSpace::fromRadius(0.0);
  ASSERT_FALSE(flat.ok());
  EXPECT_NE(flat.error().find("curvature"), std::string::npos);
  EXPECT_FALSE(CurvedSpace::fromRadius(INFINITY).ok());
}

TEST_P(CurvedInertiaTest, ChartRoundTripsAndMeasuresLengths) {
  const CurvedSpace S = space();
  const int sigma = S.sigma();
  Rng rng(22);
  for (int t = 0; t < 50; ++t) {
    const Eigen::Vector3d x = rng.vec(1.4);  // inside the Poincaré ball of radius 5
    const Eigen::Vector4d X = S.fromChart(x);
    EXPECT_NEAR(cga::dot(X, X, sigma), sigma * S.radius() * S.radius(), 1e-13);
    EXPECT_LE((S.toChart(X) - x).norm(), 1e-14);
    // The geodesic distance from the origin, from the metric: cos(d/R) = −X·O/(R²) on the
    // sphere (O = −R e4), cosh(d/|R|) = X·O/(−R²)... both are X4/(−R) here.
    const double c = X[3] / -S.radius();
    const double d = S.rho() * (sigma > 0 ? std::acos(c) : std::acosh(c));
    // acos/acosh lose half the digits near d = 0; the points are ≥ ~0.05 from the origin
    // except rarely, so 1e-7 is the conditioning, not the chart.
    EXPECT_NEAR(S.chartDistance(x), d, 1e-7);
    // The metric factor: a small chart step δ has true length chartScale(x) |δ| (central
    // difference of the embedding; its error is O(δ²) = 1e-8 relative).
    const Eigen::Vector3d delta = 1e-4 * rng.vec(1.0).normalized();
    const Eigen::Vector4d dX = S.fromChart(x + delta) - S.fromChart(x - delta);
    const double ds = std::sqrt(cga::dot(dX, dX, sigma)) / 2.0;
    EXPECT_NEAR(ds / 1e-4, S.chartScale(x), 1e-7);
  }
}

TEST_P(CurvedInertiaTest, PoseFromChartRoundTrips) {
  const CurvedSpace S = space();
  Rng rng(23);
  for (int t = 0; t < 30; ++t) {
    const Eigen::Vector3d x = rng.vec(1.4);
    const Eigen::Quaterniond q = rng.rotation();
    const cga::Rotor4 psi = S.poseFromChart(x, q).value();
    EXPECT_LE(cga::unitDrift(psi, S.sigma()), 1e-14);
    Eigen::Vector3d x2;
    Eigen::Quaterniond q2;
    S.chartPose(psi, x2, q2);
    // Round trip through exp, the rotor product and the differential of the chart: a few ε of
    // |x| ≈ 1 and of the unit quaternion.
    EXPECT_LE((x2 - x).norm(), 1e-13);
    EXPECT_LE(testing::orientationError(q2, q), 1e-13);
  }
  if (S.sigma() < 0) {
    const auto out = S.poseFromChart({6.0, 0, 0}, Eigen::Quaterniond::Identity());
    ASSERT_FALSE(out.ok());
    EXPECT_NE(out.error().find("Poincare ball"), std::string::npos) << out.error();
  }
}

}  // namespace curved_inertia_test
}  // namespace dynamics
}  // namespace cga_rigid_sim
