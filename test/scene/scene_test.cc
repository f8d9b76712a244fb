// Scene-level behaviour of the loader: what the scene needs (gravity, static bodies, the
// integrator path each body takes), the summary, look-ups, massless links, and the size the
// many_bodies generator is meant for. Truths: the rules of doc/urdf.md and the path table of
// scene.h (plannedIntegratorPath).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "cga_rigid_sim/scene/scene_summary.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"

namespace cga_rigid_sim {
namespace scene {
namespace scene_test {

const std::string kUrdf = std::string(CGA_RIGID_SIM_SOURCE_DIR) + "/urdf/";

const char* const kMixed = R"(<robot name="mixed">
  <link name="world"><inertial><mass value="5"/>
    <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
  <joint name="table_fix" type="fixed"><parent link="world"/><child link="table"/></joint>
  <link name="table"/>
  <joint name="ball_float" type="floating"><parent link="world"/><child link="ball"/></joint>
  <link name="ball"><inertial><mass value="2"/>
    <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial></link>
  <joint name="top_float" type="floating"><parent link="world"/><child link="top"/></joint>
  <link name="top"><inertial><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.015"/></inertial></link>
  <joint name="marker_weld" type="fixed"><parent link="top"/><child link="marker"/>
    <origin xyz="0 0 0.2"/></joint>
  <link name="marker"/>
</robot>)";

TEST(Scene, StaticAndFreeBodiesInDocumentOrderWithMasslessLinksMerged) {
  const auto s = loadUrdfString(kMixed, "mixed", SceneOptions());
  ASSERT_TRUE(s.ok()) << s.error();
  ASSERT_EQ(s->bodies.size(), 3u);
  EXPECT_EQ(s->bodies[0].name, "table");
  EXPECT_TRUE(s->bodies[0].is_static);
  EXPECT_EQ(s->bodies[1].name, "ball");
  EXPECT_EQ(s->bodies[2].name, "top");
  EXPECT_EQ(s->bodies[2].links.size(), 2u);  // the massless marker merged into the top
  EXPECT_EQ(s->bodies[2].merged_joints, std::vector<std::string>{"marker_weld"});
  EXPECT_EQ(s->findBody("top"), 2);
  EXPECT_EQ(s->findBody("marker"), -1);
  int i = -1;
  EXPECT_EQ(s->findLink("marker", &i), 2);
  EXPECT_EQ(i, 1);
  EXPECT_EQ(s->findLink("world"), -1);
  ASSERT_EQ(s->warnings.size(), 1u);  // the world link's mass is ignored, and said so
  EXPECT_NE(s->warnings[0].find("link 'world' is the world frame"), std::string::npos);
}

TEST(Scene, IntegratorPathsUnderAuto) {
  SceneOptions o;
  auto s = loadUrdfString(kMixed, "mixed", o);
  ASSERT_TRUE(s.ok()) << s.error();
  // Gravity is torque-free: the exact path of each inertia class.
  EXPECT_EQ(plannedIntegratorPath(*s, s->bodies[0], "auto"), "static");
  EXPECT_EQ(plannedIntegratorPath(*s, s->bodies[1], "auto"), "exact-spherical");
  EXPECT_EQ(plannedIntegratorPath(*s, s->bodies[2], "auto"), "exact-symmetric");
  EXPECT_EQ(plannedIntegratorPath(*s, s->bodies[1], "rk4"), "rk4");
  EXPECT_EQ(plannedIntegratorPath(*s, s->bodies[1], "bogus"), "unknown");
  // No gravity: a body at rest stays at rest; a moving one takes its exact path.
  o.gravity_W.setZero();
  o.initial_state = ParamValue::Map{
      {"top", ParamValue::Map{{"angular_velocity", ParamValue::List{0.0, 0.0, 1.0}}}}};
  s = loadUrdfString(kMixed, "mixed", o);
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ(plannedIntegratorPath(*s, s->bodies[1], "auto"), "at-rest");
  EXPECT_EQ(plannedIntegratorPath(*s, s->bodies[2], "auto"), "exact-symmetric");
  EXPECT_TRUE(s->gravity_W.isZero(0.0));
}

TEST(Scene, SummaryShowsBodiesLinksMassMomentsClassPathAndLoads) {
  const auto s = loadUrdfFile(kUrdf + "t_handle.urdf", SceneOptions());
  ASSERT_TRUE(s.ok()) << s.error();
  const std::string text = sceneSummary(*s, "auto");
  for (const char* part :
       {"scene 't_handle'", "1 body (1 moving, 0 static)", "gravity: (0, 0, -9.81)",
        "applied wrenches", "exact+kicks", "shaft: mass 0.8 kg", "J = (0.00302, 0.00442, 0.0074)",
        "asymmetric", "path exact-asymmetric", "links: shaft, bar_left, bar_right",
        "bar_left_weld"})
    EXPECT_NE(text.find(part), std::string::npos) << part << "\n" << text;
  EXPECT_NE(sceneSummary(*s, "nope").find("unknown integrator 'nope'"), std::string::npos);
}

TEST(Scene, SummaryFitsOneScreenForManyBodies) {
  const auto s = loadUrdfFile(kUrdf + "many_bodies.urdf", SceneOptions());
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ(s->bodies.size(), 100u);
  const std::string text = sceneSummary(*s, "auto");
  EXPECT_LE(std::count(text.begin(), text.end(), '\n'), 60);
  EXPECT_NE(text.find("... and 80 more bodies"), std::string::npos) << text;
  EXPECT_NE(text.find("exact-asymmetric x100"), std::string::npos) << text;
}

TEST(Scene, EmptyWorldIsAValidScene) {
  const auto s =
      loadUrdfString("<robot name=\"r\"><link name=\"world\"/></robot>", "empty", SceneOptions());
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_TRUE(s->bodies.empty());
}

TEST(Scene, WorldFrameNameIsAnOption) {
  SceneOptions o;
  o.world_frame = "map";
  const auto s = loadUrdfString(
      "<robot name=\"r\"><link name=\"map\"/><joint name=\"f\" type=\"fixed\"><parent "
      "link=\"map\"/><child link=\"wall\"/></joint><link name=\"wall\"/></robot>",
      "map", o);
  ASSERT_TRUE(s.ok()) << s.error();
  ASSERT_EQ(s->bodies.size(), 1u);
  EXPECT_TRUE(s->bodies[0].is_static);
}

// The generator is deterministic and its output loads (N kept small here; N = 100000 is
// checked by hand, see doc/urdf.md).
TEST(Scene, ManyBodiesGeneratorOutputLoads) {
  namespace fs = std::filesystem;
  const fs::path out = fs::temp_directory_path() / "cga_rigid_sim_many_bodies_test.urdf";
  const std::string cmd = "/usr/bin/python3 " + std::string(CGA_RIGID_SIM_SOURCE_DIR) +
                          "/scripts/generate_many_bodies.py 30 > " + out.string();
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const auto s = loadUrdfFile(out.string(), SceneOptions());
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ(s->bodies.size(), 30u);
  EXPECT_EQ(s->bodies[29].name, "box_29");
  fs::remove(out);
}

}  // namespace scene_test
}  // namespace scene
}  // namespace cga_rigid_sim
