// The bad-URDF corpus (test/scene/bad_urdf/): every file breaks one rule, and loading it must
// return an error — never a crash, never a partial scene — whose message names the file and
// contains the substring(s) listed for it in expected.txt. Truth: the rules of doc/urdf.md. The
// habits of published descriptions the loader repairs by default (doc/urdf.md#inertias-from-cad)
// stay in the corpus: refused under the strict option, loaded with a warning naming the change
// by default.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"

namespace cga_rigid_sim {
namespace scene {
namespace bad_urdf_test {

namespace fs = std::filesystem;

const fs::path kCorpus = fs::path(CGA_RIGID_SIM_SOURCE_DIR) / "test/scene/bad_urdf";

// expected.txt: "<file> <substring>" per line, '#' comments; several lines per file allowed.
// `kind` selects the lines: "" the plain ones and "strict: " (both refusals: every file has one
// of them), or "warns: " (the warnings of a default load), without their prefix.
std::map<std::string, std::vector<std::string>> readExpected(const std::string& kind = "") {
  const std::string kStrict = "strict: ", kWarns = "warns: ";
  std::map<std::string, std::vector<std::string>> expected;
  std::ifstream in(kCorpus / "expected.txt");
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream words(line);
    std::string file, rest;
    words >> file;
    std::getline(words >> std::ws, rest);
    const bool warns = rest.rfind(kWarns, 0) == 0, strict = rest.rfind(kStrict, 0) == 0;
    if (kind == kWarns && warns) expected[file].push_back(rest.substr(kWarns.size()));
    if (kind.empty() && !warns)
      expected[file].push_back(strict ? rest.substr(kStrict.size()) : rest);
  }
  return expected;
}

// The files the loader repairs by default (those with "warns: " lines): refused only when strict.
std::set<std::string> repairedByDefault() {
  std::set<std::string> files;
  for (const auto& [file, warnings] : readExpected("warns: ")) files.insert(file);
  return files;
}

SceneOptions strictOptions() {
  SceneOptions o;
  o.triangle_policy = dynamics::TrianglePolicy::kRefuse;
  return o;
}

TEST(BadUrdfCorpus, HasAtLeastFifteenFilesAndEachIsListed) {
  const auto expected = readExpected();
  std::set<std::string> files;
  for (const auto& entry : fs::directory_iterator(kCorpus))
    if (entry.path().extension() == ".urdf") files.insert(entry.path().filename().string());
  EXPECT_GE(files.size(), 15u);
  for (const auto& f : files) EXPECT_TRUE(expected.count(f)) << f << " has no expected message";
  for (const auto& [f, subs] : expected) {
    EXPECT_TRUE(files.count(f)) << "expected.txt lists " << f << ", which does not exist";
    for (const auto& s : subs) EXPECT_FALSE(s.empty()) << f;
  }
}

TEST(BadUrdfCorpus, EachFileYieldsItsMessage) {
  const auto expected = readExpected();
  ASSERT_FALSE(expected.empty());
  const auto repaired = repairedByDefault();
  for (const auto& [file, substrings] : expected) {
    SCOPED_TRACE(file);
    const std::string path = (kCorpus / file).string();
    const Result<Scene> scene =
        loadUrdfFile(path, repaired.count(file) ? strictOptions() : SceneOptions());
    ASSERT_FALSE(scene.ok()) << "loaded a scene from a bad file";
    EXPECT_NE(scene.error().find(path), std::string::npos) << scene.error();
    for (const auto& s : substrings)
      EXPECT_NE(scene.error().find(s), std::string::npos)
          << "message: " << scene.error() << "\nexpected to contain: " << s;
  }
}

TEST(BadUrdfCorpus, SameMessagesFromAStringNameTheSource) {
  // loadUrdfString names its source ("robot_description") instead of a file. Meshes are
  // resolved relative to the current directory there, so only mesh-free files are compared.
  const auto expected = readExpected();
  for (const auto& [file, substrings] : expected) {
    SCOPED_TRACE(file);
    std::ifstream in(kCorpus / file);
    std::stringstream text;
    text << in.rdbuf();
    if (text.str().find("<mesh") != std::string::npos) continue;
    const Result<Scene> scene =
        loadUrdfString(text.str(), "robot_description",
                       repairedByDefault().count(file) ? strictOptions() : SceneOptions());
    ASSERT_FALSE(scene.ok());
    EXPECT_EQ(scene.error().rfind("robot_description", 0), 0u) << scene.error();
    for (const auto& s : substrings)
      EXPECT_NE(scene.error().find(s), std::string::npos) << scene.error();
  }
}

TEST(BadUrdfCorpus, MissingFileAndDirectoryNameThePath) {
  const std::string missing = (kCorpus / "no_such_file.urdf").string();
  const auto a = loadUrdfFile(missing, SceneOptions());
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.error().find("cannot read URDF file '" + missing + "'"), std::string::npos)
      << a.error();
  const auto b = loadUrdfFile(kCorpus.string(), SceneOptions());
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.error().find("is a directory"), std::string::npos) << b.error();
}

