// Curved space in the World (WorldConfig::curvature, sim/curved_bodies.h).
//
// Truths: the conservation of the 4-d world momentum (doc/curved_space.md#equation-of-motion)
// through the World's pipeline; the core's own curved integrators stepped directly from the
// same initial state (the World must add nothing and lose nothing: bit for bit); the Euclidean
// World as R → ∞ (curved2 → cga2 at O(1/R²): at R = 1e4 m the table of doc/curved_space.md
// predicts ~6e-8 after 5 s); rest; reset; and the refusals, each naming its field and rule.
#include <gtest/gtest.h>

#include <cmath>

#include "cga_rigid_sim/body/derived.h"
#include "cga_rigid_sim/curved/curved_derived.h"
#include "cga_rigid_sim/curved/curved_integrator.h"
#include "common/axis_splitting.h"
#include "common/dynamics_fixtures.h"
#include "sim/world_fixtures.h"

namespace cga_rigid_sim {
namespace sim {
namespace world_curvature_test {

using testing::makeScene;
using testing::movingBody;

const Eigen::Quaterniond kQ = Eigen::Quaterniond(0.9, 0.1, -0.3, 0.2).normalized();

scene::Scene twoBodies() {
  return makeScene({movingBody("racket", 1.5, {0.2, 0.35, 0.45}, kQ, {0.4, -0.2, 0.3},
                               {0.05, 3.0, 0.1}, {0.6, -0.3, 0.2}),
                    movingBody("ball", 2.0, {0.4, 0.4, 0.4}, Eigen::Quaterniond::Identity(),
                               {-0.5, 0.1, 0.0}, {0.3, -1.2, 2.0}, {0.2, 0.1, -0.15})});
}

Result<std::unique_ptr<World>> curvedWorld(scene::Scene s, double R,
                                           const std::string& integrator = "auto") {
  WorldConfig c;
  c.dt = 1e-3;
  c.integrator = integrator;
  c.curvature = R;
  return World::create(std::move(s), c);
}

class WorldCurvatureTest : public ::testing::TestWithParam<double> {};
INSTANTIATE_TEST_SUITE_P(SphereAndHyperbolic, WorldCurvatureTest, ::testing::Values(5.0, -5.0),
                         [](const ::testing::TestParamInfo<double>& i) {
                           return i.param > 0 ? std::string("sphere") : std::string("hyperbolic");
                         });

// 5000 steps: the total 4-d momentum is conserved to round-off; each body's state is the
// core's, stepped directly with the integrator `auto` picks (curved2 for the racket,
// curved_exact for the ball), bit for bit; the reports read its chart pose.
TEST_P(WorldCurvatureTest, StepsTheCoreDynamicsAndConservesTheFourDMomentum) {
  const double R = GetParam();
  auto w = curvedWorld(twoBodies(), R);
  ASSERT_TRUE(w.ok()) << w.error();
  World& world = **w;
  const auto m0 = world.curvedMomentum();
  ASSERT_EQ(m0.size(), 3u);
  EXPECT_EQ(m0[2].body, "total");

  // The core, by hand, from the World's initial state (its motor, read as a chart pose) and
  // the same conversion (u = v/|R|).
  const dynamics::CurvedSpace S = dynamics::CurvedSpace::fromRadius(R).value();
  const dynamics::CurvedInertia Iracket =
      dynamics::CurvedInertia::fromEuclidean("racket", testing::principal({0.2, 0.35, 0.45}, 1.5),
                                             S)
          .value();
  dynamics::CurvedBodyState racket;
  const dynamics::BodyState& init = world.model().moving[0].initial;
  racket.psi = S.poseFromChart(init.M_WB.translation(1.0), init.M_WB.rotation()).value();
  racket.omega_B = cga::Bivector4(init.omega_B.rot, init.omega_B.trans / S.rho());
  dynamics::CurvedSplittingIntegrator curved2;

  for (int i = 0; i < 5000; ++i) {
    world.step();
    curved2.step(Iracket, dynamics::CurvedLoads(), 1e-3, racket);
  }
  const auto m1 = world.curvedMomentum();
  const double dL = (m1[2].L_W - m0[2].L_W).coefficientNorm() / m0[2].L_W.coefficientNorm();
  // 5000 steps of round-off on O(1) coefficients (the core tests bound 10⁶ steps by 2e-11).
  EXPECT_LE(dL, 1e-12);
  // The ball (curved_exact): its energy to round-off; the racket (curved2): O(h²) = 1e-5.
  EXPECT_NEAR(m1[1].kinetic_energy, m0[1].kinetic_energy, 1e-14 * m0[1].kinetic_energy);
  EXPECT_NEAR(m1[0].kinetic_energy, m0[0].kinetic_energy, 1e-5 * m0[0].kinetic_energy);

  // The World's racket is the core's, bit for bit, and its report is the chart pose.
  EXPECT_EQ(world.model().moving.size(), 2u);
  EXPECT_EQ(world.data().bodies[0].curved_state.psi.c, racket.psi.c);
  Eigen::Vector3d x;
  Eigen::Quaterniond q;
  S.chartPose(racket.psi, x, q);
  const BodyStateReport rep = world.getBodyState("racket").value();
  // Through the motor of the report (fromPose, then its translation): a few ulps of |x| ≈ 4.
  EXPECT_LE((rep.com - x).norm(), 1e-14);
  EXPECT_LE(testing::orientationError(Eigen::Quaterniond(rep.pose_root.rotation()), q), 1e-15);
}

// As R → ∞ the curved World becomes the Euclidean one: curved2 against its flat limit, the
// three-axis splitting (test/common/axis_splitting.h; cga2 splits differently since it split off
// the Casimir), stepped at the same h from the flat World's initial states.
TEST_P(WorldCurvatureTest, LargeRadiusGivesTheEuclideanWorld) {
  const double sign = GetParam() > 0 ? 1.0 : -1.0;
  auto flat = testing::makeWorld(twoBodies(), 1e-3, "cga2");
  auto curved = curvedWorld(twoBodies(), sign * 1e4, "curved2");
  ASSERT_TRUE(curved.ok()) << curved.error();
  (*curved)->step(5000);
  const double lambda = flat->model().lambda;
  for (const char* body : {"racket", "ball"}) {
    const int i = flat->model().moving_of_body[flat->model().findBody(body)];
    dynamics::BodyState a = flat->getBodyState(body).value().state;
    for (int k = 0; k < 5000; ++k)
      testing::axisSplittingStep(flat->model().moving[i].inertia, 1e-3, a);
    const dynamics::BodyState b = (*curved)->getBodyState(body).value().state;
    const double err =
        (dynamics::comPosition_W(a, lambda) - dynamics::comPosition_W(b, lambda)).norm() +
        testing::orientationError(a.M_WB.rotation(), b.M_WB.rotation());
    // Predicted ~6/R² ≈ 6e-8 (doc/curved_space.md's table); 1e-6 leaves a factor 15.
    EXPECT_LE(err, 1e-6) << body;
    EXPECT_GE(err, 1e-12) << body << ": curvature had no effect at all";
  }
}

TEST_P(WorldCurvatureTest, RestAndReset) {
  auto w = curvedWorld(makeScene({movingBody("still", 1.0, {0.1, 0.2, 0.25}, kQ, {0.3, 0, 0}),
                                  movingBody("moving", 1.0, {0.1, 0.2, 0.25}, kQ, {0, 0.3, 0},
                                             {0.1, 0.2, 0.3}, {0.3, 0.2, 0.1})}),
                       GetParam());
  ASSERT_TRUE(w.ok()) << w.error();
  World& world = **w;
  const BodyStateReport still0 = world.getBodyState("still").value();
  const auto psi0 = world.data().bodies[1].curved_state.psi.c;
  world.step(300);
  EXPECT_TRUE(testing::bitwiseEqual(world.getBodyState("still")->state, still0.state));
  EXPECT_NE(world.data().bodies[1].curved_state.psi.c, psi0);
  world.reset();
  EXPECT_EQ(world.data().bodies[1].curved_state.psi.c, psi0);
}

TEST(WorldCurvatureRefusals, NameTheFieldAndTheRule) {
  auto gravity = World::create(
      makeScene({movingBody("b", 1.0, {0.1, 0.1, 0.1})}, Eigen::Vector3d(0, 0, -9.81)), [] {
        WorldConfig c;
        c.curvature = 10.0;
        return c;
      }());
  ASSERT_FALSE(gravity.ok());
  EXPECT_NE(gravity.error().find("config.curvature: needs gravity off"), std::string::npos)
      << gravity.error();

  auto flat = curvedWorld(twoBodies(), 0.0);
  ASSERT_FALSE(flat.ok());
  EXPECT_NE(flat.error().find("config.curvature"), std::string::npos) << flat.error();
  EXPECT_FALSE(curvedWorld(twoBodies(), NAN).ok());

  auto rk4 = curvedWorld(twoBodies(), 10.0, "rk4");
  ASSERT_FALSE(rk4.ok());
  EXPECT_NE(rk4.error().find("config.integrator"), std::string::npos) << rk4.error();

  auto exact = curvedWorld(twoBodies(), 10.0, "curved_exact");
  ASSERT_FALSE(exact.ok());
  EXPECT_NE(exact.error().find("racket"), std::string::npos) << exact.error();
  EXPECT_NE(exact.error().find("isotropic"), std::string::npos) << exact.error();

  // tr S = ½ tr I = 0.6 kg m² of a 1 kg body does not fit a sphere of R = 0.5 m.
  auto big = curvedWorld(makeScene({movingBody("boulder", 1.0, {0.4, 0.4, 0.4})}), 0.5);
  ASSERT_FALSE(big.ok());
  EXPECT_NE(big.error().find("boulder"), std::string::npos) << big.error();
  EXPECT_NE(big.error().find("too large for the space"), std::string::npos) << big.error();

  // Outside the Poincaré ball (|x| ≥ 2|R|).
  auto far = curvedWorld(
      makeScene({movingBody("far", 1.0, {0.1, 0.1, 0.1}, kQ, Eigen::Vector3d(25, 0, 0))}), -10.0);
  ASSERT_FALSE(far.ok());
  EXPECT_NE(far.error().find("Poincare ball"), std::string::npos) << far.error();

  auto w = curvedWorld(twoBodies(), 10.0);
  ASSERT_TRUE(w.ok()) << w.error();
  const auto edit = (*w)->setBodyState("ball", Eigen::Isometry3d::Identity(), {}, {});
  ASSERT_FALSE(edit.ok());
  EXPECT_NE(edit.error().find("set_body_state: not available in curved space"), std::string::npos)
      << edit.error();
  EXPECT_TRUE((*w)->curvedMomentum().size() == 3u);
  // A Euclidean world reports no 4-d momentum.
  EXPECT_TRUE(testing::makeWorld(twoBodies())->curvedMomentum().empty());
}

// Inputs 1 up (curved_bodies.h) on a ball at rest at the chart's origin, where ψ = 1 and the
// world and body axes agree. Truths: the 4-d world momentum gains exactly the moment of an
// impulse, X∧J with X = O = −R e4 the origin, i.e. (0; R j) for a linear impulse j through the
// centre, and (a; 0) for an angular impulse a (doc/curved_space.md, impulses), and keeps it while
// the ball moves on (conservation); a world-axes couple τ held for T adds τ T to the rotational
// part (the ball only turns about its centre, which stays at the origin: each kick's moment,
// carried back into the body at its own pose and forward again by ψ, is τ). Tolerance 1e-12
// relative: a few roundings per step over at most 100 steps.
TEST_P(WorldCurvatureTest, ImpulsesAndWrenchesAddTheirFourDMoments) {
  const double R = GetParam();
  auto w = curvedWorld(makeScene({movingBody("ball", 2.0, {0.4, 0.4, 0.4})}), R);
  ASSERT_TRUE(w.ok()) << w.error();
  World& world = **w;

  ImpulseInput imp;
  imp.body = "ball";
  imp.J.f = {0.3, -0.1, 0.2};
  imp.angular = {0.0, 0.0, 0.5};
  ASSERT_TRUE(world.applyImpulse(imp).ok());
  world.step(50);
  const cga::Bivector4 L1 = world.curvedMomentum().back().L_W;
  const Eigen::Vector3d expect_rot(0.0, 0.0, 0.5), expect_trans = R * imp.J.f;
  EXPECT_LE((L1.rot - expect_rot).norm(), 1e-12 * expect_rot.norm());
  EXPECT_LE((L1.trans - expect_trans).norm(), 1e-12 * expect_trans.norm());
  EXPECT_GT(world.bodyStates().front().pose_root.translation().norm(), 1e-3);  // it moved

  // A second ball, at rest, under a world-axes couple for 100 steps (0.1 s).
  auto w2 = curvedWorld(makeScene({movingBody("ball", 2.0, {0.4, 0.4, 0.4})}), R);
  ASSERT_TRUE(w2.ok()) << w2.error();
  WrenchInput wr;
  wr.body = "ball";
  wr.couple = {0.2, -0.1, 0.3};
  wr.duration = 0.1;
  ASSERT_TRUE((*w2)->applyWrench(wr).ok());
  (*w2)->step(120);
  const cga::Bivector4 L2 = (*w2)->curvedMomentum().back().L_W;
  const Eigen::Vector3d angular = 0.1 * wr.couple;
  EXPECT_LE((L2.rot - angular).norm(), 1e-12 * angular.norm());
  EXPECT_LE(L2.trans.norm(), 1e-12 * angular.norm() * std::abs(R));
  std::printf("[ info ] R = %g: impulse moment error %.1e, couple's angular impulse error %.1e\n",
              R, (L1.trans - expect_trans).norm() / expect_trans.norm(),
              (L2.rot - angular).norm() / angular.norm());
}

// As R → ∞ the inputs act as in flat space: a body-axes force through the centre held for 0.1 s
// on a resting ball moves it by ½ (f/m) t² with speed (f/m) t, to O(1/R²) (≈ 1e-9 at R = 1e4 m
// with the ball's spread; the kick-drift-kick splitting is exact for a constant force in flat
// space), and an impulse through the centre gives it the speed j/m. Tolerance 1e-7 relative.
TEST(WorldCurvature, InputsBecomeTheFlatOnesAsTheRadiusGrows) {
  for (double R : {1e4, -1e4}) {
    auto w = curvedWorld(makeScene({movingBody("ball", 2.0, {0.4, 0.4, 0.4})}), R);
    ASSERT_TRUE(w.ok()) << w.error();
    WrenchInput wr;
    wr.body = "ball";
    wr.frame = "ball";
    wr.F.f = {1.0, 0.5, -0.2};
    wr.duration = 0.1;
    ASSERT_TRUE((*w)->applyWrench(wr).ok());
    (*w)->step(100);
    const BodyStateReport s = (*w)->bodyStates().front();
    const Eigen::Vector3d a = wr.F.f / 2.0;
    const Eigen::Vector3d x = 0.5 * a * 0.01, v = a * 0.1;
    EXPECT_LE((s.pose_root.translation() - x).norm(), 1e-7 * x.norm()) << "R = " << R;
    EXPECT_LE((s.linear_velocity - v).norm(), 1e-7 * v.norm()) << "R = " << R;

    auto w2 = curvedWorld(makeScene({movingBody("ball", 2.0, {0.4, 0.4, 0.4})}), R);
    ImpulseInput imp;
    imp.body = "ball";
    imp.J.f = {0.3, -0.1, 0.2};
    ASSERT_TRUE((*w2)->applyImpulse(imp).ok());
    (*w2)->step(1);
    const Eigen::Vector3d v2 = (*w2)->bodyStates().front().linear_velocity;
    EXPECT_LE((v2 - imp.J.f / 2.0).norm(), 1e-7 * imp.J.f.norm() / 2.0) << "R = " << R;
  }
}

}  // namespace world_curvature_test
}  // namespace sim
}  // namespace cga_rigid_sim
