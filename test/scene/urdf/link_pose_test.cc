// Every link's initial pose out of the loader, M_WL = M_WB0 M_BL, equals the pose urdfdom's
// own data gives: the joint origins composed from the root down, computed here with urdfdom's
// Pose/Rotation/Vector3 arithmetic, independent of the loader's code path (which composes
// Eigen isometries, moves to the body frame B at the centre of mass and back through motors).
// Run on every scene in urdf/.
//
// Tolerance: both sides take a handful of rotations and additions of numbers ≤ 5 m, each
// accurate to a few ε; 1e-12 m (and 1e-12 on quaternion coefficients) leaves a wide margin
// while any frame error (a wrong offset, a transposed rotation) is of order 1e-2 or more.
#include <gtest/gtest.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"

namespace cga_rigid_sim {
namespace scene {
namespace link_pose_test {

namespace fs = std::filesystem;
constexpr double kTol = 1e-12;

// The pose of `parent ∘ child`: x ↦ R_p (R_c x + t_c) + t_p.
urdf::Pose compose(const urdf::Pose& parent, const urdf::Pose& child) {
  urdf::Pose out;
  const urdf::Vector3 moved = parent.rotation * child.position;
  out.position = urdf::Vector3(parent.position.x + moved.x, parent.position.y + moved.y,
                               parent.position.z + moved.z);
  out.rotation = parent.rotation * child.rotation;
  return out;
}

// World pose of every link (the world link itself excluded), from the root down.
std::map<std::string, urdf::Pose> urdfdomLinkPoses(const urdf::ModelInterface& model,
                                                   const std::string& world_frame) {
  std::map<std::string, urdf::Pose> poses;
  std::vector<std::pair<urdf::LinkConstSharedPtr, urdf::Pose>> stack{
      {model.getRoot(), urdf::Pose()}};
  while (!stack.empty()) {
    const auto [link, pose] = stack.back();
    stack.pop_back();
    if (link->name != world_frame) poses[link->name] = pose;
    for (const auto& joint : link->child_joints)
      stack.emplace_back(model.getLink(joint->child_link_name),
                         compose(pose, joint->parent_to_joint_origin_transform));
  }
  return poses;
}

std::vector<fs::path> exampleScenes() {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(fs::path(CGA_RIGID_SIM_SOURCE_DIR) / "urdf"))
    if (e.path().extension() == ".urdf") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

TEST(LinkPose, ExampleScenesExist) {
  std::vector<std::string> names;
  for (const auto& f : exampleScenes()) names.push_back(f.stem().string());
  for (const char* expected :
       {"tennis_racket", "symmetric_top", "thin_rod", "dumbbell", "projectile", "t_handle",
        "many_bodies", "tabletop", "double_pendulum", "arm7", "satellite"})
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
}

void checkScene(const fs::path& file, double lambda) {
  SCOPED_TRACE(file.string() + ", lambda = " + std::to_string(lambda));
  SceneOptions options;
  options.lambda = lambda;
  const auto scene = loadUrdfFile(file.string(), options);
  ASSERT_TRUE(scene.ok()) << scene.error();
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(file.string());
  ASSERT_TRUE(model);
  const auto poses = urdfdomLinkPoses(*model, options.world_frame);
  ASSERT_FALSE(poses.empty());
  std::size_t links_in_scene = 0;
  for (const auto& b : scene->bodies) links_in_scene += b.links.size();
  EXPECT_EQ(links_in_scene, poses.size());
  for (const auto& [name, pose] : poses) {
    int i = -1;
    const int b = scene->findLink(name, &i);
    ASSERT_GE(b, 0) << "link " << name << " is in no body";
    const BodyModel& body = scene->bodies[b];
    const cga::Motor M_WL = body.M_WB0 * body.links[i].M_BL;
    const Eigen::Vector3d x = M_WL.translation(lambda);
    EXPECT_LT((x - Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z))
                  .cwiseAbs()
                  .maxCoeff(),
              kTol)
        << name << ": " << x.transpose();
    Eigen::Quaterniond q = M_WL.rotation();
    const Eigen::Quaterniond expected(pose.rotation.w, pose.rotation.x, pose.rotation.y,
                                      pose.rotation.z);
    if (q.coeffs().dot(expected.coeffs()) < 0) q.coeffs() = -q.coeffs();  // double cover
    EXPECT_LT((q.coeffs() - expected.coeffs()).cwiseAbs().maxCoeff(), kTol) << name;
    EXPECT_LT(M_WL.normDrift(), kTol) << name;
  }
}

TEST(LinkPose, LoaderPoseEqualsUrdfdomJointChainForEveryExampleScene) {
  for (const auto& file : exampleScenes()) checkScene(file, 1.0);
}

TEST(LinkPose, IndependentOfLambda) {
  for (const auto& file : exampleScenes()) checkScene(file, 7.3);
}

// A root link not named `world` is a free body at the identity; a floating joint below a
// moving body starts a further free body whose pose is the whole joint chain; links fixed to
// `world` form static bodies whose B is the root link frame.
TEST(LinkPose, RootNotWorldFloatingBelowAndStaticBodies) {
  const std::string urdf = R"(<robot name="mixed">
    <link name="base"><inertial><origin xyz="0.1 0.2 0.3" rpy="0.1 0.2 0.3"/><mass value="2"/>
      <inertia ixx="0.1" ixy="0.01" ixz="0" iyy="0.2" iyz="0" izz="0.25"/></inertial></link>
    <joint name="arm_weld" type="fixed"><parent link="base"/><child link="arm"/>
      <origin xyz="0.5 0 0" rpy="0 0.4 0"/></joint>
    <link name="arm"><inertial><mass value="1"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial></link>
    <joint name="drone_float" type="floating"><parent link="arm"/><child link="drone"/>
      <origin xyz="0 0 1" rpy="0.3 0 -0.2"/></joint>
    <link name="drone"><inertial><mass value="1"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.025"/></inertial></link>
  </robot>)";
  const fs::path file = fs::temp_directory_path() / "cga_rigid_sim_link_pose_mixed.urdf";
  {
    std::ofstream out(file);
    out << urdf;
  }
  checkScene(file, 1.0);
  const auto scene = loadUrdfFile(file.string(), SceneOptions());
  ASSERT_TRUE(scene.ok()) << scene.error();
  ASSERT_EQ(scene->bodies.size(), 2u);
  EXPECT_EQ(scene->bodies[0].name, "base");
  EXPECT_EQ(scene->bodies[1].name, "drone");
  EXPECT_FALSE(scene->bodies[0].is_static);

