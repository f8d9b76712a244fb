// Ground-truth odometry (gazebo_ros_p3d, sensor/sensors.h). Truth: the link's pose as the World
// reports it (getBodyState's root link pose) and its origin's velocity by a second method, the
// central difference of that pose over ±1 step.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sensor/sensors.h"
#include "cga_rigid_sim/sim/world.h"
#include "common/urdf_world.h"

namespace cga_rigid_sim {
namespace sensor {
namespace odometry_test {

using Map = scene::ParamValue::Map;
using List = scene::ParamValue::List;

std::unique_ptr<sim::World> makeWorld(const std::string& urdf, sim::WorldConfig config = {},
                                      scene::ParamValue initial = {}) {
  return test::worldFromUrdf(urdf, config, std::move(initial));
}

// A body whose centre of mass sits 0.2 m off its link's origin (so the origin's velocity has an
// ω × r part), with a p3d on it.
std::string offCentre(const std::string& p3d) {
  return R"(<robot name="r"><link name="body"><inertial><origin xyz="0.2 0 0"/><mass value="1"/>
    <inertia ixx="0.01" iyy="0.02" izz="0.03" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <gazebo><plugin name="truth" filename="libgazebo_ros_p3d.so"><bodyName>body</bodyName>
    <topicName>odom_truth</topicName>)" +
         p3d + "</plugin></gazebo></robot>";
}

TEST(GroundTruthOdometry, PoseAndTwistOfTheLinkOrigin) {
  auto world = makeWorld(offCentre(""), {},
                         Map{{"body", Map{{"angular_velocity", List{0.5, -1.0, 2.0}},
                                          {"linear_velocity", List{1.0, 0.0, 3.0}}}}});
  Sensors sensors(*world, 3);
  world->step(300);
  const Eigen::Isometry3d before = world->getBodyState("body")->pose_root;
  world->step();
  const OdometrySample o = sensors.odometry(0, *world, 0);
  const Eigen::Isometry3d now = world->getBodyState("body")->pose_root;
  world->step();
  const Eigen::Isometry3d after = world->getBodyState("body")->pose_root;
  // The pose is the World's, bit for bit up to the motor → matrix conversion (a few ε).
  EXPECT_LT((o.X_RL.matrix() - now.matrix()).norm(), 1e-14);
  // Central difference: error (h²/6) |d³x/dt³| ≈ 1e-6 · ω³ r ≈ 1e-6 · 12 · 0.2 < 1e-5 m/s.
  const double h = world->config().dt;
  const Eigen::Vector3d v_fd = (after.translation() - before.translation()) / (2 * h);
  EXPECT_LT((o.linear_R - v_fd).norm(), 1e-5)
      << o.linear_R.transpose() << " vs " << v_fd.transpose();
  // ω from the rotation's central difference: R(t+h) R(t−h)ᵀ ≈ exp(2h [ω]×).
  const Eigen::AngleAxisd turn(after.linear() * before.linear().transpose());
  const Eigen::Vector3d w_fd = turn.angle() * turn.axis() / (2 * h);
  EXPECT_LT((o.angular_R - w_fd).norm(), 1e-5)
      << o.angular_R.transpose() << " vs " << w_fd.transpose();
}

TEST(GroundTruthOdometry, OffsetsAndNoiseAsP3dDeclaresThem) {
  // xyzOffsets add to the position; gaussianNoise σ adds N(0, σ²) to each position and velocity
  // component, reproducibly per (seed, sample).
  auto plain = makeWorld(offCentre(""));
  auto shifted =
      makeWorld(offCentre("<xyzOffsets>1 2 3</xyzOffsets><gaussianNoise>0.5</gaussianNoise>"));
  Sensors a(*plain, 3), b(*shifted, 3);
  const OdometrySample oa = a.odometry(0, *plain, 7), ob = b.odometry(0, *shifted, 7),
                       ob2 = b.odometry(0, *shifted, 7), ob8 = b.odometry(0, *shifted, 8);
  EXPECT_EQ(ob.X_RL.translation(), ob2.X_RL.translation());
  EXPECT_NE(ob.X_RL.translation(), ob8.X_RL.translation());
  // Noise of σ = 0.5 on three components: far below 10σ, and not zero.
  const Eigen::Vector3d d =
      ob.X_RL.translation() - oa.X_RL.translation() - Eigen::Vector3d(1, 2, 3);
  EXPECT_LT(d.norm(), 5.0 * std::sqrt(3.0));
  EXPECT_GT(d.norm(), 0.0);
}

}  // namespace odometry_test
}  // namespace sensor
}  // namespace cga_rigid_sim
