// Bad input is refused with a message naming the input, the field and the rule, and nothing
// is applied: the world stays bit-identical to one that never saw the input.
#include <gtest/gtest.h>

#include <functional>
#include <limits>

#include "sim/world_fixtures.h"

namespace cga_rigid_sim {
namespace world_validation_test {

using testing::makeScene;
using testing::makeWorld;
using testing::movingBody;
using testing::sameStates;
using testing::staticBody;

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

scene::Scene boxAndTable() {
  scene::BodyModel box = movingBody("box", 1.0, {0.1, 0.2, 0.25}, Eigen::Quaterniond::Identity(),
                                    {0, 0, 1}, {0.1, 0.2, 0.3}, {1, 0, 0});
  box.links.push_back({"lid", cga::Motor::translator({0, 0, 0.1}, 1.0)});
  scene::BodyModel other = movingBody("ball", 1.0, {1, 1, 1});
  return makeScene({box, other, staticBody("table")}, Eigen::Vector3d(0, 0, -9.81));
}

sim::WrenchInput goodWrench() {
  sim::WrenchInput in;
  in.body = "box";
  in.frame = "lid";
  in.F = cga::Force(Eigen::Vector3d(1, 2, 3), 0.5);
  in.point = Eigen::Vector3d(0.1, 0, 0);
  in.couple = Eigen::Vector3d(0, 0, 0.1);
  in.duration = 0.01;
  return in;
}
sim::ImpulseInput goodImpulse() {
  sim::ImpulseInput in;
  in.body = "box";
  in.frame = "world";
  in.J = cga::Force(Eigen::Vector3d(0.1, 0, 0));
  in.point = Eigen::Vector3d(0, 0, 1.05);
  in.angular = Eigen::Vector3d(0, 0.01, 0);
  return in;
}

struct BadCase {
  std::string expected;  // the whole message, or a part of it when `exact` is false
  std::function<Result<bool>(sim::World&)> apply;
  bool exact = true;
};

std::vector<BadCase> badCases() {
  std::vector<BadCase> c;
  auto wrench = [&](std::string msg, std::function<void(sim::WrenchInput&)> edit,
                    bool exact = true) {
    c.push_back({std::move(msg),
                 [edit](sim::World& w) {
                   sim::WrenchInput in = goodWrench();
                   edit(in);
                   return w.applyWrench(in);
                 },
                 exact});
  };
  auto impulse = [&](std::string msg, std::function<void(sim::ImpulseInput&)> edit,
                     bool exact = true) {
    c.push_back({std::move(msg),
                 [edit](sim::World& w) {
                   sim::ImpulseInput in = goodImpulse();
                   edit(in);
                   return w.applyImpulse(in);
                 },
                 exact});
  };
  // Non-finite numbers, each field named.
  wrench("apply_wrench.f.y: not finite (nan)", [](auto& in) { in.F.f.y() = kNaN; });
  wrench("apply_wrench.f.x: not finite (inf)", [](auto& in) { in.F.f.x() = kInf; });
  wrench("apply_wrench.alpha: not finite (-inf)", [](auto& in) { in.F.alpha = -kInf; });
  wrench("apply_wrench.point.z: not finite (nan)", [](auto& in) { in.point.z() = kNaN; });
  wrench("apply_wrench.couple.x: not finite (inf)", [](auto& in) { in.couple.x() = kInf; });
  wrench("apply_wrench.start_time: not finite (nan)", [](auto& in) { in.start_time = kNaN; });
  wrench("apply_wrench.duration: not finite (inf)", [](auto& in) { in.duration = kInf; });
  // Limits.
  wrench("apply_wrench.f: |f| = 2000000 N exceeds max_force = 1000000 N",
         [](auto& in) { in.F.f = Eigen::Vector3d(0, 2e6, 0); });
  wrench("apply_wrench.couple: |couple| = 5000000 N m exceeds max_force = 1000000 N m",
         [](auto& in) { in.couple = Eigen::Vector3d(3e6, 4e6, 0); });
  wrench("apply_wrench.point: |point| = 10000000000 m exceeds the limit = 1000000000 m",
         [](auto& in) { in.point = Eigen::Vector3d(1e10, 0, 0); });
  wrench(
      "apply_wrench.duration: 1e+20 s is more than 1e+15 steps",
      [](auto& in) { in.duration = 1e20; }, false);
  wrench(
      "apply_wrench.start_time: start stamp 1e+20 is too far ahead",
      [](auto& in) { in.start_time = 1e20; }, false);
  // Body and frame.
  wrench("apply_wrench.body: unknown body 'nope'", [](auto& in) { in.body = "nope"; });
  wrench(
      "apply_wrench.body: body 'table' is static", [](auto& in) { in.body = "table"; }, false);
  wrench(
      "apply_wrench.frame: frame 'ball' is not the world frame 'world' nor a link of body "
      "'box'",
      [](auto& in) { in.frame = "ball"; });
  wrench(
      "apply_wrench.frame: frame 'map' is not the world frame 'world' nor a link of body "
      "'box'",
      [](auto& in) { in.frame = "map"; });
  wrench("apply_wrench.start_time: start stamp 0.001 is already past (sim time 0.005)",
         [](auto& in) { in.start_time = 0.001; });
  // Impulses.
  impulse("apply_impulse.J.z: not finite (nan)", [](auto& in) { in.J.f.z() = kNaN; });
  impulse("apply_impulse.alpha: not finite (nan)", [](auto& in) { in.J.alpha = kNaN; });
  impulse("apply_impulse.point.x: not finite (inf)", [](auto& in) { in.point.x() = kInf; });
  impulse("apply_impulse.angular.y: not finite (nan)", [](auto& in) { in.angular.y() = kNaN; });
  impulse("apply_impulse.start_time: not finite (inf)", [](auto& in) { in.start_time = kInf; });
  impulse("apply_impulse.J: |J| = 20000 N s exceeds max_impulse = 10000 N s",
          [](auto& in) { in.J.f = Eigen::Vector3d(0, 0, -2e4); });
  impulse("apply_impulse.angular: |angular| = 50000 N m s exceeds max_impulse = 10000 N m s",
          [](auto& in) { in.angular = Eigen::Vector3d(3e4, 0, 4e4); });
  impulse("apply_impulse.body: unknown body ''", [](auto& in) { in.body = ""; });
  impulse(
      "apply_impulse.body: body 'table' is static", [](auto& in) { in.body = "table"; }, false);
  impulse(
      "apply_impulse.frame: frame 'table' is not the world frame 'world' nor a link of body "
      "'box'",
      [](auto& in) { in.frame = "table"; });
  impulse("apply_impulse.start_time: start stamp 0.004 is already past (sim time 0.005)",
          [](auto& in) { in.start_time = 0.004; });
  // State overrides.
  auto set = [&](std::string msg, std::function<Result<bool>(sim::World&)> f, bool exact = true) {
    c.push_back({std::move(msg), std::move(f), exact});
  };
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d z = Eigen::Vector3d::Zero();
  set("set_body_state.body: unknown body 'nope'",
      [=](sim::World& w) { return w.setBodyState("nope", I, z, z); });
  set(
      "set_body_state.body: body 'table' is static",
      [=](sim::World& w) { return w.setBodyState("table", I, z, z); }, false);
  set("set_body_state.pose.translation.y: not finite (nan)", [=](sim::World& w) {
    Eigen::Isometry3d p = I;
    p.translation().y() = kNaN;
    return w.setBodyState("box", p, z, z);
  });
  set(
      "set_body_state.pose.rotation: not a proper rotation",
      [=](sim::World& w) {
        Eigen::Isometry3d p = I;
        p.linear()(0, 0) = -1;  // a reflection
        return w.setBodyState("box", p, z, z);
      },
      false);
  set(
      "set_body_state.pose.rotation: not a proper rotation",
      [=](sim::World& w) {
        Eigen::Isometry3d p = I;
        p.linear() *= 1.001;  // not orthonormal
        return w.setBodyState("box", p, z, z);
      },
      false);
  set("set_body_state.pose.rotation: not finite", [=](sim::World& w) {
    Eigen::Isometry3d p = I;
    p.linear()(1, 2) = kNaN;
    return w.setBodyState("box", p, z, z);
  });
  set("set_body_state.linear_velocity.z: not finite (inf)",
      [=](sim::World& w) { return w.setBodyState("box", I, Eigen::Vector3d(0, 0, kInf), z); });
  set("set_body_state.angular_velocity.x: not finite (nan)",
      [=](sim::World& w) { return w.setBodyState("box", I, z, Eigen::Vector3d(kNaN, 0, 0)); });
  // Finite but overflowing: found by fuzz/fuzz_world_inputs.cc (an angular velocity of
  // (1.56e147, DBL_MAX, 119) was accepted and made the state NaN on the spot). The bounds are
  // kMaxPointDistance and the largest speeds of src/sim/state_edit.h, 1e9 each.
  set("set_body_state.angular_velocity: |angular_velocity| = 1.79769313486232e+308 rad/s "
      "exceeds the largest angular speed = 1000000000 rad/s",
      [=](sim::World& w) {
        const double huge = std::numeric_limits<double>::max();
        return w.setBodyState("box", I, z, Eigen::Vector3d(1.56e147, huge, 119));
      });
  set("set_body_state.linear_velocity: |linear_velocity| = 2000000000 m/s exceeds the largest "
      "speed = 1000000000 m/s",
      [=](sim::World& w) { return w.setBodyState("box", I, Eigen::Vector3d(0, 2e9, 0), z); });
  set("set_body_state.pose.translation: |pose.translation| = 1000000000000 m exceeds the largest "
      "distance = 1000000000 m",
      [=](sim::World& w) {
        Eigen::Isometry3d p = I;
        p.translation() = Eigen::Vector3d(0, 0, 1e12);
        return w.setBodyState("box", p, z, z);
      });
  set("delete_body.body: unknown body 'nope'", [](sim::World& w) { return w.deleteBody("nope"); });
  set("delete_body.body: unknown body 'lid'", [](sim::World& w) { return w.deleteBody("lid"); });
  return c;
}

// Truth: world.h's validation rules and message format. Each bad input is refused with the
// expected message, and afterwards (having seen every bad input) the world is bit-identical to
// a twin that saw none — after 5 steps before and 100 steps after, so queued or half-applied
// inputs would show.
TEST(WorldValidation, BadInputIsRefusedWithItsMessageAndChangesNothing) {
  auto w = makeWorld(boxAndTable()), twin = makeWorld(boxAndTable());
  ASSERT_TRUE(w->applyWrench(goodWrench()).ok());
  ASSERT_TRUE(twin->applyWrench(goodWrench()).ok());
  w->step(5);
  twin->step(5);
  const auto topology = w->topologyVersion();
  for (const BadCase& c : badCases()) {
    auto r = c.apply(*w);
    ASSERT_FALSE(r.ok()) << "accepted; expected: " << c.expected;
    if (c.exact) {
      EXPECT_EQ(r.error(), c.expected);
    } else {
      EXPECT_EQ(r.error().rfind(c.expected, 0), 0u) << r.error() << "\nexpected: " << c.expected;
    }
    EXPECT_TRUE(sameStates(*w, *twin)) << c.expected;
  }
  EXPECT_EQ(w->queuedInputCount(), twin->queuedInputCount());
  EXPECT_EQ(w->activeWrenchCount(), twin->activeWrenchCount());
  EXPECT_EQ(w->topologyVersion(), topology);
  w->step(100);
  twin->step(100);
  EXPECT_TRUE(sameStates(*w, *twin));
}

// Truth: the bounds on inputs (world_config.h). A world filled to every bound — waiting inputs
// per body and in all, active wrenches per body and in all — refuses each valid input past a
// bound, when it arrives (waiting) or when it is due to start (active), with the message naming
// the bound; afterwards it is bit-identical to a twin that got only the inputs within the
// bounds, after 5 steps and after 100 more, with the same waiting and active counts.
TEST(WorldValidation, InputsPastABoundAreRefusedAndChangeNothing) {
  sim::WorldConfig config;
  config.max_queued_inputs = 12;
  config.max_queued_inputs_per_body = 8;
  config.max_active_wrenches = 3;
  config.max_active_wrenches_per_body = 2;
  auto make = [&] {
    auto w = sim::World::create(boxAndTable(), config);
    EXPECT_TRUE(w.ok()) << w.error();
    return std::move(w.value());
  };
  auto w = make(), twin = make();
  auto both = [&](auto apply) {
    ASSERT_TRUE(apply(*w).ok());
    ASSERT_TRUE(apply(*twin).ok());
  };
  sim::WrenchInput forever = goodWrench();
  forever.duration = -1;
  // Active: the box's two and the ball's one fill both bounds; each world-only extra is refused
  // when due (step 0), one past the box's bound and one past the total.
  both([&](sim::World& x) { return x.applyWrench(forever); });
  both([&](sim::World& x) { return x.applyWrench(forever); });
  ASSERT_TRUE(w->applyWrench(forever).ok());  // box: 3rd, past max_active_wrenches_per_body
  sim::WrenchInput ball = forever;
  ball.body = "ball";
  ball.frame = "";
  both([&](sim::World& x) { return x.applyWrench(ball); });
  ASSERT_TRUE(w->applyWrench(ball).ok());  // ball: 4th in all, past max_active_wrenches
  w->step(5);
  twin->step(5);
  EXPECT_EQ(w->startRefusalCount(), 2u);
  EXPECT_EQ(w->lastStartRefusal()->message(),
            "apply_wrench.body: 3 wrenches and timed joint efforts already act at step 0 "
            "(max_active_wrenches = 3)");
  EXPECT_TRUE(sameStates(*w, *twin));
  // Waiting: 8 far-future impulses fill the box's bound, 4 the total; then one more of each is
  // refused on arrival with its message.
  sim::ImpulseInput later = goodImpulse();
  later.start_time = 1.0;
  for (int i = 0; i < 8; ++i) both([&](sim::World& x) { return x.applyImpulse(later); });
  auto r = w->applyImpulse(later);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(),
            "apply_impulse.body: body 'box' already has 8 inputs waiting for their step "
            "(max_queued_inputs_per_body = 8)");
  sim::ImpulseInput ball_later = later;
  ball_later.body = "ball";
  for (int i = 0; i < 4; ++i) both([&](sim::World& x) { return x.applyImpulse(ball_later); });
  r = w->applyImpulse(ball_later);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(),
            "apply_impulse.start_time: 12 inputs are already waiting for their step "
            "(max_queued_inputs = 12)");
  EXPECT_TRUE(sameStates(*w, *twin));
  EXPECT_EQ(w->queuedInputCount(), 12u);
  EXPECT_EQ(w->queuedInputCount(), twin->queuedInputCount());
  EXPECT_EQ(w->activeWrenchCount(), twin->activeWrenchCount());
  w->step(1000);  // the impulses at 1 s act
  twin->step(1000);
  EXPECT_TRUE(sameStates(*w, *twin));
  EXPECT_EQ(w->queuedInputCount(), 0u);
}

