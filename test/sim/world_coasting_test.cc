// Coasting (src/sim/coasting.h): bodies on their closed form take no step; their state is
// evaluated when read. What a body does must not depend on whether, when or how often it is read.
#include <gtest/gtest.h>

#include <random>

#include "cga_rigid_sim/body/impulse.h"
#include "cga_rigid_sim/body/integrator_exact.h"
#include "sim/world_fixtures.h"

namespace cga_rigid_sim {
namespace world_coasting_test {

using testing::makeScene;
using testing::makeWorld;
using testing::movingBody;

// Bodies of every inertia class, some at rest, under gravity, tumbling.
scene::Scene mixedScene(int n) {
  return makeScene(testing::tumblingBodies(n, 5, 7, 3), Eigen::Vector3d(0, 0, -9.81));
}

// Truth: a second run of the same world, read differently. Three worlds get the same inputs —
// impulses and wrenches in world and link frames, starting at later times, some on bodies at
// rest — and are read every step, every 13 steps (plus one body's get_body_state every 5), and
// never until the end. The states must agree bit for bit wherever two of them are read: a
// read that changed what it read (e.g. re-anchored a coast, or continued from the last read)
// would show as a difference in the last bits. Also under `exact`, which coasts the same way.
TEST(WorldCoasting, ReadingNeverChangesTheRun) {
  for (const char* integrator : {"auto", "exact"}) {
    const scene::Scene scene = mixedScene(40);
    auto every = makeWorld(scene, 1e-3, integrator);
    auto sometimes = makeWorld(scene, 1e-3, integrator);
    auto never = makeWorld(scene, 1e-3, integrator);
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < 30; ++k) {
      const std::string body = "b" + std::to_string(rng() % 40);
      sim::WrenchInput in;
      in.body = body;
      in.frame = k % 2 ? "world" : body;
      in.F = cga::Force(Eigen::Vector3d(u(rng), u(rng), u(rng)));
      in.point = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.1;
      in.couple = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.1;
      in.start_time = 0.001 * (rng() % 2000);
      in.duration = 0.001 * (rng() % 50);
      sim::ImpulseInput j;
      j.body = "b" + std::to_string(rng() % 40);
      j.frame = k % 3 ? "world" : j.body;
      j.J = cga::Force(Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.1);
      j.point = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.1;
      j.start_time = 0.001 * (rng() % 2000);
      for (auto* w : {every.get(), sometimes.get(), never.get()}) {
        ASSERT_TRUE(w->applyWrench(in).ok());
        ASSERT_TRUE(w->applyImpulse(j).ok());
      }
    }
    for (int s = 1; s <= 2500; ++s) {
      every->step();
      sometimes->step();
      never->step();
      (void)every->bodyStates();
      if (s % 5 == 0) (void)sometimes->getBodyState("b11");
      if (s % 13 == 0) {
        ASSERT_TRUE(testing::sameStates(*every, *sometimes)) << "step " << s;
      }
    }
    EXPECT_TRUE(testing::sameStates(*every, *never)) << integrator;
    EXPECT_TRUE(testing::sameStates(*sometimes, *never)) << integrator;
  }
}

// Truth: a second method — the exact integrator stepped alone, every step, with the impulse
// applied by hand at its step (impulseMoment_B at that step's pose). The World coasts the body
// (checked), ends the coast at the impulse and coasts again from there. Tolerance: each
// half runs 800 steps, where stepped and evaluated closed forms agree to 64 ε (1 + phase)
// (FreeFlowAt.EqualsTheSteppedFlowToRoundOff); phases here are ≤ 4 rad, and the second half
// carries the first half's difference through the impulse and the flow, which does not amplify
// it by more than a few: 1e-12 on the rotor, w and x.
TEST(WorldCoasting, FollowsTheExactFlowThroughAnImpulse) {
  const Eigen::Quaterniond R0(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()));
  const Eigen::Vector3d w0(0.3, -2.0, 1.1), v0(0.4, 0.1, -0.3), x0(0.5, -1.0, 2.0);
  const Eigen::Vector3d g(0, 0, -9.81);
  auto w = makeWorld(makeScene({movingBody("box", 3.0, {0.1, 0.2, 0.25}, R0, x0, w0, v0)}, g));
  sim::ImpulseInput in;
  in.body = "box";
  in.frame = "world";
  in.J = cga::Force(Eigen::Vector3d(0.7, -0.4, 1.2));
  in.point = Eigen::Vector3d(0.6, -0.9, 1.2);
  in.angular = Eigen::Vector3d(0.01, 0.02, -0.03);
  in.start_time = 0.8;  // at the start of step 800
  ASSERT_TRUE(w->applyImpulse(in).ok());
  w->step(400);
  EXPECT_TRUE(w->data().coasting[0]);  // coasting, also after a read
  w->step(1200);
  EXPECT_TRUE(w->data().coasting[0]);                // coasting again after the impulse
  EXPECT_EQ(w->data().bodies[0].coast.start, 800u);  // from the impulse's step

