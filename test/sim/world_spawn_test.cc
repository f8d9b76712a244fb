// spawnUrdf and deleteBody: the set of bodies changes while the world runs.
#include <gtest/gtest.h>

#include "sim/world_fixtures.h"

namespace cga_rigid_sim {
namespace world_spawn_test {

using testing::makeScene;
using testing::makeWorld;
using testing::momentumOf;
using testing::movingBody;
using testing::staticBody;

// (Eigen's {} leaves a vector uninitialised: spell zero out.)
const Eigen::Vector3d kZero = Eigen::Vector3d::Zero();

// A crate: base link with its CoM off the link origin, and a lid merged by a fixed joint.
const char* const kCrateUrdf = R"(<?xml version="1.0"?>
<robot name="crate">
  <link name="crate_base">
    <inertial>
      <origin xyz="0.1 0 0" rpy="0 0 0"/>
      <mass value="2.0"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.25"/>
    </inertial>
  </link>
  <link name="crate_lid">
    <inertial>
      <origin xyz="0 0 0" rpy="0 0 0"/>
      <mass value="0.5"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
    </inertial>
  </link>
  <joint name="lid_joint" type="fixed">
    <parent link="crate_base"/>
    <child link="crate_lid"/>
    <origin xyz="0 0 0.2" rpy="0 0 0"/>
  </joint>
</robot>
)";

// A URDF whose only body is fixed to the world: not spawnable.
const char* const kFixedUrdf = R"(<?xml version="1.0"?>
<robot name="post">
  <link name="world"/>
  <link name="post">
    <inertial>
      <mass value="1.0"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/>
    </inertial>
  </link>
  <joint name="post_joint" type="fixed">
    <parent link="world"/>
    <child link="post"/>
  </joint>
</robot>
)";

scene::Scene base() {
  return makeScene(
      {movingBody("a", 1.0, {0.1, 0.2, 0.3}, Eigen::Quaterniond::Identity(), {0, 0, 1}, {0, 0, 1}),
       movingBody("b", 2.0, {0.2, 0.2, 0.3}, Eigen::Quaterniond::Identity(), {1, 0, 1}, {1, 0, 0}),
       movingBody("c", 3.0, {0.3, 0.3, 0.3}, Eigen::Quaterniond::Identity(), {2, 0, 1}, {0, 1, 0},
                  {0, 0, 0.5}),
       staticBody("floor")},
      Eigen::Vector3d(0, 0, -9.81));
}

Eigen::Isometry3d somePose() {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  p.translation() = Eigen::Vector3d(0.5, -1.0, 3.0);
  return p;
}