// Truth: the good inputs the bad ones were made from are accepted (so each refusal above is due
// to the one field that was changed), including an empty frame (= the world frame) and a body
// named by one of its links.
TEST(WorldValidation, TheUnalteredInputsAreAccepted) {
  auto w = makeWorld(boxAndTable());
  w->step(5);
  EXPECT_TRUE(w->applyWrench(goodWrench()).ok());
  EXPECT_TRUE(w->applyImpulse(goodImpulse()).ok());
  sim::ImpulseInput in = goodImpulse();
  in.frame = "";
  in.body = "lid";
  EXPECT_TRUE(w->applyImpulse(in).ok());
  EXPECT_EQ(w->queuedInputCount(), 3u);
}

// Truth: World::create's rules: dt, limits, world frame, integrator name, scene consistency.
TEST(WorldValidation, CreateRefusesABadConfigurationOrScene) {
  struct Case {
    std::string expected;
    std::function<void(sim::WorldConfig&, scene::Scene&)> edit;
  };
  const Case cases[] = {
      {"config.dt: must be finite and > 0 (got 0)", [](auto& c, auto&) { c.dt = 0; }},
      {"config.dt: must be finite and > 0 (got nan)", [](auto& c, auto&) { c.dt = kNaN; }},
      {"config.max_force: must be finite and > 0 (got -1)",
       [](auto& c, auto&) { c.max_force = -1; }},
      {"config.max_impulse: must be finite and > 0 (got inf)",
       [](auto& c, auto&) { c.max_impulse = kInf; }},
      {"config.world_frame: must not be empty", [](auto& c, auto&) { c.world_frame = ""; }},
      {"config.integrator: ", [](auto& c, auto&) { c.integrator = "verlet"; }},
      {"scene.lambda: must be finite and > 0 (got 0)", [](auto&, auto& s) { s.lambda = 0; }},
      {"scene.body 'ball': link 'lid' used twice",
       [](auto&, auto& s) {
         s.bodies[1].links.push_back({"lid", cga::Motor()});
       }},
      {"scene.body 'table': link 'world' has the name of the world frame",
       [](auto&, auto& s) { s.bodies[2].links[0].link = "world"; }},
      {"scene.body 'ball': moving body without inertia",
       [](auto&, auto& s) { s.bodies[1].inertia.reset(); }},
  };
  for (const Case& c : cases) {
    sim::WorldConfig config;
    scene::Scene s = boxAndTable();
    c.edit(config, s);
    auto w = sim::World::create(s, config);
    ASSERT_FALSE(w.ok()) << c.expected;
    EXPECT_EQ(w.error().rfind(c.expected, 0), 0u) << w.error();
  }
  auto unknown = sim::World::create(boxAndTable(), [] {
    sim::WorldConfig c;
    c.integrator = "verlet";
    return c;
  }());
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.error().find("verlet"), std::string::npos) << unknown.error();
}

}  // namespace world_validation_test
}  // namespace cga_rigid_sim
