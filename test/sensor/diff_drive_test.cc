// A differential drive (doc/sensors.md#drives): wheel odometry's dead reckoning
// (sensor/wheel_odometry.h) against the unicycle's circle, and a two-wheeled robot on flat
// ground driven through its wheels' velocity servos as the node's drive drives them (a
// velocity group controller, wheel speeds (v ∓ ω s/2)/r): it follows the unicycle model, and
// its wheel odometry equals the ground truth while the wheels do not slip.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sensor/wheel_odometry.h"
#include "cga_rigid_sim/sim/world.h"

namespace cga_rigid_sim {
namespace sensor {
namespace diff_drive_test {

using Map = scene::ParamValue::Map;
using List = scene::ParamValue::List;

TEST(WheelOdometry, ConstantWheelSpeedsTraceTheUnicyclesCircle) {
  // Truth: wheels rolling s_l, s_r per interval at separation b turn the base by (s_r − s_l)/b
  // on a circle of radius R = b (s_l + s_r) / (2 (s_r − s_l)) about (0, R): after N intervals,
  // θ = N Δθ and (x, y) = (R sin θ, R (1 − cos θ)), whatever N (each step is the exact chord);
  // the rounding of N additions of size |x| ≈ 1 bounds the error: N ε.
  const double b = 0.4, s_l = 0.009, s_r = 0.011;
  const double dtheta = (s_r - s_l) / b, R = b * (s_l + s_r) / (2 * (s_r - s_l));
  for (int N : {1, 10, 1000}) {
    PlanarPose p;
    const double scale = 1000.0 / N;  // the same arc in N pieces
    for (int k = 0; k < N; ++k) p = integrateWheels(p, s_l * scale, s_r * scale, b);
    const double theta = 1000 * dtheta;
    EXPECT_NEAR(p.theta, theta, 1e-13);
    EXPECT_NEAR(p.x, R * std::sin(theta), 1e-12 * N);
    EXPECT_NEAR(p.y, R * (1 - std::cos(theta)), 1e-12 * N);
  }
  // Straight ahead (s_l = s_r): the series branch, exactly s along the heading.
  const PlanarPose q = integrateWheels(PlanarPose{1.0, 2.0, 0.5}, 0.3, 0.3, b);
  EXPECT_DOUBLE_EQ(q.x, 1.0 + 0.3 * std::cos(0.5));
  EXPECT_DOUBLE_EQ(q.y, 2.0 + 0.3 * std::sin(0.5));
  EXPECT_EQ(q.theta, 0.5);
}

// A 6 kg box base on two wheels (radius 0.1 m, 0.4 m apart) and a frictionless ball caster,
// with a diff drive declared the Gazebo way. The wheels' tyres are spheres, so that each touches
// the ground at one point right below its centre, where the unicycle model puts it (a
// cylinder's line contact sits where the detection finds the deepest point — on a slightly
// tilted base its inner edge, 2 cm in: the turn is then 0.4/0.36 of the model's, measured).
std::string robot() {
  const std::string wheel =
      R"(<inertial><mass value="0.5"/><inertia ixx="0.00125" iyy="0.0025" izz="0.00125" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><sphere radius="0.1"/></geometry></collision>)";
  return R"(<robot name="diffbot">
    <link name="base"><inertial><mass value="6"/><inertia ixx="0.05" iyy="0.09" izz="0.12" ixy="0" ixz="0" iyz="0"/></inertial>
      <collision><geometry><box size="0.4 0.3 0.06"/></geometry></collision>
      <collision><origin xyz="-0.15 0 -0.05"/><geometry><sphere radius="0.05"/></geometry><cga_rigid_sim:contact mu="0"/></collision></link>
    <link name="left_wheel">)" +
         wheel + R"(</link><link name="right_wheel">)" + wheel + R"(</link>
    <joint name="left_joint" type="continuous"><parent link="base"/><child link="left_wheel"/><origin xyz="0 0.2 0"/><axis xyz="0 1 0"/><limit effort="5" velocity="50"/></joint>
    <joint name="right_joint" type="continuous"><parent link="base"/><child link="right_wheel"/><origin xyz="0 -0.2 0"/><axis xyz="0 1 0"/><limit effort="5" velocity="50"/></joint>
    <gazebo><plugin name="drive" filename="libgazebo_ros_diff_drive.so"><leftJoint>left_joint</leftJoint><rightJoint>right_joint</rightJoint>
      <wheelSeparation>0.4</wheelSeparation><wheelDiameter>0.2</wheelDiameter><wheelTorque>5</wheelTorque></plugin></gazebo>
  </robot>)";
}

std::unique_ptr<sim::World> driveWorld(double mu = 1.0) {
  scene::SceneOptions options;
  options.initial_state = Map{{"base", Map{{"position", List{0.0, 0.0, 0.1}}}}};
  auto scene = scene::loadUrdfString(robot(), "diffbot.urdf", options);
  EXPECT_TRUE(scene) << scene.error();
  sim::WorldConfig config;
  config.ground_plane = sim::GroundPlane{};
  config.ground_plane->surface.mu = mu;
  auto world = sim::World::create(std::move(*scene), config);
  EXPECT_TRUE(world) << world.error();
  // The node's drive: a velocity group controller on the wheels, p = 10 × wheelTorque.
  const Map controllers{
      {"wheels", Map{{"type", "velocity_controllers/JointGroupVelocityController"},
                     {"joints", List{"left_joint", "right_joint"}}}}};
  const Map gains{{"left_joint", Map{{"p", 50.0}, {"i", 0.0}, {"d", 0.0}}},
                  {"right_joint", Map{{"p", 50.0}, {"i", 0.0}, {"d", 0.0}}}};
  auto loaded = (*world)->loadControllers(controllers, {"wheels"}, gains);
  EXPECT_TRUE(loaded) << loaded.error();
  return std::move(*world);
}

double wheelAngle(const sim::World& world, const std::string& joint) {
  for (const auto& j : world.jointStates())
    if (j.name == joint) return j.position;
  return NAN;
}

TEST(DiffDrive, FollowsTheUnicycleAndItsWheelOdometryTheTruth) {
  // cmd_vel (v, ω) = (0.5 m/s, 0.8 rad/s) → wheels (v ∓ ω s/2)/r = 3.4 and 6.6 rad/s. Once the
  // servos have brought the wheels to speed (1 s), the base moves as the unicycle: its forward
  // speed v and yaw rate ω, and over the next second its chord, to 1e-4 relative (the wheels'
  // contacts creep by the solver's tolerance and the servo lags by its slip; measured 1e-5);
  // the wheel odometry's displacement to 1 mm of the truth's and its turn to 1e-4 rad
  // (measured 1.7e-4 m over 0.49 m and 1e-6 rad).
  auto world = driveWorld();
  const double v = 0.5, w = 0.8, r = 0.1, b = 0.4;
  ASSERT_TRUE(world->commandGroup("wheels", {(v - w * b / 2) / r, (v + w * b / 2) / r}));
  world->step(1000);
  auto truth0 = *world->getBodyState("base");
  PlanarPose odom{truth0.pose_root.translation().x(), truth0.pose_root.translation().y(),
                  std::atan2(truth0.pose_root.linear()(1, 0), truth0.pose_root.linear()(0, 0))};
  const PlanarPose start = odom;
  double left = wheelAngle(*world, "left_joint"), right = wheelAngle(*world, "right_joint");
  for (int k = 0; k < 100; ++k) {
    world->step(10);
    const double l = wheelAngle(*world, "left_joint"), rr = wheelAngle(*world, "right_joint");
    odom = integrateWheels(odom, (l - left) * r, (rr - right) * r, b);
    left = l, right = rr;
  }
  const auto truth1 = *world->getBodyState("base");
  const Eigen::Vector3d vel = truth1.linear_velocity;
  const double yaw = std::atan2(truth1.pose_root.linear()(1, 0), truth1.pose_root.linear()(0, 0));
  EXPECT_NEAR(std::cos(yaw) * vel.x() + std::sin(yaw) * vel.y(), v, 1e-4 * v);
  EXPECT_NEAR(truth1.angular_velocity.z(), w, 1e-4 * w);
  // The unicycle over that second: a turn of ω·1 s, a chord of 2 (v/ω) sin(ω/2).
  const Eigen::Vector3d moved = truth1.pose_root.translation() - truth0.pose_root.translation();
  EXPECT_NEAR(std::hypot(moved.x(), moved.y()), 2 * (v / w) * std::sin(w / 2), 1e-4 * v);
  EXPECT_NEAR(odom.x - start.x, moved.x(), 1e-3);
  EXPECT_NEAR(odom.y - start.y, moved.y(), 1e-3);
  EXPECT_NEAR(std::remainder(odom.theta - yaw, 2 * M_PI), 0.0, 1e-4);
}

TEST(DiffDrive, WheelOdometryDriftsFromTheTruthWhenTheWheelsSlip) {
  // Truth: on ice (μ = 0.02) the ground can push the 7 kg robot forward by at most μ m g ≈ 1.4 N,
  // 0.2 m/s²: over 1 s it gains at most 0.2 m/s, while its wheels, servoed to 2 m/s within a
  // few steps (5 N m at 0.1 m radius against their own small inertia), spin at that speed. The
  // wheel odometry, which assumes rolling, runs ahead of the truth by more than half.
  auto world = driveWorld(0.02);
  const double r = 0.1, b = 0.4;
  ASSERT_TRUE(world->commandGroup("wheels", {2.0 / r, 2.0 / r}));
  const Eigen::Vector3d x0 = world->getBodyState("base")->pose_root.translation();
  PlanarPose odom;
  double left = wheelAngle(*world, "left_joint"), right = wheelAngle(*world, "right_joint");
  for (int k = 0; k < 100; ++k) {
    world->step(10);
    const double l = wheelAngle(*world, "left_joint"), rr = wheelAngle(*world, "right_joint");
    odom = integrateWheels(odom, (l - left) * r, (rr - right) * r, b);
    left = l, right = rr;
  }
  const double moved = (world->getBodyState("base")->pose_root.translation() - x0).norm();
  EXPECT_LT(moved, 0.5 * 0.2 * 1.0 + 1e-3);  // ½ a t² with a ≤ μ g, and a margin of 1 mm
  EXPECT_GT(odom.x, 1.5);                    // the wheels turned as at ~2 m/s
  EXPECT_GT(odom.x - moved, 0.5 * odom.x);
}

}  // namespace diff_drive_test
}  // namespace sensor
}  // namespace cga_rigid_sim
