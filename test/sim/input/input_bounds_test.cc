// The bounds on inputs (WorldConfig::max_queued_inputs[_per_body], max_active_wrenches[_per_body])
// and the heap the queue keeps: order kept for any arrival order, refusal exactly at the bound
// with a message naming it, counts, and the queue never holding more than the bound. No timing:
// the O(log n) of the heap shows as correctness here, its cost in doc/README.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/input/input_queue.h"
#include "sim/world_fixtures.h"

namespace cga_rigid_sim {
namespace input_bounds_test {

using testing::makeScene;
using testing::movingBody;
using testing::sameStates;

sim::QueuedInput queued(std::uint64_t step, int body, sim::QueuedInput::Kind kind, double tag) {
  sim::QueuedInput q;
  q.kind = kind;
  q.step = step;
  q.body = kind == sim::QueuedInput::Kind::kWrench || kind == sim::QueuedInput::Kind::kImpulse
               ? body
               : -1;
  q.tree = q.body < 0 ? body : -1;
  q.F.f.x() = tag;
  return q;
}

// Truth: a stable sort by step of the inputs in arrival order is (step, arrival) order; the
// heap, fed 21 000 inputs of random steps (many sharing a step) and popped step by step with
// more pushed in between, hands them out in exactly that order, and its per-body, per-tree and
// wrench counters always equal a count over what is still waiting.
TEST(InputQueueHeap, KeepsStepThenArrivalOrderAndItsCounts) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<std::uint64_t> step(0, 500);
  std::uniform_int_distribution<int> body(0, 4), kind(0, 3);
  sim::InputQueue q;
  std::vector<sim::QueuedInput> waiting;  // the truth, in arrival order
  std::vector<double> expected, got;
  double tag = 0;
  auto push = [&](std::uint64_t earliest) {
    auto in = queued(std::max(earliest, step(rng)), body(rng),
                     static_cast<sim::QueuedInput::Kind>(kind(rng)), ++tag);
    q.push(in);
    waiting.push_back(in);
  };
  auto checkCounts = [&] {
    for (int b = 0; b < 5; ++b) {
      std::size_t bodies = 0, wrenches = 0, trees = 0, timed = 0;
      for (const auto& w : waiting) {
        bodies += w.body == b;
        wrenches += w.body == b && w.kind == sim::QueuedInput::Kind::kWrench;
        trees += w.tree == b;
        timed += w.tree == b && w.kind == sim::QueuedInput::Kind::kTimedEffort;
      }
      ASSERT_EQ(q.bodyCount(b), bodies);
      ASSERT_EQ(q.wrenchCount(b), wrenches);
      ASSERT_EQ(q.treeCount(b), trees);
      ASSERT_EQ(q.timedEffortCount(b), timed);
    }
    ASSERT_EQ(q.size(), waiting.size());
  };
  for (int i = 0; i < 10000; ++i) push(0);
  checkCounts();
  for (std::uint64_t k = 0; k <= 500; ++k) {
    if (k % 50 == 0)
      for (int i = 0; i < 1000; ++i) push(k);  // later arrivals, some due this very step
    // The truth for step k: what waits with step ≤ k, in arrival order (stable by step).
    std::vector<sim::QueuedInput> due;
    std::copy_if(waiting.begin(), waiting.end(), std::back_inserter(due),
                 [k](const auto& w) { return w.step <= k; });
    std::stable_sort(due.begin(), due.end(),
                     [](const auto& a, const auto& b) { return a.step < b.step; });
    for (const auto& d : due) expected.push_back(d.F.f.x());
    waiting.erase(
        std::remove_if(waiting.begin(), waiting.end(), [k](const auto& w) { return w.step <= k; }),
        waiting.end());
    while (const sim::QueuedInput* in = q.popDue(k)) {
      ASSERT_LE(in->step, k);
      got.push_back(in->F.f.x());
    }
    if (k % 100 == 0) checkCounts();
  }
  EXPECT_EQ(got.size(), 21000u);  // 10 000 at first, 1000 at each of the 11 steps k % 50 == 0
  EXPECT_EQ(got, expected);
  EXPECT_TRUE(q.empty());
  checkCounts();
}

// Truth: removal keeps the (step, arrival) order of what stays and the counters.
TEST(InputQueueHeap, RemovalKeepsOrderAndCounts) {
  sim::InputQueue q;
  using K = sim::QueuedInput::Kind;
  for (int i = 0; i < 30; ++i)
    q.push(
        queued(static_cast<std::uint64_t>(30 - i) / 3, i % 3, i % 2 ? K::kWrench : K::kImpulse, i));
  q.removeBody(1);  // drops i % 3 == 1; body 2 becomes body 1
  EXPECT_EQ(q.size(), 20u);
  EXPECT_EQ(q.bodyCount(1), 10u);
  EXPECT_EQ(q.bodyCount(2), 0u);
  q.clearWrenches();  // drops odd i
  EXPECT_EQ(q.size(), 10u);
  EXPECT_EQ(q.wrenchCount(), 0u);
  std::vector<double> got;
  while (const auto* in = q.popDue(100)) got.push_back(in->F.f.x());
  // Even i with i % 3 != 1, by step (30 − i)/3 ascending (one kept input per step here).
  EXPECT_EQ(got, (std::vector<double>{26, 24, 20, 18, 14, 12, 8, 6, 2, 0}));
}

scene::Scene twoBodies() {
  return makeScene({movingBody("box", 1.0, {0.1, 0.2, 0.25}, Eigen::Quaterniond::Identity(),
                               {0, 0, 0}, {0.3, 1.0, 0.2}),
                    movingBody("ball", 2.0, {0.4, 0.4, 0.4})});
}

std::unique_ptr<sim::World> boundedWorld(int queued, int queued_per_body, int active,
                                         int active_per_body) {
  sim::WorldConfig c;
  c.max_queued_inputs = queued;
  c.max_queued_inputs_per_body = queued_per_body;
  c.max_active_wrenches = active;
  c.max_active_wrenches_per_body = active_per_body;
  auto w = sim::World::create(twoBodies(), c);
  EXPECT_TRUE(w.ok()) << w.error();
  return std::move(w.value());
}

sim::ImpulseInput farImpulse(const std::string& body, double t = 1e6) {
  sim::ImpulseInput in;
  in.body = body;
  in.J = cga::Force(Eigen::Vector3d(0.1, 0, 0));
  in.start_time = t;
  return in;
}

sim::WrenchInput untilCleared(const std::string& body, double fx, double start = 0) {
  sim::WrenchInput in;
  in.body = body;
  in.F = cga::Force(Eigen::Vector3d(fx, 0.5, 0));
  in.point = Eigen::Vector3d(0, 0.1, 0);
  in.start_time = start;
  in.duration = -1;
  return in;
}

// Truth: the bound itself. 150 valid far-future impulses on two bodies against
// max_queued_inputs = 100: exactly the first 100 are queued, the other 50 refused with the
// message naming the bound, and the queue never holds more than 100.
TEST(InputBounds, QueuedInputsStopAtTheTotalBound) {
  auto w = boundedWorld(100, 1000, 1000, 64);
  int refused = 0;
  for (int i = 0; i < 150; ++i) {
    auto r = w->applyImpulse(farImpulse(i % 2 ? "box" : "ball"));
    if (!r.ok()) {
      ++refused;
      EXPECT_EQ(r.error(),
                "apply_impulse.start_time: 100 inputs are already waiting for their step "
                "(max_queued_inputs = 100)");
    }
    EXPECT_EQ(r.ok(), i < 100) << i;
    EXPECT_LE(w->queuedInputCount(), 100u);
  }
  EXPECT_EQ(refused, 50);
  EXPECT_EQ(w->queuedInputCount(), 100u);
  // Room again once inputs are taken: 10 due at step 0 leave room for exactly 10.
  w->reset();
  EXPECT_EQ(w->queuedInputCount(), 0u);
  EXPECT_TRUE(w->applyImpulse(farImpulse("box")).ok());
}

// Truth: the per-body bound counts one body only: the box's 11th waiting input is refused
// naming it, the ball still takes its 10, and an input taken from the queue makes room again.
TEST(InputBounds, QueuedInputsStopAtThePerBodyBound) {
  auto w = boundedWorld(1000, 10, 1000, 64);
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(w->applyImpulse(farImpulse("box", 0.005)).ok());
  auto r = w->applyWrench(untilCleared("box", 1.0, 0.005));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(),
            "apply_wrench.body: body 'box' already has 10 inputs waiting for their step "
            "(max_queued_inputs_per_body = 10)");
  for (int i = 0; i < 10; ++i) EXPECT_TRUE(w->applyImpulse(farImpulse("ball")).ok());
  EXPECT_FALSE(w->applyImpulse(farImpulse("ball")).ok());
  w->step(6);  // the box's 10 impulses (step 5) are taken
  EXPECT_EQ(w->queuedInputCount(), 10u);
  EXPECT_TRUE(w->applyWrench(untilCleared("box", 1.0)).ok());
}

