// The length scale λ of the conformal model must not change any result
// (doc/conventions.md#length-scale-lambda).
#include <gtest/gtest.h>

#include "sim/world_fixtures.h"

namespace cga_rigid_sim {
namespace world_lambda_test {

using testing::makeScene;
using testing::makeWorld;
using testing::movingBody;

scene::Scene sceneWithLambda(double lambda) {
  scene::BodyModel b =
      movingBody("box", 2.0, {0.1, 0.2, 0.25},
                 Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized())),
                 {1.0, -2.0, 0.5}, {0.3, -0.2, 1.1}, {0.4, 0.1, -0.3}, lambda);
  b.links[0].M_BL =
      cga::Motor::fromPose(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())),
                           {0.1, 0, -0.05}, lambda);
  b.links.push_back({"nozzle", cga::Motor::fromPose(Eigen::Quaterniond(Eigen::AngleAxisd(
                                                        1.0, Eigen::Vector3d::UnitX())),
                                                    {0, 0.2, 0}, lambda)});
  return makeScene({b}, Eigen::Vector3d(0, 0, -9.81), lambda);
}

// Truth: λ-independence (doc/conventions.md#length-scale-lambda: λ = 1 and λ = 7.3 give the same
// trajectory to 1e-12 relative). λ enters every conversion of the world (link placements, wrench
// points, impulse moments, setBodyState), so a wrench in a link frame, one in the world frame, an
// impulse and a state override all go through it; 500 steps later poses and velocities agree to
// 1e-12.
TEST(WorldLambda, ResultsDoNotDependOnLambda) {
  auto run = [](double lambda) {
    auto w = makeWorld(sceneWithLambda(lambda));
    sim::WrenchInput thruster;
    thruster.body = "box";
    thruster.frame = "nozzle";
    thruster.F = cga::Force(Eigen::Vector3d(2, 0, 1));
    thruster.point = Eigen::Vector3d(0.05, 0, 0);
    thruster.couple = Eigen::Vector3d(0, 0.1, 0);
    thruster.duration = 0.2;
    EXPECT_TRUE(w->applyWrench(thruster).ok());
    sim::WrenchInput push = thruster;
    push.frame = "world";
    push.point = Eigen::Vector3d(1.1, -2.0, 0.6);
    push.start_time = 0.1;
    EXPECT_TRUE(w->applyWrench(push).ok());
    sim::ImpulseInput kick;
    kick.body = "box";
    kick.frame = "nozzle";
    kick.J = cga::Force(Eigen::Vector3d(0, 0.5, 0));
    kick.point = Eigen::Vector3d(0.1, 0, 0.1);
    kick.start_time = 0.3;
    EXPECT_TRUE(w->applyImpulse(kick).ok());
    w->step(250);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(0.5, 0.5, 2.0);
    EXPECT_TRUE(w->setBodyState("box", pose, {1, 0, 0}, {0, 1, 2}).ok());
    w->step(250);
    return *w->getBodyState("box");
  };
  const auto a = run(1.0), b = run(7.3);
  const double scale = std::max(1.0, a.com.norm());
  EXPECT_LE((a.pose_root.matrix() - b.pose_root.matrix()).cwiseAbs().maxCoeff(), 1e-12 * scale);
  EXPECT_LE((a.com - b.com).norm(), 1e-12 * scale);
  EXPECT_LE((a.linear_velocity - b.linear_velocity).norm(), 1e-12 * a.linear_velocity.norm());
  EXPECT_LE((a.angular_velocity - b.angular_velocity).norm(), 1e-12 * a.angular_velocity.norm());
}

}  // namespace world_lambda_test
}  // namespace cga_rigid_sim
