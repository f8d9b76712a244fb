// Tests of forces, impulses and wrenches in curved space (curved/curved_impulse.h).
//
// Truths: the work–energy identity of an impulse, ΔT = ½ J·(Ẋ₀ + Ẋ₁) at its point (true for
// the exact moment X∧J and false for any other sign or factor); the lecture's elastic impulse
// (the nonzero root of the energy balance, a linear equation) reverses the normal velocity and
// keeps T; the impulse in world and in body axes agree; the normal part of a force drops out;
// a world-fixed moment M_W changes the world momentum as dL_W/dt = M_W exactly (the free
// pieces and the kicks both keep that law); a torque in one plane spins a ball up linearly.
#include "cga_rigid_sim/curved/curved_impulse.h"

#include <gtest/gtest.h>

#include <cmath>

#include "cga_rigid_sim/curved/curved_derived.h"
#include "cga_rigid_sim/curved/curved_integrator.h"
#include "common/cga_embedding.h"
#include "common/dynamics_fixtures.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace curved_impulse_test {

using cga::Bivector4;

class CurvedImpulseTest : public ::testing::TestWithParam<double> {
 protected:
  CurvedSpace space() const { return CurvedSpace::fromRadius(GetParam()).value(); }
  CurvedInertia racket(const CurvedSpace& S) const {
    return CurvedInertia::fromEuclidean("racket", testing::principal({0.2, 0.35, 0.45}, 1.5), S)
        .value();
  }
};
INSTANTIATE_TEST_SUITE_P(SphereAndHyperbolic, CurvedImpulseTest, ::testing::Values(2.0, -2.0),
                         [](const ::testing::TestParamInfo<double>& i) {
                           return i.param > 0 ? std::string("sphere") : std::string("hyperbolic");
                         });

CurvedBodyState moving(const CurvedSpace& S) {
  CurvedBodyState s;
  s.psi = S.poseFromChart({0.4, -0.2, 0.3}, Eigen::Quaterniond(0.9, 0.1, -0.3, 0.2)).value();
  s.omega_B = Bivector4({0.5, -1.0, 2.0}, Eigen::Vector3d(0.6, -0.3, 0.2) / S.rho());
  return s;
}

TEST_P(CurvedImpulseTest, ImpulseAtTheCentreGivesTheLinearMomentum) {
  const CurvedSpace S = space();
  const CurvedInertia I = racket(S);
  CurvedBodyState s;  // at rest at the origin
  const double J = 0.7;
  applyCurvedImpulse_B(I, S.origin(), Eigen::Vector4d(J, 0, 0, 0), s);
  // ΔL = O∧J e1 = R J e1∧e4, so u1 = σ R J/k14 and v = |R| u1 = J R²/k14 (→ J/m as R → ∞).
  const double v = S.rho() * s.omega_B.trans[0];
  EXPECT_NEAR(v, J * S.radius() * S.radius() / I.planeMoments().trans[0], 1e-15);
  EXPECT_NEAR(v, J / I.mass(), 0.1 * J / I.mass());  // within (tr S − S1)/(m R²) ≈ 3%
  EXPECT_EQ(s.omega_B.rot.norm(), 0.0);
  EXPECT_EQ(s.omega_B.trans.tail<2>().norm(), 0.0);
}

TEST_P(CurvedImpulseTest, ImpulseDoesTheWorkOfItsMeanVelocityAndElasticImpulseKeepsEnergy) {
  const CurvedSpace S = space();
  const int sigma = S.sigma();
  const CurvedInertia I = racket(S);
  const CurvedBodyState s0 = moving(S);
  const Eigen::Vector4d X = curvedBodyPoint(S, {0.15, -0.1, 0.05});
  const Eigen::Vector4d J = curvedBodyVector(S, {0.15, -0.1, 0.05}, {0.3, 0.8, -0.4});
  CurvedBodyState s1 = s0;
  applyCurvedImpulse_B(I, X, J, s1);
  const Eigen::Vector4d V0 = cga::dot(X, s0.omega_B, sigma), V1 = cga::dot(X, s1.omega_B, sigma);
  const double dT = curvedKineticEnergy(I, s1) - curvedKineticEnergy(I, s0);
  // Products of O(1) numbers: 1e-14 absolute.
  EXPECT_NEAR(dT, 0.5 * cga::dot(J, V0 + V1, sigma), 1e-14);

  // The elastic impulse along the unit normal n at X (the lecture's linear root):
  // j = −2 n·Ẋ₀ / n·(X·I⁻¹(X∧n)).
  const Eigen::Vector4d n = J / std::sqrt(cga::dot(J, J, sigma));
  const Eigen::Vector4d G = cga::dot(X, I.velocity(cga::wedge(X, n)), sigma);
  const double j = -2.0 * cga::dot(n, V0, sigma) / cga::dot(n, G, sigma);
  CurvedBodyState s2 = s0;
  applyCurvedImpulse_B(I, X, j * n, s2);
  EXPECT_NEAR(curvedKineticEnergy(I, s2), curvedKineticEnergy(I, s0), 1e-14);
  EXPECT_NEAR(cga::dot(n, cga::dot(X, s2.omega_B, sigma), sigma), -cga::dot(n, V0, sigma), 1e-14);
}