// Truth: a world given N + extra until-cleared wrenches on the box ends bit-identical to a twin
// given only the first N (per-body bound N = 4): the extra ones are refused when due to start,
// counted, and described naming the bound; the active count stays at the bound.
TEST(InputBounds, ActiveWrenchesStopAtThePerBodyBound) {
  auto w = boundedWorld(1000, 1000, 1000, 4), twin = boundedWorld(1000, 1000, 1000, 4);
  for (int i = 0; i < 10; ++i) {
    ASSERT_TRUE(w->applyWrench(untilCleared("box", 0.1 * i)).ok());
    if (i < 4) {
      ASSERT_TRUE(twin->applyWrench(untilCleared("box", 0.1 * i)).ok());
    }
  }
  // The ball's wrenches are not the box's: one more still starts at step 1.
  ASSERT_TRUE(w->applyWrench(untilCleared("ball", 1.0, 0.001)).ok());
  ASSERT_TRUE(twin->applyWrench(untilCleared("ball", 1.0, 0.001)).ok());
  w->step(200);
  twin->step(200);
  EXPECT_TRUE(sameStates(*w, *twin));
  EXPECT_EQ(w->activeWrenchCount(), 5u);
  EXPECT_EQ(w->startRefusalCount(), 6u);
  EXPECT_EQ(twin->startRefusalCount(), 0u);
  ASSERT_TRUE(w->lastStartRefusal().has_value());
  EXPECT_EQ(w->lastStartRefusal()->message(),
            "apply_wrench.body: body 'box' already has 4 active wrenches at step 0 "
            "(max_active_wrenches_per_body = 4)");
  // Cleared, the box takes wrenches again.
  w->clearWrenches();
  ASSERT_TRUE(w->applyWrench(untilCleared("box", 1.0)).ok());
  w->step();
  EXPECT_EQ(w->activeWrenchCount(), 1u);
  EXPECT_EQ(w->startRefusalCount(), 6u);
}

