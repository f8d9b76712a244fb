// The node's per-tick outputs written in place (conversions.h fillTfMessage,
// fillMomentumArrayMsg, fillBodyStateArrayMsg) into a message kept from tick to tick.
// Truth: a fresh message of the same reports built by the to…Msg conversions (the form every
// output had before the messages were reused), compared field by field after its serialisation
// — equal bytes mean equal messages — and the names and counts written out by hand. The cases
// are those of a running node: the first tick, ticks with moved bodies, a body spawned, a body
// deleted and another spawned under a new name at the same count (the names must follow the
// topology version), and a tick without subscribers skipped in between. tf made from the body
// states (the node's way when both are subscribed) against World::movingFrames() of real
// Worlds: free bodies with merged links, an articulated tree, a spawn and a delete.
#include <gtest/gtest.h>
#include <ros/serialization.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "cga_rigid_sim/ros/conversions.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/world.h"

namespace cga_rigid_sim {
namespace node {
namespace output_fill_test {

// The serialised bytes of a message: equal bytes, equal messages (every field is written).
template <class M>
std::vector<std::uint8_t> bytesOf(const M& m) {
  const std::uint32_t n = ::ros::serialization::serializationLength(m);
  std::vector<std::uint8_t> out(n);
  ::ros::serialization::OStream stream(out.data(), n);
  ::ros::serialization::serialize(stream, m);
  return out;
}

Eigen::Isometry3d poseOf(double k) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.3 * k, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(k, -2 * k, 0.5 + k);
  return T;
}

// One tick's reports of the bodies `names` (the total last, as World::momentum() has it); the
// numbers depend on the tick so that stale numbers would show.
struct Tick {
  std::vector<sim::FramePose> frames;
  std::vector<sim::MomentumReport> momentum;
  std::vector<sim::BodyStateReport> states;
  ::ros::Time stamp;
};

Tick tickOf(const std::vector<std::string>& names, int tick) {
  Tick t;
  t.stamp = ::ros::Time(0, 10000000u * static_cast<std::uint32_t>(tick));
  for (std::size_t i = 0; i < names.size(); ++i) {
    const double k = static_cast<double>(tick) + 0.1 * static_cast<double>(i);
    t.frames.push_back({"world", names[i], poseOf(k)});
    sim::MomentumReport m;
    m.body = names[i];
    m.linear = {k, 1.0, -k};
    m.angular = {0.5 * k, 0.0, 2.0};
    m.angular_origin = {0.0, k, k};
    m.kinetic_energy = 3.0 * k;
    m.potential_energy = -k;
    t.momentum.push_back(m);
    sim::BodyStateReport s;
    s.name = names[i];
    s.pose_root = poseOf(k);
    s.com = {k, k, 1.0};
    s.linear_velocity = {1.0, -k, 0.0};
    s.angular_velocity = {0.0, 2.0 * k, 1.0};
    s.state.M_WB = cga::Motor::fromPose(Eigen::Quaterniond(poseOf(k).rotation()),
                                        poseOf(k).translation(), 1.0);
    t.states.push_back(s);
  }
  sim::MomentumReport total;
  total.kind = sim::MomentumReport::Kind::kTotal;
  total.body = "total";
  total.kinetic_energy = static_cast<double>(tick);
  total.dissipated_energy = 0.25 * tick;
  t.momentum.push_back(total);
  return t;
}

// The three kept messages and the node's rule for `names`: true when the topology version
// changed since the message's names were written.
struct Kept {
  tf2_msgs::TFMessage tf;
  cga_rigid_sim::MomentumArray momentum;
  cga_rigid_sim::BodyStateArray states;
  std::uint64_t names_version = UINT64_MAX;

