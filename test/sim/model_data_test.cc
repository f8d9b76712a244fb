// The Model/Data split of the World (sim/model.h, sim/data.h, sim/topology.cc): index spaces
// that stay consistent through spawn and delete, and refusals as structured errors.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"
#include "sim/world_fixtures.h"

namespace cga_rigid_sim {
namespace model_data_test {

using testing::makeScene;
using testing::makeWorld;
using testing::movingBody;
using testing::staticBody;

const char* const kBallUrdf = R"(<robot name="ball">
  <link name="ball"><inertial><mass value="2"/>
    <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
</robot>)";

// The invariants of model.h: every moving index i and body index j point at each other, the
// Data has one entry per moving body, names resolve to the right body, and the bodies whose
// loads wait for a rebuild are valid moving indices.
::testing::AssertionResult consistent(const sim::World& w) {
  const sim::Model& m = w.model();
  const sim::Data& d = w.data();
  const std::size_t nb = m.scene.bodies.size();
  if (m.moving_of_body.size() != nb)
    return ::testing::AssertionFailure() << "per-body arrays differ in size";
  if (d.bodies.size() != m.moving.size())
    return ::testing::AssertionFailure()
           << "Data has " << d.bodies.size() << " bodies, Model " << m.moving.size();
  for (std::size_t i = 0; i < m.moving.size(); ++i) {
    const int j = m.moving[i].body;
    if (j < 0 || static_cast<std::size_t>(j) >= nb || m.moving_of_body[j] != static_cast<int>(i))
      return ::testing::AssertionFailure() << "moving " << i << " ↔ body " << j << " broken";
  }
  for (std::size_t j = 0; j < nb; ++j) {
    const scene::BodyModel& b = m.scene.bodies[j];
    if ((m.moving_of_body[j] < 0) != b.is_static)
      return ::testing::AssertionFailure() << "body " << b.name << ": static flag vs index";
    if (m.findBody(b.name) != static_cast<int>(j))
      return ::testing::AssertionFailure() << "name " << b.name << " resolves elsewhere";
    for (const auto& l : b.links)
      if (m.resolveBody(l.link) != static_cast<int>(j))
        return ::testing::AssertionFailure() << "link " << l.link << " resolves elsewhere";
  }
  for (int i : d.dirty_list)
    if (i < 0 || static_cast<std::size_t>(i) >= d.bodies.size() || !d.bodies[i].loads_dirty)
      return ::testing::AssertionFailure() << "dirty-list entry " << i << " invalid";
  std::size_t active = 0;
  for (const auto& b : d.bodies) active += b.wrenches.size();
  if (active != d.active_wrenches)
    return ::testing::AssertionFailure()
           << active << " active wrenches, counted " << d.active_wrenches;
  for (const auto& e : d.expiries)
    if (e.body < 0 || static_cast<std::size_t>(e.body) >= d.bodies.size())
      return ::testing::AssertionFailure() << "wrench ending on body " << e.body;
  return ::testing::AssertionSuccess();
}

sim::WrenchInput oneStepPush(const std::string& body) {
  sim::WrenchInput in;
  in.body = body;
  in.F = cga::Force(Eigen::Vector3d(1.0, 0.0, 0.0));
  in.point = Eigen::Vector3d(0.0, 0.1, 0.0);
  in.duration = 0.0;  // one step
  return in;
}

// Truth: the index bookkeeping of model.h, checked after every edit; and a second method for
// the surviving bodies — a world that never had the deleted body, given the same inputs, ends
// bit-identical. Wrenches of one step end at the end of the step, so right after it the loads
// of every pushed body wait for a rebuild: deleting a body then must not leave its index (or a
// shifted one) in that list.
TEST(ModelData, SpawnAndDeleteKeepEveryIndexConsistent) {
  const Eigen::Vector3d J(0.1, 0.2, 0.3);
  auto bodies = [&](bool with_a) {
    std::vector<scene::BodyModel> b;
    b.push_back(staticBody("table"));
    if (with_a) b.push_back(movingBody("a", 1.0, J, Eigen::Quaterniond::Identity(), {1, 0, 0}));
    b.push_back(movingBody("b", 2.0, J, Eigen::Quaterniond::Identity(), {0, 1, 0}, {0, 0, 3}));
    b.push_back(movingBody("c", 3.0, J, Eigen::Quaterniond::Identity(), {0, 0, 1}, {1, 2, 3}));
    return b;
  };
  auto w = makeWorld(makeScene(bodies(true)));
  auto ref = makeWorld(makeScene(bodies(false)));
  ASSERT_TRUE(consistent(*w));
  for (const std::string body : {"a", "b", "c"})
    ASSERT_TRUE(w->applyWrench(oneStepPush(body)).ok());
  for (const std::string body : {"b", "c"}) ASSERT_TRUE(ref->applyWrench(oneStepPush(body)).ok());
  w->step();
  ref->step();
  EXPECT_EQ(w->data().dirty_list.size(), 3u);  // the three wrenches just ended
  ASSERT_TRUE(w->deleteBody("a").ok());
  EXPECT_TRUE(consistent(*w));
  EXPECT_EQ(w->data().dirty_list.size(), 2u);
  const Eigen::Isometry3d pose = Eigen::Isometry3d(Eigen::Translation3d(0, 0, 5));
  for (auto* world : {w.get(), ref.get()})
    ASSERT_TRUE(world->spawnUrdf("ball", kBallUrdf, pose, {0, 1, 0}, {0, 0, 1}).ok());
  EXPECT_TRUE(consistent(*w));
  ASSERT_TRUE(w->deleteBody("table").ok());
  ASSERT_TRUE(ref->deleteBody("table").ok());
  EXPECT_TRUE(consistent(*w));
  for (const std::string body : {"ball", "c"}) {
    ASSERT_TRUE(w->applyWrench(oneStepPush(body)).ok());
    ASSERT_TRUE(ref->applyWrench(oneStepPush(body)).ok());
  }
  w->step(20);
  ref->step(20);
  EXPECT_TRUE(testing::sameStates(*w, *ref));
  EXPECT_TRUE(consistent(*w));
}

// Truth: the documented form of a refusal (result.h, world.h): input, field and rule apart,
// and the message "<input>.<field>: <rule>" built from them.
TEST(ModelData, RefusalsAreStructured) {
  auto w = makeWorld(makeScene({movingBody("box", 1.0, {0.1, 0.2, 0.3}), staticBody("table")}));
  sim::ImpulseInput in;
  in.body = "box";
  in.J = cga::Force(Eigen::Vector3d(0.0, std::numeric_limits<double>::quiet_NaN(), 0.0));
  auto r = w->applyImpulse(in);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.failure().input, "apply_impulse");
  EXPECT_EQ(r.failure().field, "J.y");
  EXPECT_EQ(r.failure().rule, "not finite (nan)");
  EXPECT_EQ(r.error(), "apply_impulse.J.y: not finite (nan)");