  const std::string with_world = R"(<robot name="statics">
    <link name="world"/>
    <joint name="table_fix" type="fixed"><parent link="world"/><child link="table"/>
      <origin xyz="1 2 0" rpy="0 0 0.5"/></joint>
    <link name="table"/>
    <joint name="lamp_fix" type="fixed"><parent link="table"/><child link="lamp"/>
      <origin xyz="0 0 0.8"/></joint>
    <link name="lamp"/>
    <joint name="ball_float" type="floating"><parent link="table"/><child link="ball"/>
      <origin xyz="0 0 1"/></joint>
    <link name="ball"><inertial><mass value="1"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  </robot>)";
  const fs::path file2 = fs::temp_directory_path() / "cga_rigid_sim_link_pose_statics.urdf";
  {
    std::ofstream out(file2);
    out << with_world;
  }
  checkScene(file2, 1.0);
  const auto s2 = loadUrdfFile(file2.string(), SceneOptions());
  ASSERT_TRUE(s2.ok()) << s2.error();
  ASSERT_EQ(s2->bodies.size(), 2u);
  EXPECT_TRUE(s2->bodies[0].is_static);  // massless static bodies are fine: never stepped
  EXPECT_FALSE(s2->bodies[0].inertia.has_value());
  EXPECT_EQ(s2->bodies[0].links.size(), 2u);
  EXPECT_EQ(s2->bodies[1].name, "ball");
  fs::remove(file);
  fs::remove(file2);
}

}  // namespace link_pose_test
}  // namespace scene
}  // namespace cga_rigid_sim
