// Time, stamps, determinism and reset.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "sim/world_fixtures.h"

namespace cga_rigid_sim {
namespace world_time_test {

using testing::makeScene;
using testing::makeWorld;
using testing::movingBody;
using testing::sameStates;

scene::Scene twoBodies() {
  return makeScene({movingBody("a", 2.0, {0.1, 0.2, 0.25},
                               Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())),
                               {0, 0, 1}, {0.5, -0.2, 1.3}, {0.1, 0, 0}),
                    movingBody("b", 1.0, {0.3, 0.3, 0.5}, Eigen::Quaterniond::Identity(), {2, 0, 1},
                               {0, 0.4, 2.0})},
                   Eigen::Vector3d(0, 0, -9.81));
}

// Truth: t = stepCount·dt, computed from the integer count (not by adding dt), so after three
// steps of 0.1 s it is 3·0.1 exactly (0.30000000000000004), and stepCount never goes back.
TEST(WorldTime, TimeIsStepCountTimesDt) {
  auto w = makeWorld(twoBodies(), 0.1);
  EXPECT_EQ(w->time(), 0.0);
  w->step(3);
  EXPECT_EQ(w->stepCount(), 3u);
  EXPECT_EQ(w->time(), 3 * 0.1);
  w->reset();
  EXPECT_EQ(w->stepCount(), 3u);
  w->step(4);
  EXPECT_EQ(w->time(), 7 * 0.1);
}

// A fixed set of inputs with distinct steps, stamped in sim time.
struct Stamped {
  bool impulse;
  sim::WrenchInput wrench;
  sim::ImpulseInput imp;
};
std::vector<Stamped> someInputs(double dt) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Stamped> v;
  for (int k = 0; k < 12; ++k) {
    Stamped s;
    s.impulse = k % 3 == 1;
    const std::string body = k % 2 ? "a" : "b";
    const std::string frame = k % 4 < 2 ? "world" : body;
    const double stamp = (3 + 7 * k) * dt;  // distinct steps
    s.wrench.body = s.imp.body = body;
    s.wrench.frame = s.imp.frame = frame;
    s.wrench.F = cga::Force(Eigen::Vector3d(u(rng), u(rng), u(rng)) * 5.0);
    s.wrench.point = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.1;
    s.wrench.couple = Eigen::Vector3d(u(rng), u(rng), u(rng));
    s.wrench.duration = (k % 5) * 4 * dt;
    s.wrench.start_time = stamp;
    s.imp.J = cga::Force(Eigen::Vector3d(u(rng), u(rng), u(rng)));
    s.imp.point = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.1;
    s.imp.angular = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.01;
    s.imp.start_time = stamp;
    v.push_back(s);
  }
  return v;
}
void send(sim::World& w, const Stamped& s) {
  auto r = s.impulse ? w.applyImpulse(s.imp) : w.applyWrench(s.wrench);
  ASSERT_TRUE(r.ok()) << r.error();
}
double stampOf(const Stamped& s) { return s.impulse ? s.imp.start_time : s.wrench.start_time; }

// Truth: determinism. Inputs take effect at the step of their stamp whatever the order and time
// they were queued in: world A gets them all up front in stamp order, world B in reverse order,
// world C each just before its step (stepping in between). All three end bit-identical.
TEST(WorldTime, StampedInputsApplyAtTheirStepWhateverTheQueueOrder) {
  auto a = makeWorld(twoBodies()), b = makeWorld(twoBodies()), c = makeWorld(twoBodies());
  const double dt = a->config().dt;
  const auto inputs = someInputs(dt);
  for (const auto& s : inputs) send(*a, s);
  for (auto it = inputs.rbegin(); it != inputs.rend(); ++it) send(*b, *it);
  const std::uint64_t total = 120;
  for (const auto& s : inputs) {
    const auto k = static_cast<std::uint64_t>(std::llround(stampOf(s) / dt));
    c->step(k - c->stepCount());
    send(*c, s);
  }
  a->step(total);
  b->step(total);
  c->step(total - c->stepCount());
  EXPECT_TRUE(sameStates(*a, *b));
  EXPECT_TRUE(sameStates(*a, *c));
  // And they did something: the state differs from a world without inputs.
  auto none = makeWorld(twoBodies());
  none->step(total);
  EXPECT_FALSE(sameStates(*a, *none));
}

