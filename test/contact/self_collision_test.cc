// Self-collision rules (doc/contacts.md#self-collision): which pairs of one robot's links the
// World tests, decided once when it is made, from the mode, the URDF's Gazebo <self_collide>, an
// SRDF, and (auto) what overlaps at the initial configuration. Truths: the rules as documented,
// checked pair by pair on an arm whose links two joints apart overlap at the zero pose (as a
// published industrial arm's forearm and palm do), and that a pair left out never makes a
// contact.
#include <gtest/gtest.h>

#include <algorithm>

#include "cga_rigid_sim/scene/urdf/srdf.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/world.h"
#include "common/real_like_robots.h"

namespace cga_rigid_sim {
namespace sim {
namespace self_collision_test {

using Pair = std::pair<std::string, std::string>;
using scene::SelfCollisionMode;

scene::Scene loadArm(const std::string& urdf = test::overlappingArmUrdf()) {
  auto scene = scene::loadUrdfString(urdf, "arm", scene::SceneOptions());
  EXPECT_TRUE(scene.ok()) << scene.error();
  return scene.ok() ? std::move(scene.value()) : scene::Scene();
}

std::unique_ptr<World> makeWorld(scene::Scene scene, SelfCollisionMode mode) {
  WorldConfig config;
  config.self_collision = mode;
  auto w = World::create(std::move(scene), config);
  EXPECT_TRUE(w.ok()) << w.error();
  return w.ok() ? std::move(w.value()) : nullptr;
}

bool has(const std::vector<Pair>& pairs, const std::string& a, const std::string& b) {
  return std::find(pairs.begin(), pairs.end(), Pair(a, b)) != pairs.end() ||
         std::find(pairs.begin(), pairs.end(), Pair(b, a)) != pairs.end();
}

// The arm: base (static) – upper – fore – palm – tip; the palm overlaps the upper arm by 1 cm.
// auto leaves out the four joined pairs and the overlapping one: 10 pairs of 5 bodies with
// shapes, 5 left.
TEST(SelfCollision, AutoLeavesOutJoinedAndInitiallyOverlappingPairs) {
  auto w = makeWorld(loadArm(), SelfCollisionMode::kAuto);
  ASSERT_TRUE(w);
  const auto pairs = w->selfCollisionPairs();
  EXPECT_EQ(pairs.size(), 5u);
  for (const auto& [a, b] :
       std::vector<Pair>{{"base", "upper"}, {"upper", "fore"}, {"fore", "palm"}, {"palm", "tip"}})
    EXPECT_FALSE(has(pairs, a, b)) << a << "–" << b << " are joined";
  EXPECT_FALSE(has(pairs, "upper", "palm")) << "they overlap at the zero pose";
  for (const auto& [a, b] : std::vector<Pair>{
           {"base", "fore"}, {"base", "palm"}, {"base", "tip"}, {"upper", "tip"}, {"fore", "tip"}})
    EXPECT_TRUE(has(pairs, a, b)) << a << "–" << b;
  // The summary says so, with the overlap's depth (the boxes overlap by 1 cm).
  std::string summary;
  for (const auto& line : w->selfCollisionSummary()) summary += line + "\n";
  EXPECT_NE(summary.find("5 of 10 pairs of its links collide"), std::string::npos) << summary;
  EXPECT_NE(summary.find("overlapping at the initial configuration (1): upper–palm 10 mm"),
            std::string::npos)
      << summary;
  // No start-up overlap warning for a pair left out (the rule is said in the summary instead).
  for (const auto& warning : w->scene().warnings)
    EXPECT_EQ(warning.find("overlap"), std::string::npos) << warning;
}

TEST(SelfCollision, AllKeepsOverlappingPairsAndNoneKeepsNothing) {
  auto all = makeWorld(loadArm(), SelfCollisionMode::kAll);
  ASSERT_TRUE(all);
  EXPECT_EQ(all->selfCollisionPairs().size(), 6u);
  EXPECT_TRUE(has(all->selfCollisionPairs(), "upper", "palm"));
  auto none = makeWorld(loadArm(), SelfCollisionMode::kNone);
  ASSERT_TRUE(none);
  EXPECT_TRUE(none->selfCollisionPairs().empty());
}

// A pair left out never makes a contact: under `all` the overlapping palm and upper arm touch
// in the first step; under `auto` no contact ever names them (2 s of the arm swinging from a
// kick).
TEST(SelfCollision, AFilteredPairNeverMakesAContact) {
  const auto touches = [](const World& w) {
    for (const ContactReport& c : w.contacts())
      if ((c.body_a == "palm" && c.body_b == "upper") ||
          (c.body_a == "upper" && c.body_b == "palm"))
        return true;
    return false;
  };
  auto all = makeWorld(loadArm(), SelfCollisionMode::kAll);
  ASSERT_TRUE(all);
  all->step();
  EXPECT_TRUE(touches(*all));
  auto w = makeWorld(loadArm(), SelfCollisionMode::kAuto);
  ASSERT_TRUE(w);
  ImpulseInput kick;
  kick.body = "tip";
  kick.J.f = Eigen::Vector3d(3.0, 2.0, 0.0);
  ASSERT_TRUE(w->applyImpulse(kick).ok());
  for (int k = 0; k < 2000; ++k) {
    w->step();
    ASSERT_FALSE(touches(*w)) << "step " << k;
  }
}

// An SRDF's <disable_collisions> removes a pair that would collide; <disable_default_collisions>
// every pair of a link, <enable_collisions> brings one back (MoveIt's SRDF).
TEST(SelfCollision, SrdfDisablesAndEnablesPairs) {
  scene::Scene s = loadArm();
  const auto err =
      scene::applySrdf(s,
                       "<robot name='arm'>"
                       "<group name='arm'><chain base_link='base' tip_link='tip'/></group>"
                       "<disable_collisions link1='fore' link2='tip' reason='Never'/>"
                       "<disable_default_collisions link='base'/>"
                       "<enable_collisions link1='base' link2='tip'/>"
                       "</robot>",
                       "arm.srdf");
  ASSERT_FALSE(err) << err->message();
  auto w = makeWorld(std::move(s), SelfCollisionMode::kAuto);
  ASSERT_TRUE(w);
  const auto pairs = w->selfCollisionPairs();
  EXPECT_FALSE(has(pairs, "fore", "tip"));
  EXPECT_FALSE(has(pairs, "base", "fore"));
  EXPECT_FALSE(has(pairs, "base", "palm"));
  EXPECT_TRUE(has(pairs, "base", "tip"));
  EXPECT_TRUE(has(pairs, "upper", "tip"));
  EXPECT_EQ(pairs.size(), 2u);
  // `all` ignores the SRDF: it tests every pair but a link and its parent.
  scene::Scene s2 = loadArm();
  ASSERT_FALSE(scene::applySrdf(
      s2, "<robot name='arm'><disable_collisions link1='fore' link2='tip'/></robot>", "arm.srdf"));
  auto w2 = makeWorld(std::move(s2), SelfCollisionMode::kAll);
  ASSERT_TRUE(w2);
  EXPECT_TRUE(has(w2->selfCollisionPairs(), "fore", "tip"));
}

// Bad SRDFs are refused naming the source, the line and the rule; the scene is unchanged.
TEST(SelfCollision, BadSrdfIsRefusedByNameAndLine) {
  const struct {
    const char* xml;
    const char* expected;
  } cases[] = {
      {"<robot><disable_collisions link1='fore' link2='elbow'/></robot>",
       "srdf 'arm.srdf':1: <disable_collisions> link2 'elbow': the URDF has no link of that name"},
      {"<robot>\n<disable_collisions link1='fore'/></robot>",
       "srdf 'arm.srdf':2: <disable_collisions> has no link2 attribute"},
      {"<robot><disable_collisions link1='tip' link2='tip'/></robot>",
       "srdf 'arm.srdf':1: <disable_collisions> names link 'tip' twice"},
      {"<robot><disable_default_collisions/></robot>",
       "srdf 'arm.srdf':1: <disable_default_collisions> has no link attribute"},
      {"<robot><disable_collisions link1='a' link2='b'>", "srdf 'arm.srdf':1: malformed XML"},
      {"<srdf/>", "srdf 'arm.srdf':1: no <robot> element at the top level"},
      {"", "srdf 'arm.srdf': the SRDF is empty"},
  };
  for (const auto& c : cases) {
    scene::Scene s = loadArm();
    const auto err = scene::applySrdf(s, c.xml, "arm.srdf");
    ASSERT_TRUE(err) << c.xml;
    EXPECT_EQ(err->message().rfind(c.expected, 0), 0u) << err->message();
    EXPECT_TRUE(s.self_collision.srdf_disabled.empty());
    EXPECT_FALSE(s.self_collision.hasSrdf());
  }
}

// Gazebo's rule where the URDF carries <self_collide>: two links of one model collide when
// either says true (a link's own value, else the model's, else false).
TEST(SelfCollision, GazeboSelfCollideDecidesWhereTheUrdfSaysIt) {
  std::string urdf = test::overlappingArmUrdf();
  const std::string tail = "</robot>";
  urdf.insert(urdf.size() - tail.size(),
              "<gazebo><self_collide>false</self_collide></gazebo>"
              "<gazebo reference='tip'><self_collide>true</self_collide></gazebo>");
  auto w = makeWorld(loadArm(urdf), SelfCollisionMode::kAuto);
  ASSERT_TRUE(w);
  const auto pairs = w->selfCollisionPairs();
  EXPECT_EQ(pairs.size(), 3u);
  EXPECT_TRUE(has(pairs, "base", "tip"));
  EXPECT_TRUE(has(pairs, "upper", "tip"));
  EXPECT_TRUE(has(pairs, "fore", "tip"));
  // A value that is not a boolean, and a reference to no link, are refused by line.
  std::string bad = test::overlappingArmUrdf();
  bad.insert(bad.size() - tail.size(), "<gazebo><self_collide>maybe</self_collide></gazebo>");
  auto refused = scene::loadUrdfString(bad, "arm", scene::SceneOptions());
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().find("<self_collide> must be true or false (got 'maybe')"),
            std::string::npos)
      << refused.error();
  std::string unknown = test::overlappingArmUrdf();
  unknown.insert(unknown.size() - tail.size(),
                 "<gazebo reference='claw'><self_collide>true</self_collide></gazebo>");
  refused = scene::loadUrdfString(unknown, "arm", scene::SceneOptions());
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().find("'claw' is not a link of this URDF"), std::string::npos)
      << refused.error();
}

// Links of different robots always collide: two copies of the arm side by side (joined by
// nothing) keep every pair between them whatever the mode; a free body too.
// A free 1 kg box of 0.1 m, "ball", spawned at the origin: a body of no robot.
bool spawnBall(World& w) {
  return w
      .spawnUrdf("ball",
                 "<robot name='b'><link name='b'>" + test::boxInertial(1.0, {0.1, 0.1, 0.1}) +
                     test::boxCollision({0.1, 0.1, 0.1}) + "</link></robot>",
                 Eigen::Isometry3d::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero())
      .ok();
}

TEST(SelfCollision, DifferentRobotsAlwaysCollide) {
  auto w = makeWorld(loadArm(), SelfCollisionMode::kNone);
  ASSERT_TRUE(w);
  const Model& m = w->model();
  const int upper = m.findBody("upper"), palm = m.findBody("palm");
  ASSERT_GE(upper, 0);
  EXPECT_FALSE(m.self_collision.collides(upper, palm));
  ASSERT_TRUE(spawnBall(*w));
  const int ball = w->model().findBody("ball");
  EXPECT_TRUE(w->model().self_collision.collides(ball, upper));
  EXPECT_TRUE(w->model().self_collision.collides(palm, ball));
}

// The pair matrix collides() reads agrees with its definition on every pair of bodies: true
// for bodies of different robots or of none, else exactly for the pairs in the sorted list
// `allowed` (found by bisection, as collides() did before the matrix). Checked on the
// overlapping arm, after spawning two copies of it as robots and a free body (appendBody,
// appendRobot) and after deleting the first copy (eraseBodies: the second's indices shift).
TEST(SelfCollision, PairMatrixAgreesWithTheAllowedList) {
  auto w = makeWorld(loadArm(), SelfCollisionMode::kAuto);
  ASSERT_TRUE(w);
  const auto agrees = [&w](const char* when) {
    const SelfCollision& sc = w->model().self_collision;
    const int n = static_cast<int>(sc.robot_of_body.size());
    ASSERT_EQ(n, static_cast<int>(w->model().scene.bodies.size())) << when;
    ASSERT_TRUE(std::is_sorted(sc.allowed().begin(), sc.allowed().end())) << when;
    int listed = 0;
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        if (a == b) continue;
        const int ra = sc.robot_of_body[a];
        const bool in_list = std::binary_search(sc.allowed().begin(), sc.allowed().end(),
                                                std::make_pair(std::min(a, b), std::max(a, b)));
        const bool expected = ra < 0 || ra != sc.robot_of_body[b] || in_list;
        listed += in_list;
        EXPECT_EQ(sc.collides(a, b), expected) << when << ": bodies " << a << ", " << b;
      }
    EXPECT_EQ(listed, 2 * static_cast<int>(sc.allowed().size())) << when;
  };
  agrees("loaded");
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  SpawnOptions options;
  options.robot_namespace = "c1";
  pose.translation().x() = 3.0;
  ASSERT_TRUE(w->spawnUrdf("c1", test::overlappingArmUrdf(), pose, Eigen::Vector3d::Zero(),
                           Eigen::Vector3d::Zero(), options)
                  .ok());
  ASSERT_TRUE(spawnBall(*w));
  options.robot_namespace = "c2";
  pose.translation().x() = -3.0;
  ASSERT_TRUE(w->spawnUrdf("c2", test::overlappingArmUrdf(0.0), pose, Eigen::Vector3d::Zero(),
                           Eigen::Vector3d::Zero(), options)
                  .ok());
  agrees("spawned");
  ASSERT_TRUE(w->deleteBody("c1").ok());
  agrees("deleted");
  w->step(3);  // and detection with it still runs
  agrees("stepped");
}

// The mode's names.
TEST(SelfCollision, ModeNames) {
  EXPECT_EQ(scene::parseSelfCollisionMode("auto"), SelfCollisionMode::kAuto);
  EXPECT_EQ(scene::parseSelfCollisionMode("all"), SelfCollisionMode::kAll);
  EXPECT_EQ(scene::parseSelfCollisionMode("none"), SelfCollisionMode::kNone);
  EXPECT_FALSE(scene::parseSelfCollisionMode("Auto"));
  EXPECT_FALSE(scene::parseSelfCollisionMode(""));
}

}  // namespace self_collision_test
}  // namespace sim
}  // namespace cga_rigid_sim
