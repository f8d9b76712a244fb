// The bumper (gazebo_ros_bumper, sensor/sensors.h): the contacts of one link, or of the one
// collision of it that <contact><collision> names, in frameName's frame. Truths: the World's own
// contact list, filtered by hand (by the contact points' side for one collision); a box's
// geometry for the frame (its bottom face at −half its height, its corners at ± half its width).
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
namespace bumper_test {

using Map = scene::ParamValue::Map;
using List = scene::ParamValue::List;

std::unique_ptr<sim::World> makeWorld(const std::string& urdf, sim::WorldConfig config = {},
                                      scene::ParamValue initial = {}) {
  return test::worldFromUrdf(urdf, config, std::move(initial));
}

TEST(Bumper, ListsExactlyTheContactsOfItsLink) {
  // Two boxes on the ground, one with a bumper: the bumper lists the World's contacts whose
  // side a or b is its link, turned so that its link is side a, and no other.
  const std::string box =
      R"(<inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision>)";
  const std::string urdf = R"(<robot name="two"><link name="world"/>
    <link name="a">)" + box +
                           R"(</link><link name="b">)" + box + R"(</link>
    <joint name="ja" type="floating"><parent link="world"/><child link="a"/></joint>
    <joint name="jb" type="floating"><parent link="world"/><child link="b"/><origin xyz="1 0 0"/></joint>
    <gazebo reference="a"><sensor name="bump" type="contact"><contact><collision>a_collision</collision></contact>
      <plugin name="p" filename="libgazebo_ros_bumper.so"><bumperTopicName>bumper_a</bumperTopicName></plugin></sensor></gazebo>
    </robot>)";
  sim::WorldConfig config;
  config.ground_plane = sim::GroundPlane{};
  auto world = makeWorld(urdf, config,
                         Map{{"a", Map{{"position", List{0.0, 0.0, 0.1}}}},
                             {"b", Map{{"position", List{1.0, 0.0, 0.1}}}}});
  Sensors sensors(*world, 1);
  world->step(200);
  const auto all = world->contacts();
  const auto mine = sensors.contacts(0, *world);
  std::size_t expected = 0;
  for (const auto& c : all) expected += (c.link_a == "a" || c.link_b == "a") ? 1 : 0;
  ASSERT_GT(expected, 0u);
  EXPECT_LT(expected, all.size());  // b's contacts exist and are left out
  EXPECT_EQ(mine.size(), expected);
  for (const auto& c : mine) EXPECT_EQ(c.link_a, "a");
}

TEST(Bumper, OnAStaticLinkTurnsItsContactsToPutItOnSideA) {
  // A box resting on a static table whose link has the bumper: the World reports each contact
  // with the moving box as side a; the bumper's list is the same contacts with the sides
  // swapped, the normal turned (from the box towards the table: down) and the friction impulse
  // negated, the normal impulse unchanged.
  const std::string urdf = R"(<robot name="t"><link name="world"/>
    <link name="table"><collision><geometry><box size="1 1 0.1"/></geometry></collision></link>
    <joint name="fix" type="fixed"><parent link="world"/><child link="table"/><origin xyz="0 0 0.5"/></joint>
    <link name="box"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
      <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
    <joint name="free" type="floating"><parent link="world"/><child link="box"/></joint>
    <gazebo reference="table"><sensor name="bump" type="contact">
      <plugin name="p" filename="libgazebo_ros_bumper.so"><bumperTopicName>table_bumper</bumperTopicName></plugin></sensor></gazebo>
    </robot>)";
  auto world = makeWorld(urdf, {}, Map{{"box", Map{{"position", List{0.0, 0.0, 0.66}}}}});
  Sensors sensors(*world, 1);
  world->step(300);
  const auto all = world->contacts();
  const auto mine = sensors.contacts(0, *world);
  ASSERT_GT(all.size(), 0u);
  ASSERT_EQ(mine.size(), all.size());
  for (std::size_t k = 0; k < all.size(); ++k) {
    EXPECT_EQ(all[k].link_b, "table");
    EXPECT_EQ(mine[k].link_a, "table");
    EXPECT_EQ(mine[k].link_b, "box");
    EXPECT_EQ(mine[k].normal, -all[k].normal);
    EXPECT_LT(mine[k].normal.z(), -0.99);
    EXPECT_EQ(mine[k].normal_impulse, all[k].normal_impulse);
    EXPECT_EQ(mine[k].friction_impulse, -all[k].friction_impulse);
  }
}