// Truth: determinism of replay. The same inputs in the same arrival order, several in one step
// (concurrent wrenches are summed in arrival order), give bit-identical states.
TEST(WorldTime, ReplayIsBitIdentical) {
  auto run = [] {
    auto w = makeWorld(twoBodies());
    const double dt = w->config().dt;
    for (auto s : someInputs(dt)) {
      s.wrench.start_time = s.imp.start_time = 5 * dt;  // all in one step
      send(*w, s);
    }
    w->step(200);
    return w;
  };
  EXPECT_TRUE(sameStates(*run(), *run()));
}

// Truth: the stamp rule of world.h. After 10 steps (t = 10 dt): stamps of done steps (5 dt,
// 9.5 dt) are refused with "start stamp s is already past (sim time t)"; 10 dt (the next step),
// 10 dt minus round-off (1e-12 relative) and 0 (= the next step) are accepted; a refusal
// leaves nothing queued.
TEST(WorldTime, PastStampsAreRefused) {
  auto w = makeWorld(twoBodies(), 0.1);
  w->step(10);
  sim::ImpulseInput in;
  in.body = "a";
  in.J = cga::Force(Eigen::Vector3d(1, 0, 0));
  for (const double s : {0.5, 0.95, -0.1}) {
    in.start_time = s;
    auto r = w->applyImpulse(in);
    ASSERT_FALSE(r.ok()) << s;
    EXPECT_NE(r.error().find("apply_impulse.start_time: start stamp"), std::string::npos)
        << r.error();
    EXPECT_NE(r.error().find("is already past (sim time 1)"), std::string::npos) << r.error();
  }
  sim::WrenchInput wr;
  wr.body = "a";
  wr.start_time = 0.5;
  auto r = w->applyWrench(wr);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(), "apply_wrench.start_time: start stamp 0.5 is already past (sim time 1)");
  EXPECT_EQ(w->queuedInputCount(), 0u);
  for (const double s : {1.0, 1.0 * (1 - 1e-12), 0.0, 1.05}) {
    in.start_time = s;
    EXPECT_TRUE(w->applyImpulse(in).ok()) << s;
  }
  EXPECT_EQ(w->queuedInputCount(), 4u);
}

// Truth: reset() puts every body back to its initial state bit for bit, drops active wrenches
// and queued inputs, and lets time run on; afterwards the world evolves exactly like a fresh
// one (the integrators keep no state across reset).
TEST(WorldTime, ResetRestoresTheInitialStateBitwiseAndTimeRunsOn) {
  auto w = makeWorld(twoBodies());
  auto fresh = makeWorld(twoBodies());
  const auto initial = w->bodyStates();
  const double dt = w->config().dt;
  for (const auto& s : someInputs(dt)) send(*w, s);
  sim::WrenchInput forever;
  forever.body = "a";
  forever.F = cga::Force(Eigen::Vector3d(1, 1, 1));
  forever.duration = -1;
  ASSERT_TRUE(w->applyWrench(forever).ok());
  w->step(50);
  ASSERT_GT(w->queuedInputCount(), 0u);
  ASSERT_GT(w->activeWrenchCount(), 0u);
  w->reset();
  EXPECT_EQ(w->stepCount(), 50u);
  EXPECT_EQ(w->queuedInputCount(), 0u);
  EXPECT_EQ(w->activeWrenchCount(), 0u);
  const auto after = w->bodyStates();
  ASSERT_EQ(after.size(), initial.size());
  for (std::size_t i = 0; i < after.size(); ++i)
    EXPECT_TRUE(testing::bitwiseEqual(after[i].state, initial[i].state)) << after[i].name;
  w->step(300);  // past every stamp of the dropped inputs
  fresh->step(300);
  const auto sw = w->bodyStates(), sf = fresh->bodyStates();
  for (std::size_t i = 0; i < sw.size(); ++i)
    EXPECT_TRUE(testing::bitwiseEqual(sw[i].state, sf[i].state)) << sw[i].name;
}

}  // namespace world_time_test
}  // namespace cga_rigid_sim