// Truth: the total bound counts every body; wrenches that ended make room (one-step wrenches
// never reach it); the refusal names the total bound.
TEST(InputBounds, ActiveWrenchesStopAtTheTotalBound) {
  auto w = boundedWorld(1000, 1000, 3, 64), twin = boundedWorld(1000, 1000, 3, 64);
  for (int i = 0; i < 6; ++i) {
    ASSERT_TRUE(w->applyWrench(untilCleared(i % 2 ? "box" : "ball", 0.1 * i)).ok());
    if (i < 3) {
      ASSERT_TRUE(twin->applyWrench(untilCleared(i % 2 ? "box" : "ball", 0.1 * i)).ok());
    }
  }
  w->step(10);
  twin->step(10);
  EXPECT_TRUE(sameStates(*w, *twin));
  EXPECT_EQ(w->activeWrenchCount(), 3u);
  EXPECT_EQ(w->startRefusalCount(), 3u);
  EXPECT_EQ(w->lastStartRefusal()->message(),
            "apply_wrench.body: 3 wrenches and timed joint efforts already act at step 0 "
            "(max_active_wrenches = 3)");
  // One-step wrenches of a world below the bound: 100 in sequence all act.
  auto v = boundedWorld(1000, 1000, 3, 64);
  for (int i = 0; i < 100; ++i) {
    sim::WrenchInput in = untilCleared("box", 1.0, 0.001 * i);
    in.duration = 0;
    ASSERT_TRUE(v->applyWrench(in).ok());
  }
  v->step(100);
  EXPECT_EQ(v->startRefusalCount(), 0u);
}