TEST(Bumper, ReportsOnlyTheCollisionItNames) {
  // A sled with two runners (boxes at y = ±0.2) resting on the ground; the bumper names the
  // right runner (a named collision: its SDF name is "sled_fixed_joint_lump__right_collision_1",
  // sdformat's rule) and lists exactly the contacts on that runner: those at y < 0.
  const std::string urdf = R"(<robot name="s"><link name="world"/>
    <link name="sled"><inertial><mass value="2"/><inertia ixx="0.05" iyy="0.05" izz="0.05" ixy="0" ixz="0" iyz="0"/></inertial>
      <collision><origin xyz="0 0.2 0"/><geometry><box size="0.6 0.1 0.1"/></geometry></collision>
      <collision name="right"><origin xyz="0 -0.2 0"/><geometry><box size="0.6 0.1 0.1"/></geometry></collision></link>
    <joint name="free" type="floating"><parent link="world"/><child link="sled"/></joint>
    <gazebo reference="sled"><sensor name="bump" type="contact">
      <contact><collision>sled_fixed_joint_lump__right_collision_1</collision></contact>
      <plugin name="p" filename="libgazebo_ros_bumper.so"><bumperTopicName>right_runner</bumperTopicName></plugin></sensor></gazebo>
    </robot>)";
  sim::WorldConfig config;
  config.ground_plane = sim::GroundPlane{};
  auto world = makeWorld(urdf, config, Map{{"sled", Map{{"position", List{0.0, 0.0, 0.05}}}}});
  ASSERT_EQ(world->scene().sensors.sensors[0].collision, 1);
  Sensors sensors(*world, 1);
  world->step(200);
  const auto all = world->contacts();
  std::size_t right = 0;
  for (const auto& c : all) right += c.point.y() < 0 ? 1 : 0;
  ASSERT_GT(right, 0u);
  ASSERT_LT(right, all.size());  // the left runner's contacts exist and are left out
  const auto mine = sensors.contacts(0, *world);
  EXPECT_EQ(mine.size(), right);
  for (const auto& c : mine) EXPECT_LT(c.point.y(), -0.14);  // within the right runner
}

TEST(Bumper, FrameNameExpressesTheContactsInThatLink) {
  // A 0.2 m cube resting on the ground, turned 0.5 rad about z and set 1 m off along x, its
  // bumper's frameName the cube's own link: in it the contact points are the bottom corners,
  // (±0.1, ±0.1, −0.1), and the normal (from the ground towards the cube) is +z. Tolerance: the
  // resting penetration of the contact model (the slop, 1e-4 m at most) and rounding.
  const std::string urdf = R"(<robot name="c"><link name="world"/>
    <link name="cube"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
      <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
    <joint name="free" type="floating"><parent link="world"/><child link="cube"/></joint>
    <gazebo reference="cube"><sensor name="bump" type="contact">
      <plugin name="p" filename="libgazebo_ros_bumper.so"><bumperTopicName>cube_bumper</bumperTopicName><frameName>cube</frameName></plugin></sensor></gazebo>
    </robot>)";
  sim::WorldConfig config;
  config.ground_plane = sim::GroundPlane{};
  auto world = makeWorld(
      urdf, config,
      Map{{"cube", Map{{"position", List{1.0, 0.0, 0.1}}, {"rpy", List{0.0, 0.0, 0.5}}}}});
  Sensors sensors(*world, 1);
  world->step(300);
  const auto mine = sensors.contacts(0, *world);
  ASSERT_EQ(mine.size(), world->contacts().size());
  ASSERT_GE(mine.size(), 4u);
  for (const auto& c : mine) {
    EXPECT_NEAR(std::abs(c.point.x()), 0.1, 1e-4) << c.point.transpose();
    EXPECT_NEAR(std::abs(c.point.y()), 0.1, 1e-4) << c.point.transpose();
    EXPECT_NEAR(c.point.z(), -0.1, 1e-4) << c.point.transpose();
    EXPECT_NEAR(c.normal.z(), 1.0, 1e-9) << c.normal.transpose();
  }
  // In the world (no frameName) the same points are far from the link's axes: x near 1.
  EXPECT_GT(world->contacts().front().point.x(), 0.8);
}

}  // namespace bumper_test
}  // namespace sensor
}  // namespace cga_rigid_sim