TEST(BadUrdfCorpus, TheRepairedHabitsLoadByDefaultWithAWarningNamingTheChange) {
  const auto warns = readExpected("warns: ");
  ASSERT_GE(warns.size(), 3u);
  for (const auto& [file, substrings] : warns) {
    SCOPED_TRACE(file);
    const auto scene = loadUrdfFile((kCorpus / file).string(), SceneOptions());
    ASSERT_TRUE(scene.ok()) << scene.error();
    std::string all;
    for (const auto& w : scene->warnings) all += w + "\n";
    for (const auto& s : substrings)
      EXPECT_NE(all.find(s), std::string::npos) << "warnings:\n" << all << "expected: " << s;
  }
}

TEST(BadUrdfCorpus, TheTriangleCaseTakesTheNearestPhysicalMoments) {
  // The nearest physical moments of (1, 1, 3) are (1 + 1/3, 1 + 1/3, 3 − 1/3) (projection along
  // (1, 1, −1) onto I1 + I2 = I3).
  const auto scene =
      loadUrdfFile((kCorpus / "06_triangle_inequality.urdf").string(), SceneOptions());
  ASSERT_TRUE(scene.ok()) << scene.error();
  ASSERT_EQ(scene->warnings.size(), 1u);
  EXPECT_NE(scene->warnings[0].find("link 'slab'"), std::string::npos) << scene->warnings[0];
  EXPECT_NE(scene->warnings[0].find("~relax_inertia:=false refuses"), std::string::npos)
      << scene->warnings[0];
  const Eigen::Vector3d J = scene->bodies.at(0).inertia->principalMoments();
  const Eigen::Vector3d expected(4.0 / 3.0, 4.0 / 3.0, 8.0 / 3.0);
  EXPECT_LT((J - expected).cwiseAbs().maxCoeff(), 1e-14) << J.transpose();
}

TEST(BadUrdfCorpus, BadOptionsAreRefused) {
  const std::string good = fs::path(CGA_RIGID_SIM_SOURCE_DIR) / "urdf/symmetric_top.urdf";
  SceneOptions o;
  o.lambda = 0.0;
  EXPECT_NE(loadUrdfFile(good, o).error().find("lambda"), std::string::npos);
  o = SceneOptions();
  o.gravity_W.z() = std::nan("");
  EXPECT_NE(loadUrdfFile(good, o).error().find("gravity_W must be finite"), std::string::npos);
  o = SceneOptions();
  o.world_frame = "";
  EXPECT_NE(loadUrdfFile(good, o).error().find("world_frame"), std::string::npos);
}

}  // namespace bad_urdf_test
}  // namespace scene
}  // namespace cga_rigid_sim
