// Impulses: the velocity jump ΔΩ_B = (I∧n)⁻¹ T_imp at the start of the step the stamp is in.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/world_fixtures.h"

namespace cga_rigid_sim {
namespace world_impulse_test {

using testing::kEps;
using testing::makeScene;
using testing::makeWorld;
using testing::momentumOf;
using testing::movingBody;

const Eigen::Quaterniond kR0(Eigen::AngleAxisd(1.1, Eigen::Vector3d(-1, 2, 0.5).normalized()));

scene::Scene tumbler() {
  return makeScene({movingBody("box", 3.0, {0.1, 0.2, 0.25}, kR0, {0.5, -1.0, 2.0},
                               {0.3, -0.2, 1.1}, {0.4, 0.1, -0.3})});
}

// Truth: the impulse-momentum laws, Δp = J and ΔL_com = r × J + J_ang with r = p − x_c, for an
// impulse in the world frame on a tumbling body. Measured one step later: the torque-free step
// after the jump conserves p and L_com (to the integrator's round-off for the exact free paths),
// so the tolerance is 1e-12 of the momenta involved.
TEST(WorldImpulse, OffComImpulseChangesMomentaByJAndRCrossJ) {
  auto w = makeWorld(tumbler());
  const auto before = momentumOf(*w, "box");
  const Eigen::Vector3d x_c = w->getBodyState("box")->com;
  sim::ImpulseInput in;
  in.body = "box";
  in.frame = "world";
  in.J = cga::Force(Eigen::Vector3d(0.7, -0.4, 1.2));
  const Eigen::Vector3d r(0.15, 0.05, -0.1);
  in.point = x_c + r;
  in.angular = Eigen::Vector3d(0.01, 0.02, -0.03);
  ASSERT_TRUE(w->applyImpulse(in).ok());
  w->step();
  const auto after = momentumOf(*w, "box");
  const Eigen::Vector3d dp = after.linear - before.linear;
  const Eigen::Vector3d dL = after.angular - before.angular;
  EXPECT_LE((dp - in.J.f).norm(), 1e-12 * std::max(before.linear.norm(), after.linear.norm()));
  const Eigen::Vector3d dL_expected = r.cross(in.J.f) + in.angular;
  EXPECT_LE((dL - dL_expected).norm(),
            1e-12 * std::max(before.angular.norm(), after.angular.norm()))
      << dL.transpose() << " vs " << dL_expected.transpose();
}

// Truth: an impulse in a link frame L is in that link's axes at the current pose:
// J_W = R_WB R_BL J_L, p_W = M_WB M_BL p_L, angular_W = R_WB R_BL angular_L; then the same
// impulse-momentum laws as above. Same tolerance.
TEST(WorldImpulse, LinkFrameImpulseIsInTheLinkAxesAtTheCurrentPose) {
  scene::Scene sc = tumbler();
  const cga::Motor M_BL = cga::Motor::fromPose(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.8, Eigen::Vector3d(0, 1, 1).normalized())),
      {0.2, -0.1, 0.05}, 1.0);
  sc.bodies[0].links.push_back({"handle", M_BL});
  auto w = makeWorld(sc);
  w->step(37);  // somewhere along the tumble
  const auto before = momentumOf(*w, "box");
  const auto s = w->getBodyState("box");
  sim::ImpulseInput in;
  in.body = "box";
  in.frame = "handle";
  in.J = cga::Force(Eigen::Vector3d(-0.3, 0.9, 0.2));
  in.point = Eigen::Vector3d(0.02, 0.03, -0.04);
  in.angular = Eigen::Vector3d(0.05, 0, 0.01);
  ASSERT_TRUE(w->applyImpulse(in).ok());
  w->step();
  const auto after = momentumOf(*w, "box");
  const cga::Motor M_WL = s->state.M_WB * M_BL;
  const Eigen::Vector3d J_W = M_WL.transformVector(in.J.f);
  const Eigen::Vector3d r = M_WL.transformPoint(in.point, 1.0) - s->com;
  const Eigen::Vector3d dL_expected = r.cross(J_W) + M_WL.transformVector(in.angular);
  EXPECT_LE((after.linear - before.linear - J_W).norm(), 1e-12 * after.linear.norm());
  EXPECT_LE((after.angular - before.angular - dL_expected).norm(), 1e-12 * after.angular.norm());
}

// Truth: the stamp rule. An impulse stamped s acts at the start of step floor(s/dt + 1e-9):
// before that step the body coasts (v unchanged, bitwise, for a free body at constant velocity
// and no spin), after it v has jumped by J/m. Stamps inside a step (4.7 dt) belong to it.
TEST(WorldImpulse, AppliedAtTheStartOfTheStepItsStampFallsIn) {
  for (const double stamp_steps : {5.0, 4.7, 0.0}) {
    auto w = makeWorld(makeScene({movingBody("box", 2.0, {1, 1, 1})}));
    const double dt = w->config().dt;
    const int k = static_cast<int>(std::floor(stamp_steps));
    sim::ImpulseInput in;
    in.body = "box";
    in.J = cga::Force(Eigen::Vector3d(0, 0, 4.0));
    in.start_time = stamp_steps * dt;
    ASSERT_TRUE(w->applyImpulse(in).ok());
    w->step(k);
    EXPECT_EQ(w->getBodyState("box")->linear_velocity.z(), 0.0) << stamp_steps;
    EXPECT_EQ(w->queuedInputCount(), 1u);
    w->step();
    EXPECT_EQ(w->getBodyState("box")->linear_velocity.z(), 2.0) << stamp_steps;
    EXPECT_EQ(w->queuedInputCount(), 0u);
    // The jump came before the step's integration: the body moved v dt in that step.
    EXPECT_NEAR(w->getBodyState("box")->com.z(), 2.0 * dt, 4 * kEps);
  }
}

}  // namespace world_impulse_test
}  // namespace cga_rigid_sim