// Truth: joint efforts share the queue and its bounds (per tree, in all), and timed efforts the
// bounds on active inputs, on the double pendulum of urdf/.
TEST(InputBounds, JointEffortsShareTheBounds) {
  scene::SceneOptions options;
  auto scene = scene::loadUrdfFile(
      std::string(CGA_RIGID_SIM_SOURCE_DIR) + "/urdf/double_pendulum.urdf", options);
  ASSERT_TRUE(scene.ok()) << scene.error();
  sim::WorldConfig c;
  c.max_queued_inputs_per_body = 5;
  c.max_active_wrenches_per_body = 2;
  auto made = sim::World::create(std::move(scene.value()), c);
  ASSERT_TRUE(made.ok()) << made.error();
  sim::World& w = *made.value();
  sim::JointEffortInput held;
  held.names = {"shoulder", "elbow"};
  held.efforts = {0.1, 0.2};
  ASSERT_TRUE(w.setJointEfforts(held).ok());  // 2 waiting
  sim::TimedJointEffortInput timed;
  timed.joint = "elbow";
  timed.effort = 0.3;
  timed.duration = -1;
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(w.applyJointEffort(timed).ok());  // 5 waiting
  auto r = w.applyJointEffort(timed);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(),
            "apply_joint_effort.joint: the tree of joint 'elbow' already has 5 inputs waiting "
            "for their step (max_queued_inputs_per_body = 5)");
  auto h = w.setJointEfforts(held);
  ASSERT_FALSE(h.ok());
  EXPECT_EQ(h.error().rfind("joint_efforts.name: the tree of joint 'shoulder' already has 5", 0),
            0u)
      << h.error();
  w.step();  // 3 timed efforts due: 2 start, the third is refused at its start
  EXPECT_EQ(w.queuedInputCount(), 0u);
  EXPECT_EQ(w.startRefusalCount(), 1u);
  EXPECT_EQ(w.lastStartRefusal()->message(),
            "apply_joint_effort.joint: the tree of joint 'elbow' already has 2 active timed "
            "joint efforts at step 0 (max_active_wrenches_per_body = 2)");
  // The effort the actuator applies is the held one plus the two timed ones that started.
  w.step();
  EXPECT_NEAR(w.jointStates().back().effort, 0.2 + 2 * 0.3, 1e-15);  // sums of 3 decimals
}

// Truth: expiry by the heap of end steps. World A gets 300 link-frame wrenches on 5 bodies with
// random starts and durations (1–30 steps); world B gets, for every step each of them acts in,
// a one-step wrench — so B never relies on a wrench ending later than the step after it
// started. Queued in (start step, A's arrival) order, B sums each body's loads in A's order, so
// the two stay bit-identical at every step, with the same active count.
TEST(InputBounds, WrenchesEndAtTheirStepWhateverTheirOrder) {
  std::vector<scene::BodyModel> bodies;
  for (int i = 0; i < 5; ++i)
    bodies.push_back(movingBody("b" + std::to_string(i), 1.0 + i, {0.1, 0.2, 0.25},
                                Eigen::Quaterniond::Identity(), {0, 0, 0}, {0.3, 1.0, 0.2}));
  sim::WorldConfig c;
  c.max_queued_inputs = c.max_queued_inputs_per_body = 100000;
  auto a = sim::World::create(makeScene(bodies), c).value();
  auto b = sim::World::create(makeScene(bodies), c).value();
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> start(0, 99), steps(1, 30), body(0, 4);
  struct W {
    int start, steps, body;
    double fx;
  };
  std::vector<W> ws;
  for (int i = 0; i < 300; ++i) ws.push_back({start(rng), steps(rng), body(rng), 0.01 * (i + 1)});
  const double dt = c.dt;
  auto input = [&](const W& w, double duration, int at) {
    sim::WrenchInput in;
    in.body = "b" + std::to_string(w.body);
    in.frame = in.body;  // link frame: fixed in the body, the same whenever it starts
    in.F = cga::Force(Eigen::Vector3d(w.fx, 0.1, 0));
    in.point = Eigen::Vector3d(0, 0.05, 0.02);
    in.start_time = at * dt;
    in.duration = duration;
    return in;
  };
  for (const W& w : ws) ASSERT_TRUE(a->applyWrench(input(w, w.steps * dt, w.start)).ok());
  std::vector<int> order(ws.size());  // A's start order: by start step, then arrival
  for (std::size_t i = 0; i < ws.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(),
                   [&](int x, int y) { return ws[x].start < ws[y].start; });
  for (int s = 0; s < 130; ++s)
    for (int i : order)
      if (ws[i].start <= s && s < ws[i].start + ws[i].steps) {
        ASSERT_TRUE(b->applyWrench(input(ws[i], 0.0, s)).ok());
      }
  for (int s = 0; s < 140; ++s) {
    a->step();
    b->step();
    ASSERT_TRUE(sameStates(*a, *b)) << "step " << s;
  }
  EXPECT_EQ(a->activeWrenchCount(), 0u);
  EXPECT_EQ(a->startRefusalCount(), 0u);
}

// Truth: WorldConfig's rule for the bounds (each ≥ 1), as World::create says it.
TEST(InputBounds, CreateRefusesABoundBelowOne) {
  sim::WorldConfig c;
  c.max_active_wrenches_per_body = 0;
  auto w = sim::World::create(twoBodies(), c);
  ASSERT_FALSE(w.ok());
  EXPECT_EQ(w.error(), "config.max_active_wrenches_per_body: must be ≥ 1 (got 0)");
}

}  // namespace input_bounds_test
}  // namespace cga_rigid_sim
