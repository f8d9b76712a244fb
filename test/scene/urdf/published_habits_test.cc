// The habits of published robot descriptions (doc/urdf.md, README "Published robot
// descriptions"), each on a small robot of test/scene/robots/: what loads and how, what each
// warning names, what the strict option refuses, and the bounds on what the loader reads. Truths:
// the URDF's own numbers (limits, moments, mesh sizes), the projection onto the nearest physical
// moments, the volumes and moments of the Collada boxes.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cga_rigid_sim/scene/scene_summary.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"

namespace cga_rigid_sim {
namespace scene {
namespace published_habits_test {

namespace fs = std::filesystem;

const fs::path kRobots = fs::path(CGA_RIGID_SIM_SOURCE_DIR) / "test/scene/robots";

std::string allWarnings(const Scene& s) {
  std::string all;
  for (const auto& w : s.warnings) all += w + "\n";
  return all;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

SceneOptions strict() {
  SceneOptions o;
  o.triangle_policy = dynamics::TrianglePolicy::kRefuse;
  return o;
}

const JointModel& joint(const Scene& s, const std::string& name) {
  const int k = s.findJoint(name);
  EXPECT_GE(k, 0) << name;
  return s.joints.at(k);
}

TEST(PublishedHabits, MimicJointsLoadResolvedToTheirIndependentLeader) {
  const auto s = loadUrdfFile((kRobots / "knuckle_gripper.urdf").string(), SceneOptions());
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_TRUE(s->warnings.empty()) << allWarnings(*s);
  const int leader = s->findJoint("knuckle_left");
  EXPECT_FALSE(joint(*s, "knuckle_left").mimic);
  EXPECT_FALSE(joint(*s, "wrist").mimic);
  // tip_left = −knuckle_left + 0.1; knuckle_right = −knuckle_left;
  // tip_right = −knuckle_right − 0.1 = knuckle_left − 0.1 (a mimic of a mimic, composed).
  const auto& tl = *joint(*s, "tip_left").mimic;
  EXPECT_EQ(tl.leader, leader);
  EXPECT_EQ(tl.multiplier, -1.0);
  EXPECT_EQ(tl.offset, 0.1);
  const auto& tr = *joint(*s, "tip_right").mimic;
  EXPECT_EQ(tr.leader, leader);
  EXPECT_EQ(tr.multiplier, 1.0);
  EXPECT_EQ(tr.offset, -0.1);
  EXPECT_EQ(tr.written, "knuckle_right");
  // The followers start where the leader (at 0) puts them.
  EXPECT_EQ(joint(*s, "tip_left").initial_position, 0.1);
  EXPECT_EQ(joint(*s, "tip_right").initial_position, -0.1);
  // Every joint's limits mapped to the leader: [−0.2, 0.8] (knuckle_right's [−0.8, 0.2]).
  const auto [lower, upper] = mimicRange(s->joints, leader);
  EXPECT_DOUBLE_EQ(lower, -0.2);
  EXPECT_DOUBLE_EQ(upper, 0.8);
  const std::string summary = sceneSummary(*s, "auto");
  EXPECT_TRUE(contains(summary,
                       "mimics knuckle_left: q = 1 q_knuckle_left + -0.1 rad (through "
                       "knuckle_right)"))
      << summary;
}

TEST(PublishedHabits, MimicInitialStateGoesToTheLeaderAndKeepsTheFollowersInTheirLimits) {
  SceneOptions o;
  o.initial_state = ParamValue::Map{{"knuckle_left", ParamValue::Map{{"position", 0.9}}}};
  auto s = loadUrdfFile((kRobots / "knuckle_gripper.urdf").string(), o);
  ASSERT_TRUE(s.ok()) << s.error();
  // 0.9 is beyond knuckle_left's own limit 0.8: clamped there (knuckle_right at −0.8).
  EXPECT_EQ(joint(*s, "knuckle_left").initial_position, 0.8);
  EXPECT_EQ(joint(*s, "knuckle_right").initial_position, -0.8);
  EXPECT_DOUBLE_EQ(joint(*s, "tip_left").initial_position, -0.7);
  o.initial_state = ParamValue::Map{{"tip_left", ParamValue::Map{{"position", 0.1}}}};
  s = loadUrdfFile((kRobots / "knuckle_gripper.urdf").string(), o);
  ASSERT_FALSE(s.ok());
  EXPECT_TRUE(contains(s.error(),
                       "initial_state.tip_left: joint 'tip_left' mimics joint "
                       "'knuckle_left' (<mimic>)"))
      << s.error();
}

TEST(PublishedHabits, CadInertiasAndMassesAreRepairedWithAWarningNamingLinkAndChange) {
  const auto s = loadUrdfFile((kRobots / "cad_habits.urdf").string(), SceneOptions());
  ASSERT_TRUE(s.ok()) << s.error();
  const std::string w = allWarnings(*s);
  // The dummy link (−1e-22, 2e-22, 3e-6): projected along (1, 1, −1) onto I1 + I2 = I3, by
  // d = (3e-6 − 1e-22)/3 ≈ 1e-6: (1e-6, 1e-6, 2e-6).
  EXPECT_TRUE(contains(w, "link 'flange': inertia breaks the triangle inequality")) << w;
  EXPECT_TRUE(contains(w, "using the nearest physical moments 1e-06, 1e-06, 2e-06 kg m^2")) << w;
  // The camera's real defect: 8.7e-6 + 6.7e-4 < 1.4e-3, d = (1.4e-3 − 6.787e-4)/3.
  const double d = (1.4e-3 - 8.7e-6 - 6.7e-4) / 3;
  std::ostringstream camera;
  camera.precision(10);
  camera << "using the nearest physical moments " << 8.7e-6 + d << ", " << 6.7e-4 + d << ", "
         << 1.4e-3 - d;
  EXPECT_TRUE(contains(w, "link 'camera_link': inertia breaks the triangle inequality")) << w;
  EXPECT_TRUE(contains(w, camera.str())) << w << "expected " << camera.str();
  EXPECT_TRUE(contains(w, "link 'ghost': mass is 0 but the inertia is not")) << w;
  EXPECT_TRUE(contains(w, "the inertia is dropped")) << w;
  // The universal joint's cross carries the 0.8 kg hand: a placeholder of 1e-6 of it.
  EXPECT_TRUE(contains(w,
                       "body 'wrist_cross' has no mass of its own (links 'wrist_cross') but "
                       "moves the 0.8 kg below it: given 8e-07 kg"))
      << w;
  const int cross = s->findBody("wrist_cross");
  ASSERT_GE(cross, 0);
  EXPECT_DOUBLE_EQ(s->bodies[cross].inertia->mass(), 8e-7);
  // The laser frame on a continuous joint moves no mass: welded, and its frame kept.
  EXPECT_TRUE(contains(w,
                       "continuous joint 'laser_spin' moves link 'laser_frame', which carries "
                       "no mass"))
      << w;
  EXPECT_EQ(s->findJoint("laser_spin"), -1);
  int link_index = -1;
  EXPECT_EQ(s->findLink("laser_frame", &link_index), s->findBody("hand"));
  // Every repair says how to refuse it.
  EXPECT_TRUE(contains(w, "~relax_inertia:=false refuses this instead")) << w;
  // Strict: the first of them (document order) is refused, naming the link and the option.
  const auto refused = loadUrdfFile((kRobots / "cad_habits.urdf").string(), strict());
  ASSERT_FALSE(refused.ok());
  EXPECT_TRUE(contains(refused.error(), "inertia breaks the triangle inequality"))
      << refused.error();
  EXPECT_TRUE(contains(refused.error(), "~relax_inertia is false")) << refused.error();
}

TEST(PublishedHabits, ZeroEffortAndVelocityLimitsAreReadAsNoLimitGiven) {
  const auto s = loadUrdfFile((kRobots / "cad_habits.urdf").string(), SceneOptions());
  ASSERT_TRUE(s.ok()) << s.error();
  const JointModel& j = joint(*s, "shoulder");
  EXPECT_EQ(j.limits.effort, std::numeric_limits<double>::infinity());
  EXPECT_EQ(j.limits.velocity, std::numeric_limits<double>::infinity());
  EXPECT_EQ(j.limits.lower, -3.0);
  const std::string w = allWarnings(*s);
  EXPECT_TRUE(contains(w, "joint 'shoulder': <limit effort=\"0\"> read as no limit given")) << w;
  EXPECT_TRUE(contains(w, "joint 'shoulder': <limit velocity=\"0\"> read as no limit given")) << w;
}

TEST(PublishedHabits, LinkNamesWithALeadingSlashArePublishedWithoutIt) {
  const auto s = loadUrdfFile((kRobots / "cad_habits.urdf").string(), SceneOptions());
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_GE(s->findBody("base_link"), 0);
  EXPECT_GE(s->findBody("upper_arm"), 0);
  EXPECT_EQ(s->findBody("/upper_arm"), -1);
  EXPECT_EQ(joint(*s, "shoulder").parent_link, "base_link");
  EXPECT_EQ(joint(*s, "shoulder").child_link, "upper_arm");
  const std::string w = allWarnings(*s);
  EXPECT_TRUE(contains(w, "link '/upper_arm' is published on tf as 'upper_arm'")) << w;
  // The initial-state dictionary knows the link by its tf name.
  SceneOptions o;
  o.initial_state = ParamValue::Map{{"shoulder", ParamValue::Map{{"position", 0.5}}}};
  EXPECT_TRUE(loadUrdfFile((kRobots / "cad_habits.urdf").string(), o).ok());
}

// Box 0.1 × 0.2 × 0.3 m of density 1000: 6 kg, J = m/12 (b² + c², a² + c², a² + b²).
Eigen::Vector3d boxMoments(double a, double b, double c) {
  const double m = 1000 * a * b * c;
  return m / 12 * Eigen::Vector3d(b * b + c * c, a * a + c * c, a * a + b * b);
}

// Each box's mass, principal moments (compared sorted) and extent along z (its up axis once
// read). assimp keeps coordinates as floats (ai_real): each within 2⁻²⁴ ≈ 6e-8 of its value
// (relative), so volumes and moments within a few 1e-7 (relative bound 1e-6).
TEST(PublishedHabits, ColladaMeshesAreReadInTheirUnitWithTheirUpAxisAndTheUrdfScale) {
  const auto s = loadUrdfFile((kRobots / "collada_meshes.urdf").string(), SceneOptions());
  ASSERT_TRUE(s.ok()) << s.error();
  const auto check = [&](const std::string& body, double a, double b, double c) {
    const int k = s->findBody(body);
    ASSERT_GE(k, 0) << body;
    const dynamics::Inertia& I = *s->bodies[k].inertia;
    EXPECT_NEAR(I.mass(), 1000 * a * b * c, 1e-6 * I.mass()) << body;
    Eigen::Vector3d want = boxMoments(a, b, c), got = I.principalMoments();
    std::sort(want.data(), want.data() + 3);
    std::sort(got.data(), got.data() + 3);
    EXPECT_LT((got - want).cwiseAbs().maxCoeff(), 1e-6 * want.maxCoeff())
        << body << ": " << got.transpose();
    // The box's extent along z (the up axis) from its collision mesh.
    double zmin = 1e9, zmax = -1e9;
    for (const auto& x : s->bodies[k].shapes.at(0).mesh.vertices) {
      zmin = std::min(zmin, x.z());
      zmax = std::max(zmax, x.z());
    }
    EXPECT_NEAR(zmax - zmin, c, 1e-6 * c) << body;
  };
  check("mm_box", 0.1, 0.2, 0.3);      // 100 × 200 × 300 mm, Z_UP
  check("scaled_box", 0.2, 0.2, 0.3);  // the same, scale 2 along x
  check("y_up_box", 0.1, 0.3, 0.2);    // 0.1 × 0.2 × 0.3 m, Y_UP: its y (0.2 m) along z
  const std::string w = allWarnings(*s);
  EXPECT_TRUE(contains(w,
                       "box_m_y_up.dae' declares <up_axis>Y_UP</up_axis>: turned so that its "
                       "up axis is +z"))
      << w;
  EXPECT_FALSE(contains(w, "box_mm_z_up.dae' declares")) << w;
}

TEST(PublishedHabits, AnUnresolvablePackageNamesTheFirstMeshInTheDocument) {
  // Links named so that their alphabetical order (urdfdom's map) is not the document's.
  const std::string xml = R"(<robot name="r"><link name="world"/>
    <joint name="j1" type="fixed"><parent link="world"/><child link="zeta"/></joint>
    <link name="zeta"><collision><geometry><mesh filename="package://no_pkg/meshes/first.stl"/></geometry></collision></link>
    <joint name="j2" type="fixed"><parent link="world"/><child link="alpha"/></joint>
    <link name="alpha"><collision><geometry><mesh filename="package://no_pkg/meshes/second.stl"/></geometry></collision></link>
    </robot>)";
  const auto s = loadUrdfString(xml, "robot_description", SceneOptions());
  ASSERT_FALSE(s.ok());
  EXPECT_TRUE(contains(s.error(), "link 'zeta'")) << s.error();
  EXPECT_TRUE(contains(s.error(), "package://no_pkg/meshes/first.stl")) << s.error();
  EXPECT_TRUE(contains(s.error(), "package 'no_pkg' not found")) << s.error();
}

// A chain of n links joined by fixed joints: the depth bound's input.
std::string chain(int n) {
  std::ostringstream os;
  os << "<robot name=\"chain\">\n<link name=\"l0\"/>\n";
  for (int k = 1; k <= n; ++k)
    os << "<joint name=\"j" << k << "\" type=\"fixed\"><parent link=\"l" << k - 1
       << "\"/><child link=\"l" << k << "\"/></joint><link name=\"l" << k << "\"/>\n";
  os << "</robot>\n";
  return os.str();
}

TEST(PublishedHabits, DescriptionsBeyondTheLoadersBoundsAreRefusedNamingTheBound) {
  // Depth: the chain of kMaxUrdfDepth joints loads (a massless free body is refused for its
  // mass, after urdfdom), one more is refused before urdfdom sees it.
  const auto deepest = loadUrdfString(chain(kMaxUrdfDepth), "robot_description", SceneOptions());
  ASSERT_FALSE(deepest.ok());
  EXPECT_TRUE(contains(deepest.error(), "has no mass")) << deepest.error();
  const auto deeper = loadUrdfString(chain(kMaxUrdfDepth + 1), "robot_description", SceneOptions());
  ASSERT_FALSE(deeper.ok());
  EXPECT_TRUE(contains(deeper.error(), "kMaxUrdfDepth")) << deeper.error();
  EXPECT_TRUE(contains(deeper.error(),
                       "link 'l1001' is more than 1000 joints below the root link "
                       "'l0'"))
      << deeper.error();
  // 200 000 links on floating joints would load (the bound); one more link is refused.
  std::string many = "<robot name=\"heap\"><link name=\"world\"/>";
  for (int k = 0; k < kMaxUrdfLinks; ++k) many += "<link name=\"b" + std::to_string(k) + "\"/>";
  many += "</robot>";
  const auto heap = loadUrdfString(many, "robot_description", SceneOptions());
  ASSERT_FALSE(heap.ok());
  EXPECT_TRUE(contains(heap.error(), "the robot has more than 200000 links")) << heap.error();
  EXPECT_TRUE(contains(heap.error(), "kMaxUrdfLinks")) << heap.error();
  // Text: one byte past kMaxUrdfBytes.
  const std::string huge(kMaxUrdfBytes + 1, ' ');
  const auto big = loadUrdfString(huge, "robot_description", SceneOptions());
  ASSERT_FALSE(big.ok());
  EXPECT_TRUE(contains(big.error(), "kMaxUrdfBytes")) << big.error();
}

// A humanoid-sized robot: 50 revolute joints on a floating torso (a chain per limb). The summary
// lists every body and joint, and a scene past the lists' lengths says where the rest is.
std::string humanoid(int joints) {
  const char* inertial =
      "<inertial><mass value=\"1\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" "
      "iyz=\"0\" izz=\"0.01\"/></inertial>";
  std::ostringstream os;
  os << "<robot name=\"humanoid\"><link name=\"torso\">" << inertial << "</link>";
  for (int k = 0; k < joints; ++k) {
    const std::string parent = k % 10 == 0 ? "torso" : "link" + std::to_string(k - 1);
    os << "<joint name=\"joint" << k << "\" type=\"revolute\"><parent link=\"" << parent
       << "\"/><child link=\"link" << k << "\"/><origin xyz=\"0 0 0.1\"/><axis xyz=\"0 1 0\"/>"
       << "<limit lower=\"-1\" upper=\"1\" effort=\"50\" velocity=\"5\"/></joint><link name=\"link"
       << k << "\">" << inertial << "</link>";
  }
  os << "</robot>";
  return os.str();
}

TEST(PublishedHabits, TheSummaryOfAFiftyJointRobotListsItWhole) {
  const auto s = loadUrdfString(humanoid(50), "robot_description", SceneOptions());
  ASSERT_TRUE(s.ok()) << s.error();
  const std::string text = sceneSummary(*s, "auto");
  EXPECT_TRUE(contains(text, "  link49: mass 1 kg")) << text;
  EXPECT_TRUE(contains(text, "  joint49: revolute, link48 -> link49")) << text;
  EXPECT_FALSE(contains(text, "more")) << text;
  // 120 joints: the lists are cut at 60 and say where the rest is.
  SummaryOptions o;
  o.whole_list = "see there";
  const auto big = loadUrdfString(humanoid(120), "robot_description", SceneOptions());
  ASSERT_TRUE(big.ok()) << big.error();
  const std::string cut = sceneSummary(*big, "auto", o);
  EXPECT_TRUE(contains(cut, "  ... and 61 more bodies of articulated trees (see there)")) << cut;
  EXPECT_TRUE(contains(cut, "  ... and 60 more joints (see there)")) << cut;
  o.max_bodies = o.max_robot_entries = 0;
  const std::string all = sceneSummary(*big, "auto", o);
  EXPECT_TRUE(contains(all, "  joint119: revolute")) << all;
  EXPECT_FALSE(contains(all, "more joints")) << all;
}

}  // namespace published_habits_test
}  // namespace scene
}  // namespace cga_rigid_sim
