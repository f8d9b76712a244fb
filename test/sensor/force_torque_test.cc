// The force-torque sensor (sensor/sensors.h WrenchSample, doc/sensors.md#force-torque): the
// wrench a joint transmits. Truths: at the base of an arm at rest it is the weight of everything
// below and its moment (statics, by hand); in motion its component along the joint's axis is the
// joint's effort, and that is what the inverse dynamics (RNEA, src/tree/inverse_dynamics.cc) of
// the recorded motion gives — a second, independent method.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sensor/sensors.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/world.h"
#include "cga_rigid_sim/tree/articulated_body.h"
#include "common/urdf_world.h"

namespace cga_rigid_sim {
namespace sensor {
namespace force_torque_test {

constexpr double kG = 9.81;

std::unique_ptr<sim::World> makeWorld(const std::string& urdf, scene::ParamValue initial = {}) {
  return test::worldFromUrdf(urdf, {}, std::move(initial));
}

// A two-link arm from a base 1 m up: the shoulder and the elbow turn about `axis`; link 1 (2 kg)
// has its centre 0.3 m out along x, the elbow sits at 0.6 m, link 2 (1 kg) has its centre 0.2 m
// beyond it. A force-torque sensor on the shoulder, in the child frame, parent_to_child.
std::string arm(const std::string& axis, const std::string& direction = "parent_to_child") {
  return R"(<robot name="arm"><link name="world"/>
    <link name="upper"><inertial><origin xyz="0.3 0 0"/><mass value="2"/><inertia ixx="0.01" iyy="0.06" izz="0.06" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <link name="lower"><inertial><origin xyz="0.2 0 0"/><mass value="1"/><inertia ixx="0.005" iyy="0.02" izz="0.02" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <joint name="shoulder" type="continuous"><parent link="world"/><child link="upper"/><origin xyz="0 0 1"/><axis xyz=")" +
         axis + R"("/></joint>
    <joint name="elbow" type="continuous"><parent link="upper"/><child link="lower"/><origin xyz="0.6 0 0"/><axis xyz=")" +
         axis + R"("/></joint>
    <gazebo reference="shoulder"><sensor name="ft" type="force_torque"><force_torque><frame>child</frame>
      <measure_direction>)" +
         direction + R"(</measure_direction></force_torque>
      <plugin name="p" filename="libgazebo_ros_ft_sensor.so"><topicName>ft</topicName></plugin></sensor></gazebo>
    </robot>)";
}

WrenchSample sampleAfterStep(Sensors& sensors, sim::World& world) {
  sensors.remember(0, world);
  world.step();
  EXPECT_TRUE(sensors.ready(0, world));
  return sensors.wrench(0, world, 0);
}

TEST(ForceTorque, AtTheBaseOfAnArmAtRestIsTheWeightAndMomentBelow) {
  // Vertical axes: gravity turns neither joint, the arm stays at rest, stretched along x.
  // The shoulder holds up m g = 3 · 9.81 N and the moment of the weights about its origin:
  // −Σ r_i × m_i g with r = (0.3, 0, 0) for 2 kg and (0.8, 0, 0) for 1 kg: (0, −(0.6 + 0.8) g, 0).
  // Child frame = world axes at q = 0, origin at the shoulder. At rest the momenta change only
  // by the rounding of the tree's step (velocities of ~1e-16 m/s per step, divided by h = 1 ms):
  // 1e-10.
  for (const char* direction : {"parent_to_child", "child_to_parent"}) {
    auto world = makeWorld(arm("0 0 1", direction));
    Sensors sensors(*world, 1);
    ASSERT_TRUE(sensors.measures(0));
    world->step(100);
    const WrenchSample w = sampleAfterStep(sensors, *world);
    const double sign = std::string(direction) == "parent_to_child" ? 1.0 : -1.0;
    EXPECT_LT((w.force - sign * Eigen::Vector3d(0, 0, 3 * kG)).norm(), 1e-10)
        << w.force.transpose();
    EXPECT_LT((w.torque - sign * Eigen::Vector3d(0, -1.4 * kG, 0)).norm(), 1e-10)
        << w.torque.transpose();
  }
}

TEST(ForceTorque, AWrenchAppliedBelowTheJointIsAnExternalLoadNotTheJoints) {
  // The arm of the test above at rest, vertical axes, with a wrench applied to the lower link
  // for the whole run (~apply_wrench): 4 N along z (vertical: it cannot turn the arm) at the
  // lower link's point (0.1, 0, 0) in its frame — the world point (0.7, 0, 1) — plus a couple of
  // (0, 0.5, 0) N m (about y: held by the joints' constraint). The arm stays at rest, so the
  // shoulder carries the weight less the push: (0, 0, 3 g − 4) N, and the moment about it of the
  // weights and of the wrench: (0, −1.4 g, 0) − ((0.7, 0, 0) × (0, 0, 4) + (0, 0.5, 0)) =
  // (0, −1.4 g + 2.8 − 0.5, 0). Statics, by hand. Were the wrench not subtracted, the sensor
  // would read the weight alone (4 N and 2.3 N m off). Tolerance as above: rounding at rest.
  auto world = makeWorld(arm("0 0 1"));
  sim::WrenchInput push;
  push.body = "lower";
  push.frame = "lower";
  push.F.f = Eigen::Vector3d(0, 0, 4);
  push.point = Eigen::Vector3d(0.1, 0, 0);
  push.couple = Eigen::Vector3d(0, 0.5, 0);
  push.duration = -1;  // until cleared
  ASSERT_TRUE(world->applyWrench(push));
  Sensors sensors(*world, 1);
  world->step(100);
  const WrenchSample w = sampleAfterStep(sensors, *world);
  EXPECT_LT((w.force - Eigen::Vector3d(0, 0, 3 * kG - 4)).norm(), 1e-10) << w.force.transpose();
  EXPECT_LT((w.torque - Eigen::Vector3d(0, -1.4 * kG + 2.8 - 0.5, 0)).norm(), 1e-10)
      << w.torque.transpose();
}

TEST(ForceTorque, InMotionEqualsTheInverseDynamicsOfTheRecordedMotion) {
  // Horizontal axes (y): the arm swings under gravity from 0.3 rad with 5 N m held on the
  // shoulder. The sensor's torque about the shoulder axis is the joint's effort; the RNEA gives
  // it from the recorded motion alone: at the step's midpoint (q, q̇ the means of the step's
  // ends) with its mean acceleration q̈ = (q̇(t) − q̇(t − h))/h, a second-order estimate of the
  // step's mean effort: O(h²) off, with h = 1 ms and the arm's rates of a few rad/s, 1e-4 N m.
  // (Taken at the step's end instead, it is O(h) off: 1.2e-2 N m, measured.)
  auto world =
      makeWorld(arm("0 1 0"),
                scene::ParamValue::Map{{"shoulder", scene::ParamValue::Map{{"position", 0.3}}}});
  sim::JointEffortInput effort;
  effort.names = {"shoulder"};
  effort.efforts = {5.0};
  ASSERT_TRUE(world->setJointEfforts(effort));
  Sensors sensors(*world, 1);
  world->step(200);
  const dynamics::TreeState before = world->data().trees[0].state;
  const WrenchSample w = sampleAfterStep(sensors, *world);
  dynamics::TreeState state = world->data().trees[0].state;
  const dynamics::ArticulatedBody& tree = world->model().trees[0].body;
  const Eigen::VectorXd q_dd = (state.v - before.v) / world->config().dt;
  state.q = 0.5 * (state.q + before.q);
  state.v = 0.5 * (state.v + before.v);
  dynamics::TreeKinematics kin;
  dynamics::treeKinematics(tree, state, kin);
  dynamics::BodyMoments gravity;
  dynamics::gravityMoments(tree, kin, world->scene().gravity_W, gravity);
  const Eigen::VectorXd tau = dynamics::inverseDynamics(tree, state, kin, q_dd, gravity);
  EXPECT_NEAR(tau[0], 5.0, 1e-4);  // the RNEA recovers the held effort
  // The child frame's y is the joint's axis (the joint turns the child about it).
  EXPECT_NEAR(w.torque.y(), tau[0], 1e-4) << w.torque.transpose();
  EXPECT_NEAR(w.torque.y(), 5.0, 1e-4);
  // Not at rest: the shoulder carries less than the static weight along the arm's normal.
  EXPECT_GT(std::abs(w.force.norm() - 3 * kG), 1e-3);
}

TEST(ForceTorque, AFixedJointMergedIntoItsBodyIsNotMeasured) {
  const std::string urdf =
      R"(<robot name="r"><link name="a"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <link name="b"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <joint name="weld" type="fixed"><parent link="a"/><child link="b"/><origin xyz="0 0 0.1"/></joint>
    <gazebo><plugin name="p" filename="libgazebo_ros_ft_sensor.so"><jointName>weld</jointName><topicName>ft</topicName></plugin></gazebo></robot>)";
  auto world = makeWorld(urdf);
  Sensors sensors(*world, 1);
  EXPECT_FALSE(sensors.measures(0));
}

}  // namespace force_torque_test
}  // namespace sensor
}  // namespace cga_rigid_sim
