// The Euclidean limit of the 1-up dynamics: as R → ∞ the motion in curved space converges to
// the Euclidean one at the rate O(1/R²) (doc/curved_space.md#the-euclidean-limit).
//
// Truths: the project's Euclidean exact flow (free_flow.h) for an isotropic body against the
// curved exact flow, and the three-axis splitting against curved2 at the same step (curved2 is
// that splitting in 1 up and becomes it as R → ∞). Both curved motions are read in the
// stereographic chart (position and attitude), on the sphere and in hyperbolic space. The rate is
// asserted from the table: the error ratio between R and 2R must be 4 (order 2 in 1/R) within 5%;
// the table is printed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "cga_rigid_sim/body/derived.h"
#include "cga_rigid_sim/body/free_flow.h"
#include "cga_rigid_sim/curved/curved_derived.h"
#include "cga_rigid_sim/curved/curved_integrator.h"
#include "common/axis_splitting.h"
#include "common/dynamics_fixtures.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace curved_limit_test {

const Eigen::Vector3d kX0(0.5, -0.3, 0.2);
const Eigen::Quaterniond kQ0 = Eigen::Quaterniond(0.9, 0.1, -0.3, 0.2).normalized();
const Eigen::Vector3d kW(0.3, -1.2, 2.0), kV(0.4, 0.25, -0.3);  // body axes

// Error of the curved motion read in the chart against the Euclidean one: |Δx| (m) plus the
// attitude angle (rad), at time T.
double chartError(const CurvedSpace& S, const CurvedBodyState& c, const BodyState& e) {
  Eigen::Vector3d x;
  Eigen::Quaterniond q;
  S.chartPose(c.psi, x, q);
  return (x - e.M_WB.translation(1.0)).norm() + testing::orientationError(q, e.M_WB.rotation());
}

CurvedBodyState curvedStart(const CurvedSpace& S) {
  CurvedBodyState s;
  s.psi = S.poseFromChart(kX0, kQ0).value();
  s.omega_B = cga::Bivector4(kW, kV / S.rho());
  return s;
}
BodyState euclideanStart() {
  BodyState s;
  s.M_WB = cga::Motor::fromPose(kQ0, kX0, 1.0);
  s.omega_B = cga::Bivelocity::fromVelocities(kW, kV, 1.0);
  return s;
}

// Asserts the table's rate: e(R)/e(2R) → 4.
void expectRateTwo(const char* what, const std::vector<double>& radii,
                   const std::vector<double>& err) {
  std::printf("%s\n  %10s %12s %8s\n", what, "R (m)", "error", "rate");
  for (size_t i = 0; i < radii.size(); ++i) {
    const double rate = i ? std::log2(err[i - 1] / err[i]) : NAN;
    std::printf("  %10.0f %12.4e %8.3f\n", radii[i], err[i], rate);
  }
  // The last three ratios (R ≥ 4 × the smallest): the O(1/R⁴) term is below 5% there.
  for (size_t i = radii.size() - 3; i < radii.size(); ++i)
    EXPECT_NEAR(err[i - 1] / err[i], 4.0, 0.2) << what << " at R = " << radii[i];
}

class CurvedLimitTest : public ::testing::TestWithParam<int> {};
INSTANTIATE_TEST_SUITE_P(SphereAndHyperbolic, CurvedLimitTest, ::testing::Values(1, -1),
                         [](const ::testing::TestParamInfo<int>& i) {
                           return i.param > 0 ? std::string("sphere") : std::string("hyperbolic");
                         });

// A ball (isotropic): curved exact flow vs Euclidean exact flow, 5 s.
TEST_P(CurvedLimitTest, IsotropicExactFlowConvergesAsOneOverRSquared) {
  const int sigma = GetParam();
  const double T = 5.0;
  const Inertia E = testing::principal({0.4, 0.4, 0.4}, 2.0);
  BodyState e = euclideanStart();
  FreeFlowCache cache;
  exactFreeFlow(E, 1.0, T, e, cache);
  std::vector<double> radii, err;
  for (double R = 10; R <= 640; R *= 2) {
    const CurvedSpace S = CurvedSpace::fromRadius(sigma * R).value();
    const CurvedInertia I = CurvedInertia::fromEuclidean("ball", E, S).value();
    const CurvedBodyState c = curvedIsotropicFlow(I, curvedStart(S), T);
    radii.push_back(R);
    err.push_back(chartError(S, c, e));
  }
  expectRateTwo(sigma > 0 ? "isotropic ball, curved_exact vs Euclidean exact, S3, t = 5 s"
                          : "isotropic ball, curved_exact vs Euclidean exact, H3, t = 5 s",
                radii, err);
}

// An asymmetric body: curved2 vs its flat limit, the three-axis splitting (cga2's until it split
// off the Casimir; test/common/axis_splitting.h), both at h = 10 ms over 5 s.
TEST_P(CurvedLimitTest, SplittingConvergesToCga2AsOneOverRSquared) {
  const int sigma = GetParam();
  const double T = 5.0, h = 0.01;
  const int n = static_cast<int>(std::lround(T / h));
  const Inertia E = testing::principal({0.2, 0.35, 0.45}, 1.5);
  BodyState e = euclideanStart();
  for (int i = 0; i < n; ++i) testing::axisSplittingStep(E, h, e);
  std::vector<double> radii, err;
  for (double R = 10; R <= 640; R *= 2) {
    const CurvedSpace S = CurvedSpace::fromRadius(sigma * R).value();
    const CurvedInertia I = CurvedInertia::fromEuclidean("racket", E, S).value();
    CurvedBodyState c = curvedStart(S);
    CurvedSplittingIntegrator it;
    for (int i = 0; i < n; ++i) it.step(I, CurvedLoads(), h, c);
    radii.push_back(R);
    err.push_back(chartError(S, c, e));
  }
  expectRateTwo(sigma > 0
                    ? "asymmetric body, curved2 vs the axis splitting (h = 10 ms), S3, t = 5 s"
                    : "asymmetric body, curved2 vs the axis splitting (h = 10 ms), H3, t = 5 s",
                radii, err);
}

// The world momentum's meaning in the limit: L_W's translation part over R is the linear
// momentum m v_W, and its rotation part the angular momentum about the origin,
// x × m v_W + R J w (world axes) — each to O(1/R²) (checked at R = 1e4 m: 1e-8 relative).
TEST_P(CurvedLimitTest, WorldMomentumBecomesLinearAndAngularMomentum) {
  const int sigma = GetParam();
  const Inertia E = testing::principal({0.2, 0.35, 0.45}, 1.5);
  const CurvedSpace S = CurvedSpace::fromRadius(sigma * 1e4).value();
  const CurvedInertia I = CurvedInertia::fromEuclidean("racket", E, S).value();
  const CurvedBodyState c = curvedStart(S);
  const cga::Bivector4 L_W = curvedWorldMomentum(I, c);
  const Eigen::Vector3d p = 1.5 * (kQ0 * kV);
  const Eigen::Vector3d L = kX0.cross(p) + kQ0 * E.principalMoments().cwiseProduct(kW);
  EXPECT_LE((curvedLinearMomentum(S, L_W) - p).norm(), 1e-8 * p.norm());
  EXPECT_LE((L_W.rot - L).norm(), 1e-8 * L.norm());
}

}  // namespace curved_limit_test
}  // namespace dynamics
}  // namespace cga_rigid_sim
