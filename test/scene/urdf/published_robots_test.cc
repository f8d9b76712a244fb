// Published robot descriptions nobody here wrote, read from Debian's dart-doc package at test
// time (not copied into the repository; scripts/install_deps.sh installs it): the KUKA KR5 arm
// (CAD placeholders effort="0"), the Barrett WAM (link names with '/', package://herb_description
// meshes, Collada visuals), DRC-Hubo (52 links on a floating torso, package://drchubo meshes) and
// Atlas v3 (package://atlas_description meshes, and a description with an undefined link). The
// package:// URIs are resolved through a package directory of symlinks built in a temporary
// directory. Without dart-doc every test is skipped, and says so. Truths: the files themselves
// (their joints, links, limits and meshes).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "cga_rigid_sim/scene/scene_summary.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"

namespace cga_rigid_sim {
namespace scene {
namespace published_robots_test {

namespace fs = std::filesystem;

const fs::path kData = "/usr/share/doc/dart/data";

class PublishedRobots : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!fs::exists(kData / "urdf/KR5")) return;
    // package://herb_description/meshes/wam/… → urdf/wam/meshes/wam/…,
    // package://drchubo/meshes/… → urdf/drchubo/meshes/…,
    // package://atlas_description/meshes_v3/… → sdf/atlas/….
    packages_ =
        fs::temp_directory_path() / ("cga_rigid_sim_packages_" + std::to_string(::getpid()));
    fs::create_directories(packages_ / "atlas_description");
    fs::create_directory_symlink(kData / "urdf/wam", packages_ / "herb_description");
    fs::create_directory_symlink(kData / "urdf/drchubo", packages_ / "drchubo");
    fs::create_directory_symlink(kData / "sdf/atlas", packages_ / "atlas_description/meshes_v3");
    const char* old = std::getenv("ROS_PACKAGE_PATH");
    old_path_ = old ? old : "";
    had_path_ = old != nullptr;
    ::setenv("ROS_PACKAGE_PATH", packages_.c_str(), 1);
  }
  static void TearDownTestSuite() {
    if (packages_.empty()) return;
    std::error_code ec;
    fs::remove_all(packages_, ec);
    if (had_path_)
      ::setenv("ROS_PACKAGE_PATH", old_path_.c_str(), 1);
    else
      ::unsetenv("ROS_PACKAGE_PATH");
  }
  void SetUp() override {
    if (packages_.empty())
      GTEST_SKIP() << "Debian's dart-doc is not installed (" << kData
                   << " is missing): the published robots are not tested";
  }
  static fs::path packages_;
  static std::string old_path_;
  static bool had_path_;
};
fs::path PublishedRobots::packages_;
std::string PublishedRobots::old_path_;
bool PublishedRobots::had_path_ = false;

std::size_t meshShapes(const Scene& s) {
  std::size_t n = 0;
  for (const auto& b : s.bodies)
    for (const auto& shape : b.shapes) n += shape.kind == CollisionShape::Kind::kMesh ? 1 : 0;
  return n;
}

std::size_t warningsWith(const Scene& s, const std::string& part) {
  std::size_t n = 0;
  for (const auto& w : s.warnings) n += w.find(part) != std::string::npos ? 1 : 0;
  return n;
}

TEST_F(PublishedRobots, Kr5LoadsWithItsZeroEffortPlaceholdersReadAsNoLimit) {
  const auto s = loadUrdfFile((kData / "urdf/KR5/KR5 sixx R650.urdf").string(), SceneOptions());
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ(s->joints.size(), 6u);
  // Six revolute joints, each with <limit effort="0" velocity="…">: no effort limit given.
  EXPECT_EQ(warningsWith(*s, "<limit effort=\"0\"> read as no limit given"), 6u);
  for (const auto& j : s->joints) EXPECT_TRUE(std::isinf(j.limits.effort)) << j.name;
  EXPECT_EQ(meshShapes(*s), 7u);  // one STL per link (meshes/… relative to the file)
}

TEST_F(PublishedRobots, WamLoadsWithItsSlashedLinkNamesAndPackageMeshes) {
  const auto s = loadUrdfFile((kData / "urdf/wam/wam.urdf").string(), SceneOptions());
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ(s->joints.size(), 7u);
  EXPECT_EQ(warningsWith(*s, "is published on tf as"), 8u);
  EXPECT_GE(s->findBody("wam_base"), 0);
  EXPECT_GE(s->findBody("wam7"), 0);
  EXPECT_EQ(s->joints.back().child_link, "wam7");
  EXPECT_EQ(meshShapes(*s), 8u);  // package://herb_description/…_collision.STL
}

TEST_F(PublishedRobots, DrcHuboLoadsWholeAndItsSummaryListsEveryJoint) {
  const auto s = loadUrdfFile((kData / "urdf/drchubo/drchubo.urdf").string(), SceneOptions());
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ(s->bodies.size(), 52u);
  EXPECT_EQ(s->joints.size(), 51u);
  EXPECT_TRUE(s->warnings.empty());
  const std::string text = sceneSummary(*s, "auto");
  for (const auto& j : s->joints)
    EXPECT_NE(text.find("  " + j.name + ": "), std::string::npos) << j.name;
  EXPECT_EQ(text.find(" more "), std::string::npos) << text;
}

TEST_F(PublishedRobots, AtlasLoadsWithoutItsHeadAndIsRefusedWithItsUndefinedHeadLink) {
  const auto headless =
      loadUrdfFile((kData / "sdf/atlas/atlas_v3_no_head.urdf").string(), SceneOptions());
  ASSERT_TRUE(headless.ok()) << headless.error();
  EXPECT_EQ(headless->joints.size(), 27u);
  EXPECT_EQ(meshShapes(*headless), 29u);  // STL collisions (the Collada files are visuals)
  // The full description's defect: joint neck_ry names a child link 'head' it never defines.
  const std::string path = (kData / "sdf/atlas/atlas_v3.urdf").string();
  const auto full = loadUrdfFile(path, SceneOptions());
  ASSERT_FALSE(full.ok());
  EXPECT_NE(full.error().find(path + ":715: joint 'neck_ry': child link 'head' is not defined"),
            std::string::npos)
      << full.error();
}

}  // namespace published_robots_test
}  // namespace scene
}  // namespace cga_rigid_sim
