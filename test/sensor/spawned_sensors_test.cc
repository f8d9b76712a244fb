// Sensors and drives of what ~spawn_urdf brings in (doc/sensors.md#spawned-robots): a robot
// spawned under a namespace has its sensors read from its URDF, their links, joints and frames
// prefixed as its links are, their topics under the namespace (Gazebo's spawn service sets
// every plugin's robotNamespace to it), and they read the spawned bodies; deleting the robot
// takes them out; a single body spawned without a namespace keeps its sensors under its new
// name. Truths: the names by the rules of doc/sensors.md; the readings against the World's own
// body states (ground truth) and the analytic +g of an IMU at rest.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sensor/sensors.h"
#include "cga_rigid_sim/sim/world.h"

namespace cga_rigid_sim {
namespace sensor {
namespace spawned_sensors_test {

const Eigen::Vector3d kZero = Eigen::Vector3d::Zero();

// A two-wheeled cart fixed to nothing: a base with an IMU link on top (fixed joint), two wheels,
// ground truth on the base, a differential drive. Its plugins name a namespace of their own
// (/cart), which a spawn under a namespace replaces.
const std::string kCart = R"(<robot name="cart">
  <link name="base"><inertial><mass value="2"/><inertia ixx="0.02" iyy="0.02" izz="0.02" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="imu_link"><inertial><mass value="0.1"/><inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="imu_joint" type="fixed"><parent link="base"/><child link="imu_link"/><origin xyz="0 0 0.05"/></joint>
  <link name="left_wheel"><inertial><mass value="0.2"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="right_wheel"><inertial><mass value="0.2"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="left_joint" type="continuous"><parent link="base"/><child link="left_wheel"/><origin xyz="0 0.15 0"/><axis xyz="0 1 0"/></joint>
  <joint name="right_joint" type="continuous"><parent link="base"/><child link="right_wheel"/><origin xyz="0 -0.15 0"/><axis xyz="0 1 0"/></joint>
  <gazebo reference="imu_link"><sensor name="imu" type="imu"><update_rate>100</update_rate>
    <plugin name="imu_plugin" filename="libgazebo_ros_imu_sensor.so"><robotNamespace>/cart</robotNamespace><topicName>imu</topicName><updateRateHZ>100</updateRateHZ></plugin></sensor></gazebo>
  <gazebo><plugin name="truth" filename="libgazebo_ros_p3d.so"><robotNamespace>/cart</robotNamespace><bodyName>base</bodyName><topicName>ground_truth</topicName></plugin></gazebo>
  <gazebo><plugin name="drive" filename="libgazebo_ros_diff_drive.so"><robotNamespace>/cart</robotNamespace>
    <leftJoint>left_joint</leftJoint><rightJoint>right_joint</rightJoint><wheelSeparation>0.3</wheelSeparation><wheelDiameter>0.1</wheelDiameter>
    <odometrySource>encoder</odometrySource></plugin></gazebo>
</robot>)";

// A world holding one static slab, in free space without gravity unless given.
std::unique_ptr<sim::World> emptyWorld(const Eigen::Vector3d& gravity = kZero) {
  scene::SceneOptions options;
  options.gravity_W = gravity;
  auto scene = scene::loadUrdfString(
      R"(<robot name="w"><link name="world"/><link name="slab"><collision><geometry><box size="1 1 0.1"/></geometry></collision></link>
      <joint name="fix" type="fixed"><parent link="world"/><child link="slab"/><origin xyz="0 0 -5"/></joint></robot>)",
      "world.urdf", options);
  EXPECT_TRUE(scene) << scene.error();
  auto world = sim::World::create(std::move(*scene), sim::WorldConfig{});
  EXPECT_TRUE(world) << world.error();
  return std::move(*world);
}

Eigen::Isometry3d at(double x, double y) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Eigen::Vector3d(x, y, 0);
  return X;
}

sim::SpawnOptions underNamespace(const std::string& ns) {
  sim::SpawnOptions o;
  o.robot_namespace = ns;
  return o;
}

TEST(SpawnedSensors, ARobotUnderANamespaceBringsItsSensorsAndDriveRenamed) {
  auto world = emptyWorld();
  ASSERT_TRUE(world->scene().sensors.empty());
  ASSERT_TRUE(world->spawnUrdf("r1", kCart, at(0, 0), kZero, kZero, underNamespace("r1")));
  const scene::SensorSet& set = world->scene().sensors;
  ASSERT_EQ(set.sensors.size(), 2u);
  const scene::SensorModel& imu = set.sensors[0];
  EXPECT_EQ(imu.kind, scene::SensorKind::kImu);
  EXPECT_EQ(imu.link, "r1/imu_link");
  EXPECT_EQ(imu.frame_id, "r1/imu_link");  // the tf frame the node publishes for the link
  EXPECT_EQ(imu.topic, "r1/imu");          // robotNamespace /cart replaced by r1
  const scene::SensorModel& truth = set.sensors[1];
  EXPECT_EQ(truth.link, "r1/base");
  EXPECT_EQ(truth.frame_id, "world");
  EXPECT_EQ(truth.topic, "r1/ground_truth");
  ASSERT_EQ(set.drives.size(), 1u);
  const scene::DriveModel& drive = set.drives[0];
  EXPECT_EQ(drive.left_joints, std::vector<std::string>{"r1/left_joint"});
  EXPECT_EQ(drive.right_joints, std::vector<std::string>{"r1/right_joint"});
  EXPECT_EQ(drive.command_topic, "r1/cmd_vel");
  EXPECT_EQ(drive.odometry_topic, "r1/odom");
  EXPECT_EQ(drive.odometry_frame, "r1/odom");
  EXPECT_EQ(drive.robot_base_frame, "r1/base_footprint");
}