  void fill(const Tick& t, std::uint64_t version) {
    const bool names = version != names_version;
    names_version = version;
    fillTfMessage(t.frames, t.stamp, names, &tf);
    fillMomentumArrayMsg(t.momentum, t.stamp, "world", names, &momentum);
    fillBodyStateArrayMsg(t.states, t.stamp, "world", names, &states);
  }
};

void expectFresh(const Kept& kept, const Tick& t, const std::string& when) {
  EXPECT_EQ(bytesOf(kept.tf), bytesOf(toTfMessage(t.frames, t.stamp))) << when;
  EXPECT_EQ(bytesOf(kept.momentum), bytesOf(toMomentumArrayMsg(t.momentum, t.stamp, "world")))
      << when;
  EXPECT_EQ(bytesOf(kept.states), bytesOf(toBodyStateArrayMsg(t.states, t.stamp, "world"))) << when;
}

TEST(OutputFill, EqualsAFreshMessageThroughSpawnDeleteAndRename) {
  Kept kept;
  // Tick 1: the first fill writes everything.
  kept.fill(tickOf({"a", "b", "c"}, 1), 0);
  expectFresh(kept, tickOf({"a", "b", "c"}, 1), "first tick");
  // Ticks 2, 3: the same bodies moved; the numbers and stamps are new, the names kept.
  kept.fill(tickOf({"a", "b", "c"}, 2), 0);
  kept.fill(tickOf({"a", "b", "c"}, 3), 0);
  expectFresh(kept, tickOf({"a", "b", "c"}, 3), "same bodies, tick 3");
  // A body spawned (version 1): one more entry.
  kept.fill(tickOf({"a", "b", "c", "probe"}, 4), 1);
  expectFresh(kept, tickOf({"a", "b", "c", "probe"}, 4), "after a spawn");
  // "a" deleted, "z" spawned at the same tick (version 3): the count is the same again, the
  // names are not.
  kept.fill(tickOf({"b", "c", "probe", "z"}, 5), 3);
  expectFresh(kept, tickOf({"b", "c", "probe", "z"}, 5), "after a delete and a spawn");
  ASSERT_EQ(kept.tf.transforms.size(), 4u);
  EXPECT_EQ(kept.tf.transforms[0].child_frame_id, "b");
  EXPECT_EQ(kept.tf.transforms[3].child_frame_id, "z");
  EXPECT_EQ(kept.momentum.bodies[4].body, "total");
  EXPECT_EQ(kept.states.bodies[0].name, "b");
  // Ticks nobody subscribed to are not filled: the next fill may come several topology
  // versions later, fewer bodies than before.
  kept.fill(tickOf({"c"}, 9), 7);
  expectFresh(kept, tickOf({"c"}, 9), "after skipped ticks");
  // Every body gone: empty arrays, the momentum message keeps its total.
  kept.fill(tickOf({}, 10), 8);
  expectFresh(kept, tickOf({}, 10), "no bodies");
  EXPECT_TRUE(kept.tf.transforms.empty());
  ASSERT_EQ(kept.momentum.bodies.size(), 1u);
  EXPECT_EQ(kept.momentum.bodies[0].body, "total");
}

// The names are written only when asked or when the count changed: with `names` false and the
// same count, the strings stay as they were (this is what saves the work at each tick, and why
// the node passes true on every topology change).
TEST(OutputFill, NamesAreWrittenOnlyWhenAskedOrWhenTheCountChanges) {
  tf2_msgs::TFMessage tf;
  fillTfMessage(tickOf({"a", "b"}, 1).frames, ::ros::Time(1.0), true, &tf);
  fillTfMessage(tickOf({"x", "y"}, 2).frames, ::ros::Time(2.0), false, &tf);
  ASSERT_EQ(tf.transforms.size(), 2u);
  EXPECT_EQ(tf.transforms[1].child_frame_id, "b");
  EXPECT_EQ(tf.transforms[1].header.stamp, ::ros::Time(2.0));  // stamps and numbers: always
  EXPECT_EQ(tf.transforms[1].transform.translation.x, poseOf(2.1).translation().x());
  fillTfMessage(tickOf({"x", "y", "w"}, 3).frames, ::ros::Time(3.0), false, &tf);
  ASSERT_EQ(tf.transforms.size(), 3u);
  EXPECT_EQ(tf.transforms[0].child_frame_id, "x");
  EXPECT_EQ(tf.transforms[2].child_frame_id, "w");
}

// tf from the body states equals tf from the moving frames, byte for byte (same order, names
// and poses), through stepping, a spawn and a delete.
void expectTfFromStatesIsMovingFrames(const sim::World& world, const std::string& when) {
  const ::ros::Time stamp(0.25);
  tf2_msgs::TFMessage from_states;
  fillTfMessage(world.bodyStates(), world.config().world_frame, stamp, true, &from_states);
  EXPECT_FALSE(from_states.transforms.empty()) << when;
  EXPECT_EQ(bytesOf(from_states), bytesOf(toTfMessage(world.movingFrames(), stamp))) << when;
}

std::unique_ptr<sim::World> worldOf(const std::string& urdf_file) {
  auto scene = scene::loadUrdfFile(std::string(CGA_RIGID_SIM_SOURCE_DIR) + "/" + urdf_file,
                                   scene::SceneOptions{});
  EXPECT_TRUE(scene) << scene.error();
  auto world = sim::World::create(std::move(*scene), sim::WorldConfig{});
  EXPECT_TRUE(world) << world.error();
  return std::move(*world);
}

TEST(OutputFill, TfFromBodyStatesIsTheMovingFrames) {
  // Free bodies, one with a link merged by a fixed joint (its root link is not at its centre of
  // mass), and a static table (no moving frame).
  auto bodies = worldOf("test/ros/bodies.urdf");
  ASSERT_TRUE(bodies);
  expectTfFromStatesIsMovingFrames(*bodies, "bodies.urdf at start");
  bodies->step(200);
  expectTfFromStatesIsMovingFrames(*bodies, "bodies.urdf after 200 steps");
  std::ifstream rod_file(std::string(CGA_RIGID_SIM_SOURCE_DIR) + "/urdf/thin_rod.urdf");
  const std::string rod((std::istreambuf_iterator<char>(rod_file)), {});
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(1.0, 2.0, 3.0);
  auto spawned = bodies->spawnUrdf("probe", rod, pose, Eigen::Vector3d(0.1, 0, 0),
                                   Eigen::Vector3d(0, 0.5, 2.0));
  ASSERT_TRUE(spawned) << spawned.error();
  bodies->step(10);
  expectTfFromStatesIsMovingFrames(*bodies, "after a spawn");
  ASSERT_TRUE(bodies->deleteBody("box"));
  bodies->step(10);
  expectTfFromStatesIsMovingFrames(*bodies, "after a delete");

  // An articulated tree: every link is a moving body with its own frame.
  auto pendulum = worldOf("urdf/double_pendulum.urdf");
  ASSERT_TRUE(pendulum);
  pendulum->step(300);
  expectTfFromStatesIsMovingFrames(*pendulum, "double_pendulum.urdf after 300 steps");
}

}  // namespace output_fill_test
}  // namespace node
}  // namespace cga_rigid_sim