TEST_P(CurvedImpulseTest, WorldAndBodyImpulsesAgreeAndTheNormalPartDropsOut) {
  const CurvedSpace S = space();
  const int sigma = S.sigma();
  const CurvedInertia I = racket(S);
  const CurvedBodyState s0 = moving(S);
  const Eigen::Vector4d X_B = curvedBodyPoint(S, {-0.2, 0.1, 0.3});
  const Eigen::Vector4d J_B = curvedBodyVector(S, {-0.2, 0.1, 0.3}, {1.0, -0.5, 0.25});
  CurvedBodyState a = s0, b = s0, c = s0;
  applyCurvedImpulse_B(I, X_B, J_B, a);
  applyCurvedImpulse_W(I, cga::rotate(s0.psi, X_B, sigma), cga::rotate(s0.psi, J_B, sigma), b);
  // Two rotations by ψ of O(1) quantities: 1e-14.
  EXPECT_LE((a.omega_B - b.omega_B).coefficientNorm(), 1e-14);
  // J + αX: X∧X = 0, so α changes nothing beyond the rounding of J + αX (α = 1e3: 1e-12).
  applyCurvedImpulse_B(I, X_B, J_B + 1e3 * X_B, c);
  EXPECT_LE((a.omega_B - c.omega_B).coefficientNorm(), 1e-12);
}

TEST_P(CurvedImpulseTest, WorldFixedMomentChangesTheWorldMomentumAtItsRate) {
  const CurvedSpace S = space();
  const CurvedInertia I = racket(S);
  CurvedLoads loads;
  // A force of (0, 0.8, 0) N held at the world point of chart (0.3, 0, 0), plus a couple.
  const Eigen::Vector4d X = S.fromChart({0.3, 0, 0});
  Eigen::Vector4d F(0, 0.8, 0, 0);
  loads.moment_W = curvedMomentOfForce(X, F) + Bivector4({0, 0, 0.1}, Eigen::Vector3d::Zero());
  for (const char* name : {"curved2"}) {  // curved_exact needs an isotropic body
    CurvedBodyState s = moving(S);
    auto it = makeCurvedIntegrator(name, I).value();
    const Bivector4 L0 = curvedWorldMomentum(I, s);
    const double h = 0.01;
    // 2 s: a moment fixed in the world acts on a body that moves away from where it was
    // defined; in H³ its body-axes image grows like e^{2d/|R|} with the distance d, and after
    // ~8 s here the body is flung out of any double's range. The law holds all the same.
    for (int i = 0; i < 200; ++i) it->step(I, loads, h, s);
    const Bivector4 expected = L0 + 2.0 * loads.moment_W;
    // Exact law, 200 steps of round-off on |L| ~ 3: 1e-13.
    EXPECT_LE((curvedWorldMomentum(I, s) - expected).coefficientNorm(), 1e-13) << name;
  }
}

TEST_P(CurvedImpulseTest, TorqueInOnePlaneSpinsABallUpUniformly) {
  const CurvedSpace S = space();
  const CurvedInertia I =
      CurvedInertia::fromEuclidean("ball", testing::principal({0.4, 0.4, 0.4}, 2.0), S).value();
  CurvedLoads loads;
  loads.moment_B = Bivector4({0, 0, 0.2}, Eigen::Vector3d::Zero());  // 0.2 N m about e3
  for (const char* name : {"curved2", "curved_exact"}) {
    CurvedBodyState s;
    auto it = makeCurvedIntegrator(name, I).value();
    const double h = 0.01;
    for (int i = 0; i < 500; ++i) it->step(I, loads, h, s);
    // w(t) = τ t/k12 and the angle ½ τ t²/k12 (Strang with a constant torque is exact for it).
    const double t = 5.0, k = I.planeMoments().rot[2];
    EXPECT_NEAR(s.omega_B.rot[2], 0.2 * t / k, 1e-13) << name;
    const cga::Rotor4 expected = cga::expBlade(2, -0.25 * 0.2 * t * t / k, S.sigma());
    for (int j = 0; j < 8; ++j) EXPECT_NEAR(s.psi.c[j], expected.c[j], 1e-12) << name;
  }
}

}  // namespace curved_impulse_test
}  // namespace dynamics
}  // namespace cga_rigid_sim