TEST(SpawnedSensors, EachCopyReadsItsOwnBodiesAndADeleteTakesItsSensorsOut) {
  // Two copies, at x = 0 and x = 2, drifting in free space: each ground truth reads its own
  // base's pose (the World's state, to rounding: the same numbers through one more product).
  auto world = emptyWorld();
  ASSERT_TRUE(world->spawnUrdf("r1", kCart, at(0, 0), kZero, kZero, underNamespace("r1")));
  ASSERT_TRUE(world->spawnUrdf("r2", kCart, at(2, 0), Eigen::Vector3d(0, 0.3, 0), kZero,
                               underNamespace("r2")));
  world->step(100);
  Sensors sensors(*world, 1);
  ASSERT_EQ(sensors.size(), 4u);
  for (std::size_t k : {std::size_t{1}, std::size_t{3}}) {
    ASSERT_TRUE(sensors.present(k));
    const auto state = world->getBodyState(sensors.model(k).link);
    ASSERT_TRUE(state);
    const OdometrySample o = sensors.odometry(k, *world, 0);
    EXPECT_LT((o.X_RL.translation() - state->pose_root.translation()).norm(), 1e-12);
  }
  EXPECT_NEAR(sensors.odometry(3, *world, 0).X_RL.translation().x(), 2.0, 1e-12);
  EXPECT_NEAR(sensors.odometry(3, *world, 0).X_RL.translation().y(), 0.3 * 0.1, 1e-9);
  ASSERT_TRUE(world->deleteBody("r1"));
  const scene::SensorSet& set = world->scene().sensors;
  ASSERT_EQ(set.sensors.size(), 2u);
  EXPECT_EQ(set.sensors[0].link, "r2/imu_link");
  EXPECT_EQ(set.sensors[1].link, "r2/base");
  ASSERT_EQ(set.drives.size(), 1u);
  EXPECT_EQ(set.drives[0].left_joints.front(), "r2/left_joint");
  Sensors after(*world, 1);
  EXPECT_NEAR(after.odometry(1, *world, 0).X_RL.translation().x(), 2.0, 1e-12);
}

TEST(SpawnedSensors, AnImuOfASpawnedRobotAtRestReadsPlusG) {
  // The cart spawned 2 m above the slab under gravity... held still: gravity on, the cart's base
  // fixed to the world by its URDF root (a rooted robot), so the IMU at rest reads +g up, 9.81
  // (to rounding: the tree at rest moves by ~1e-16 per step, divided by h twice).
  const std::string rooted = std::string(kCart).replace(
      kCart.find("<link name=\"base\">"), 0,
      "<link name=\"world\"/><joint name=\"mount\" type=\"fixed\"><parent link=\"world\"/>"
      "<child link=\"base\"/></joint>");
  auto world = emptyWorld(Eigen::Vector3d(0, 0, -9.81));
  ASSERT_TRUE(world->spawnUrdf("r1", rooted, at(0, 0), kZero, kZero, underNamespace("r1")));
  Sensors sensors(*world, 1);
  ASSERT_EQ(sensors.model(0).kind, scene::SensorKind::kImu);
  sensors.remember(0, *world);
  world->step();
  ASSERT_TRUE(sensors.ready(0, *world));
  const ImuSample s = sensors.imu(0, *world, 0);
  EXPECT_LT((s.linear_acceleration_S - Eigen::Vector3d(0, 0, 9.81)).norm(), 1e-9)
      << s.linear_acceleration_S.transpose();
}

TEST(SpawnedSensors, ASingleBodyKeepsItsSensorsUnderItsNewName) {
  // A box whose root link "box" carries ground truth, spawned as "crate" without a namespace:
  // the body and its root link are renamed "crate" (World::spawnUrdf), and so is its sensor's
  // link; the topic stays the URDF's.
  const std::string box = R"(<robot name="b"><link name="box"><inertial><mass value="1"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <gazebo><plugin name="truth" filename="libgazebo_ros_p3d.so"><bodyName>box</bodyName><topicName>box_truth</topicName></plugin></gazebo></robot>)";
  auto world = emptyWorld();
  ASSERT_TRUE(world->spawnUrdf("crate", box, at(1, 2), kZero, kZero));
  ASSERT_EQ(world->scene().sensors.sensors.size(), 1u);
  EXPECT_EQ(world->scene().sensors.sensors[0].link, "crate");
  EXPECT_EQ(world->scene().sensors.sensors[0].topic, "box_truth");
  Sensors sensors(*world, 1);
  EXPECT_LT((sensors.odometry(0, *world, 0).X_RL.translation() - Eigen::Vector3d(1, 2, 0)).norm(),
            1e-12);
  ASSERT_TRUE(world->deleteBody("crate"));
  EXPECT_TRUE(world->scene().sensors.sensors.empty());
}

}  // namespace spawned_sensors_test
}  // namespace sensor
}  // namespace cga_rigid_sim