// Truth: spawnUrdf's contract (world.h). The body appears under the given name (its root link
// renamed), placed at pose_root with the given velocities (1e-12: the set/get round trip),
// keeps its other links, is stepped under the world's gravity (Δv = g·t over 100 free steps,
// 1e-12), bumps topologyVersion, and reset() brings it back to that placement bitwise.
TEST(WorldSpawn, SpawnedBodyIsPlacedRenamedAndStepped) {
  auto w = makeWorld(base());
  const auto version = w->topologyVersion();
  const Eigen::Vector3d v(0.1, 0.2, 0.3), omega(0.0, 0.5, -0.5);
  auto r = w->spawnUrdf("crate1", kCrateUrdf, somePose(), v, omega);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(w->topologyVersion(), version + 1);
  const auto s = w->getBodyState("crate1");
  ASSERT_TRUE(s.ok());
  EXPECT_LE((s->pose_root.matrix() - somePose().matrix()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LE((s->linear_velocity - v).norm(), 1e-12);
  EXPECT_LE((s->angular_velocity - omega).norm(), 1e-12);
  const auto& body = w->scene().bodies.back();
  EXPECT_EQ(body.name, "crate1");
  EXPECT_EQ(body.links.front().link, "crate1");
  ASSERT_EQ(body.links.size(), 2u);
  EXPECT_EQ(body.links[1].link, "crate_lid");
  bool lid_frame = false;
  for (const auto& f : w->staticFrames())
    if (f.parent == "crate1" && f.child == "crate_lid") {
      lid_frame = true;
      EXPECT_LE((f.pose.translation() - Eigen::Vector3d(0, 0, 0.2)).norm(), 1e-12);
    }
  EXPECT_TRUE(lid_frame);
  sim::WrenchInput in;  // its links are frames of the new body
  in.body = "crate1";
  in.frame = "crate_lid";
  EXPECT_TRUE(w->applyWrench(in).ok());
  w->clearWrenches();

  const auto initial = testing::stateOf(*w, "crate1");
  const double m = momentumOf(*w, "crate1").linear.norm() / v.norm();
  EXPECT_NEAR(m, 2.5, 1e-12);
  w->step(100);
  const Eigen::Vector3d dv = w->getBodyState("crate1")->linear_velocity - v;
  EXPECT_LE((dv - Eigen::Vector3d(0, 0, -9.81 * 100 * w->config().dt)).norm(), 1e-12);
  w->reset();
  EXPECT_TRUE(testing::bitwiseEqual(testing::stateOf(*w, "crate1"), initial));
}

// Truth: spawnUrdf refuses (and leaves the world as it was) an existing or empty name, a name
// or link that clashes with the world's links, a URDF without exactly one moving body, a bad
// URDF, and a bad placement.
TEST(WorldSpawn, SpawnRefusesClashesAndBadInput) {
  auto w = makeWorld(base());
  auto spawned = w->spawnUrdf("crate1", kCrateUrdf, somePose(), kZero, kZero);
  ASSERT_TRUE(spawned.ok()) << spawned.error();
  const auto version = w->topologyVersion();
  const std::size_t bodies = w->scene().bodies.size();
  struct Case {
    std::string name, urdf, expected;
    Eigen::Isometry3d pose = somePose();
  };
  Eigen::Isometry3d reflected = somePose();
  reflected.linear().col(0) *= -1;
  const Case cases[] = {
      {"crate1", kCrateUrdf, "spawn_urdf.name: body 'crate1' already exists"},
      {"a", kCrateUrdf, "spawn_urdf.name: body 'a' already exists"},
      {"", kCrateUrdf, "spawn_urdf.name: must not be empty"},
      {"world", kCrateUrdf, "spawn_urdf.name: 'world' is the name of the world frame"},
      {"crate2", kCrateUrdf,
       "spawn_urdf 'crate2': link 'crate_lid' already exists in the world (body 'crate1')"},
      {"crate_lid", kCrateUrdf,
       "spawn_urdf 'crate_lid': link 'crate_lid' already exists in the world (body 'crate1')"},
      {"post", kFixedUrdf,
       "spawn_urdf 'post': the URDF must hold exactly one body, a moving one (it has 0 moving "
       "and 1 static)"},
      {"junk", "<robot", "spawn_urdf 'junk'"},
      {"crate3", kCrateUrdf, "spawn_urdf.pose.rotation: not a proper rotation", reflected},
  };
  for (const Case& c : cases) {
    auto r = w->spawnUrdf(c.name, c.urdf, c.pose, kZero, kZero);
    ASSERT_FALSE(r.ok()) << c.expected;
    EXPECT_NE(r.error().find(c.expected), std::string::npos) << r.error();
    EXPECT_EQ(w->topologyVersion(), version);
    EXPECT_EQ(w->scene().bodies.size(), bodies);
  }
  auto v =
      w->spawnUrdf("crate4", kCrateUrdf, somePose(), Eigen::Vector3d(0, std::nan(""), 0), kZero);
  ASSERT_FALSE(v.ok());
  EXPECT_EQ(v.error(), "spawn_urdf.linear_velocity.y: not finite (nan)");
  // The bounds of setBodyState (src/sim/state_edit.h: speeds up to 1e9 m/s and rad/s), which
  // keep a finite state finite.
  auto fast = w->spawnUrdf("crate4", kCrateUrdf, somePose(), kZero, Eigen::Vector3d(0, 0, 1e300));
  ASSERT_FALSE(fast.ok());
  EXPECT_EQ(fast.error().rfind("spawn_urdf.angular_velocity: |angular_velocity| = 1e+300 rad/s "
                               "exceeds the largest angular speed",
                               0),
            0u)
      << fast.error();
  EXPECT_EQ(w->scene().bodies.size(), bodies);
}

// Truth: deleteBody removes a body with its queued and active inputs; the other bodies keep
// theirs (indices shift underneath): the survivors end bit-identical to a world that never had
// the deleted body and got the same inputs. Names are freed, topologyVersion bumps.
TEST(WorldSpawn, DeleteRemovesTheBodyAndKeepsTheOthersInputs) {
  auto w = makeWorld(base());
  scene::Scene without_b = base();
  without_b.bodies.erase(without_b.bodies.begin() + 1);
  auto ref = makeWorld(without_b);
  const double dt = w->config().dt;
  auto send = [&](sim::World& world, const std::string& body, double stamp, double duration) {
    sim::WrenchInput in;
    in.body = in.frame = body;
    in.F = cga::Force(Eigen::Vector3d(1, -2, 3));
    in.point = Eigen::Vector3d(0.05, 0, 0);
    in.start_time = stamp;
    in.duration = duration;
    ASSERT_TRUE(world.applyWrench(in).ok());
    sim::ImpulseInput j;
    j.body = body;
    j.J = cga::Force(Eigen::Vector3d(0, 0, 0.5));
    j.start_time = stamp + 3 * dt;
    ASSERT_TRUE(world.applyImpulse(j).ok());
  };
  for (auto* world : {w.get(), ref.get()}) {
    send(*world, "a", 2 * dt, 20 * dt);
    send(*world, "c", 0, -1);
    send(*world, "c", 30 * dt, 5 * dt);
  }
  send(*w, "b", 0, -1);
  send(*w, "b", 40 * dt, 5 * dt);
  w->step(10);
  ref->step(10);
  const auto version = w->topologyVersion();
  ASSERT_TRUE(w->deleteBody("b").ok());
  EXPECT_EQ(w->topologyVersion(), version + 1);
  EXPECT_FALSE(w->getBodyState("b").ok());
  EXPECT_EQ(w->momentum().size(), 3u);  // a, c, total
  w->step(90);
  ref->step(90);
  EXPECT_TRUE(testing::sameStates(*w, *ref));
  EXPECT_EQ(w->activeWrenchCount(), ref->activeWrenchCount());

  // A static body can be deleted too; its frames go.
  ASSERT_TRUE(w->deleteBody("floor").ok());
  for (const auto& f : w->staticFrames()) EXPECT_NE(f.child, "floor");
  // The freed name can be used again.
  auto spawned = w->spawnUrdf("b", kCrateUrdf, somePose(), kZero, kZero);
  ASSERT_TRUE(spawned.ok()) << spawned.error();
  EXPECT_TRUE(w->getBodyState("b").ok());
  ASSERT_TRUE(w->deleteBody("b").ok());
  spawned = w->spawnUrdf("b", kCrateUrdf, somePose(), kZero, kZero);  // crate_lid freed too
  EXPECT_TRUE(spawned.ok()) << spawned.error();
}

}  // namespace world_spawn_test
}  // namespace cga_rigid_sim