  const double lambda = 1.0;
  const dynamics::Inertia I = *dynamics::Inertia::fromPrincipal("box", 3.0, {0.1, 0.2, 0.25});
  dynamics::BodyState s{cga::Motor::fromPose(R0, x0, lambda),
                        cga::Bivelocity::fromVelocities(w0, v0, lambda)};
  dynamics::ExactIntegrator exact;
  dynamics::Loads loads;
  loads.setGravity(g);
  for (int k = 0; k < 800; ++k) exact.step(I, loads, lambda, 1e-3, s);
  dynamics::applyImpulse(I, dynamics::impulseMoment_B(s, in.J, in.point, in.angular, lambda),
                         lambda, s);
  exact.reset();
  for (int k = 0; k < 800; ++k) exact.step(I, loads, lambda, 1e-3, s);

  const dynamics::BodyState c = testing::stateOf(*w, "box");
  EXPECT_LE((c.M_WB.rotation().coeffs() - s.M_WB.rotation().coeffs()).norm(), 1e-12);
  EXPECT_LE((c.omega_B.rot - s.omega_B.rot).norm(), 1e-12 * s.omega_B.rot.norm());
  EXPECT_LE((c.M_WB.translation(lambda) - s.M_WB.translation(lambda)).norm(), 1e-12);
}

// Truth: a second world started at the state a set_body_state gave. A coasting body that is set
// to a new state must continue from it exactly as a body that started there: the coast restarts
// from the new state (were the old coast kept, the state would jump back onto it at the next
// read). Bit for bit over the next 500 steps, also after the step count differs by 700.
TEST(WorldCoasting, ASetStateStartsAFreshCoast) {
  const Eigen::Quaterniond R0(Eigen::AngleAxisd(0.4, Eigen::Vector3d(0.3, 1, -2).normalized()));
  const scene::Scene scene = makeScene(
      {movingBody("box", 2.0, {0.1, 0.2, 0.25}, R0, {1, 2, 3}, {0.5, -1.5, 2.0}, {0.1, 0.2, 0.3})},
      Eigen::Vector3d(0, 0, -9.81));
  auto a = makeWorld(scene);
  a->step(700);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(1.2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(-1, 0.5, 4);
  ASSERT_TRUE(a->setBodyState("box", pose, {0.3, -0.2, 1.0}, {2.0, -0.7, 0.4}).ok());
  const dynamics::BodyState set = testing::stateOf(*a, "box");

  scene::Scene from_set = scene;
  from_set.bodies[0].M_WB0 = set.M_WB;
  from_set.bodies[0].omega_B0 = set.omega_B;
  auto b = makeWorld(from_set);
  ASSERT_TRUE(testing::bitwiseEqual(testing::stateOf(*b, "box"), set));
  for (int k = 0; k < 5; ++k) {
    a->step(100);
    b->step(100);
    EXPECT_TRUE(testing::bitwiseEqual(testing::stateOf(*a, "box"), testing::stateOf(*b, "box")))
        << "100 × " << k + 1 << " steps after the set";
  }
}

}  // namespace world_coasting_test
}  // namespace cga_rigid_sim