  auto s = w->applyWrench(oneStepPush("table"));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.failure().input, "apply_wrench");
  EXPECT_EQ(s.failure().field, "body");
  EXPECT_EQ(s.error(), "apply_wrench.body: " + s.failure().rule);

  sim::WorldConfig config;
  config.dt = -1.0;
  auto c = sim::World::create(makeScene({}), config);
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.failure().input, "config");
  EXPECT_EQ(c.failure().field, "dt");
}

// Truth: model.h's compiled order — body indices are the scene's, moving indices count the
// moving bodies in that order, and every body of a scene without joints hangs on the world.
TEST(ModelData, CompiledIndicesFollowTheScene) {
  auto scene = makeScene({staticBody("floor"), movingBody("a", 1.0, {0.1, 0.1, 0.1}),
                          staticBody("wall"), movingBody("b", 1.0, {0.1, 0.2, 0.3})});
  auto m = sim::compileModel(scene, sim::WorldConfig());
  ASSERT_TRUE(m.ok()) << m.error();
  EXPECT_EQ(m->moving_of_body, (std::vector<int>{-1, 0, -1, 1}));
  ASSERT_EQ(m->moving.size(), 2u);
  EXPECT_EQ(m->moving[0].body, 1);
  EXPECT_EQ(m->moving[1].body, 3);
  EXPECT_TRUE(m->trees.empty());  // no joints: every moving body is free
  EXPECT_EQ(m->tree_of_moving, (std::vector<int>{-1, -1}));
  auto d = sim::makeData(*m);
  ASSERT_TRUE(d.ok()) << d.error();
  ASSERT_EQ(d->bodies.size(), 2u);
  EXPECT_TRUE(testing::bitwiseEqual(d->bodies[1].state, m->moving[1].initial));
}

}  // namespace model_data_test
}  // namespace cga_rigid_sim
