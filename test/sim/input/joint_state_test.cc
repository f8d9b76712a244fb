// set_joint_state (World::setJointState, sim/input/inputs.h JointStateInput): positions and
// rates set by joint name at their step, mimic joints following their leaders, controllers
// holding the new pose, and every refusal rule with nothing applied.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/world.h"

namespace cga_rigid_sim {
namespace sim {
namespace joint_state_test {

using scene::ParamValue;

std::unique_ptr<World> arm(bool gravity = true) {
  scene::SceneOptions options;
  options.gravity_W = {0, 0, gravity ? -9.81 : 0.0};
  auto scene =
      scene::loadUrdfFile(std::string(CGA_RIGID_SIM_SOURCE_DIR) + "/urdf/arm7.urdf", options);
  EXPECT_TRUE(scene.ok()) << scene.error();
  auto world = World::create(std::move(*scene), WorldConfig{});
  EXPECT_TRUE(world.ok()) << world.error();
  return std::move(*world);
}

// Without gravity and efforts a joint set moving at rate v from position p is, one step later,
// where the tree's own dynamics take it; the set itself is exact: at the step it takes effect
// the state is (p, v) before integration, so after a stamped set at step 5 and zero rates the
// arm stays exactly at the set pose (nothing acts on it).
TEST(JointState, SetsPositionsAtTheirStepExactly) {
  auto world = arm(false);
  JointStateInput in;
  in.names = {"joint2", "joint4"};
  in.positions = {0.7, -1.2};
  in.stamp = 5 * world->config().dt;
  ASSERT_TRUE(world->setJointState(in).ok());
  world->step(5);
  EXPECT_EQ(world->data().trees[0].state.q[1], 0.0);  // not yet: due at step 5
  world->step(3);
  EXPECT_EQ(world->data().trees[0].state.q[1], 0.7);  // at rest, nothing acts: exact
  EXPECT_EQ(world->data().trees[0].state.q[3], -1.2);
  EXPECT_EQ(world->data().trees[0].state.v[3], 0.0);
}

// A position-controlled arm set to a new pose stays there (its controller holds it) instead of
// being pulled back to its old reference: after 2 s it is within the servo's sag, G/kp, of the
// set pose (|G| ≤ ~60 N m, kp 4000: 0.015 rad).
TEST(JointState, ControllersHoldTheSetPose) {
  auto world = arm();
  ParamValue::List joints;
  for (int k = 1; k <= 7; ++k) joints.emplace_back("joint" + std::to_string(k));
  ParamValue::Map c, yaml, pid;
  c["type"] = "position_controllers/JointGroupPositionController";
  c["joints"] = ParamValue(joints);
  yaml["arm"] = ParamValue(c);
  for (int k = 1; k <= 7; ++k) {
    ParamValue::Map g;
    g["p"] = 4000.0;
    g["d"] = 150.0;
    pid["joint" + std::to_string(k)] = ParamValue(g);
  }
  ASSERT_TRUE(world->loadControllers(ParamValue(yaml), {}, ParamValue(pid)).ok());
  world->step(100);
  JointStateInput in;
  in.names = {"joint2"};
  in.positions = {0.9};
  ASSERT_TRUE(world->setJointState(in).ok());
  world->step(2000);
  EXPECT_NEAR(world->data().trees[0].state.q[1], 0.9, 0.02);
}

TEST(JointState, BadInputIsRefusedWithNothingApplied) {
  auto world = arm();
  JointStateInput in;
  in.names = {"joint2", "nope"};
  in.positions = {0.1, 0.2};
  EXPECT_EQ(world->setJointState(in).failure().message(),
            "set_joint_state.name[1]: unknown joint 'nope'");
  in.names = {"joint2", "joint2"};
  EXPECT_EQ(world->setJointState(in).failure().message(),
            "set_joint_state.name[1]: joint 'joint2' given twice");
  in.names = {"joint2"};
  in.positions = {3.0};
  EXPECT_EQ(world->setJointState(in).failure().message(),
            "set_joint_state.position[0]: 3 is outside the limits [-2.094395102, 2.094395102] of "
            "joint 'joint2'");
  in.positions = {0.1};
  in.velocities = {5.0};
  EXPECT_EQ(world->setJointState(in).failure().message(),
            "set_joint_state.velocity[0]: 5 is beyond the velocity limit 1.71 of joint 'joint2'");
  in.velocities = {NAN};
  EXPECT_EQ(world->setJointState(in).failure().message(),
            "set_joint_state.velocity[0]: not finite (nan)");
  in.velocities = {0.0, 0.0};
  EXPECT_FALSE(world->setJointState(in).ok());
  EXPECT_EQ(world->queuedInputCount(), 0u);  // nothing was queued
}

}  // namespace joint_state_test
}  // namespace sim
}  // namespace cga_rigid_sim
