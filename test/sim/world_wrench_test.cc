// Wrenches: duration in whole steps, world-fixed vs body-fixed directions, link frames, sums.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/world_fixtures.h"

namespace cga_rigid_sim {
namespace world_wrench_test {

using testing::kEps;
using testing::makeScene;
using testing::makeWorld;
using testing::momentumOf;
using testing::movingBody;

// A tumbling asymmetric body, no gravity.
scene::Scene tumbler() {
  return makeScene(
      {movingBody("box", 2.0, {0.1, 0.2, 0.25},
                  Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized())),
                  {1.0, -2.0, 0.5}, {0.3, -0.2, 1.1}, {0.4, 0.1, -0.3})});
}

sim::WrenchInput worldForceAtCom(const sim::World& w, const Eigen::Vector3d& f, double duration) {
  sim::WrenchInput in;
  in.body = "box";
  in.frame = "world";
  in.F = cga::Force(f);
  in.point = w.getBodyState("box")->com;  // the CoM now: no torque
  in.duration = duration;
  return in;
}

// Truth: Newton's second law for a force through the CoM, Δp = f·n·dt, whatever the spin; the
// wrench acts in exactly n = round(d/dt) steps. Tolerance: p is rounded once per step (and
// carried through the body rotation), ≤ a few ε|p| per step, so 4·n·ε·max|p|.
TEST(WorldWrench, ForceThroughComChangesMomentumByForceTimesDuration) {
  auto w = makeWorld(tumbler());
  const Eigen::Vector3d f(3.0, -1.5, 2.0);
  const double dt = w->config().dt;
  const int n = 100;
  const Eigen::Vector3d p0 = momentumOf(*w, "box").linear;
  ASSERT_TRUE(w->applyWrench(worldForceAtCom(*w, f, n * dt)).ok());
  w->step(n - 1);
  EXPECT_EQ(w->activeWrenchCount(), 1u);  // still acting in step n − 1
  w->step();
  EXPECT_EQ(w->activeWrenchCount(), 0u);  // ended after exactly n steps
  w->step(5);                             // and nothing more happens
  const Eigen::Vector3d dp = momentumOf(*w, "box").linear - p0;
  const Eigen::Vector3d expected = f * (n * dt);
  const double tol = 4 * n * kEps * std::max(p0.norm(), (p0 + expected).norm());
  EXPECT_LE((dp - expected).norm(), tol) << dp.transpose() << " vs " << expected.transpose();
}

// Truth: the documented rounding n = floor(d/dt + 1/2 + 1e-9), at least 1; d = 0 is one step.
// Counted through Δp = f·n·dt of a force through the CoM of a body at rest (so Δp/(|f| dt) is
// an integer up to n·ε round-off; compared to ±1e-9).
TEST(WorldWrench, DurationRoundsToWholeStepsHalvesUp) {
  struct Case {
    double dt, steps_given;
    int expected;
  };
  const Case cases[] = {{1e-3, 2.5, 3}, {1e-3, 2.4, 2},       {1e-3, 0.0, 1},
                        {1e-3, 0.2, 1}, {1e-3, 1.5, 2},       {0.01, 3.5, 4},
                        {0.01, 7.0, 7}, {1e-3 / 3, 3.5, 4},   {1e-3 / 3, 7.0, 7},
                        {1e-3, 0.5, 1}, {1e-3, 1000.0, 1000}, {1e-3, 2.5000001, 3}};
  for (const Case& c : cases) {
    auto w = makeWorld(makeScene({movingBody("box", 1.0, {1, 1, 1})}), c.dt);
    const Eigen::Vector3d f(0.0, 0.0, 1.0);
    ASSERT_TRUE(w->applyWrench(worldForceAtCom(*w, f, c.steps_given * c.dt)).ok());
    w->step(static_cast<std::uint64_t>(c.expected) + 3);
    const double steps = momentumOf(*w, "box").linear.z() / c.dt;
    EXPECT_NEAR(steps, c.expected, 1e-9) << "dt " << c.dt << ", d = " << c.steps_given << " dt";
  }
}

// Truth: a negative duration acts until clearWrenches(): Δp = f·(steps so far)·dt, then stops.
// Tolerance as in ForceThroughComChangesMomentumByForceTimesDuration (body at rest: |p| ≤ |Δp|).
TEST(WorldWrench, NegativeDurationLastsUntilCleared) {
  auto w = makeWorld(makeScene({movingBody("box", 1.0, {1, 1, 1})}));
  const double dt = w->config().dt;
  const Eigen::Vector3d f(1.0, 2.0, -3.0);
  ASSERT_TRUE(w->applyWrench(worldForceAtCom(*w, f, -1.0)).ok());
  w->step(500);
  EXPECT_EQ(w->activeWrenchCount(), 1u);
  w->clearWrenches();
  EXPECT_EQ(w->activeWrenchCount(), 0u);
  w->step(100);
  const Eigen::Vector3d expected = f * (500 * dt);
  EXPECT_LE((momentumOf(*w, "box").linear - expected).norm(), 4 * 500 * kEps * expected.norm());
}

// Truth (analytic): a body spinning at ω about the world z axis (torque-free, spherical, so the
// spin stays ω) with a thruster f fixed in the body through its CoM: f_W(t) = F(cos ωt,
// sin ωt, 0), so v(t) = v0 + F/(mω)(sin ωt, 1 − cos ωt, 0). The same force given in the world
// frame does not turn: v(t) = v0 + F t/m (1, 0, 0). Tolerance: an integrator of order ≥ 2 errs
// by O((ωh)²) relative on the thruster (ωh = 2e-3 → 4e-6; 1e-5 allows a constant of 2.5); the
// world-fixed force is integrated exactly (n·ε round-off).
TEST(WorldWrench, BodyFrameWrenchTurnsWithTheBodyWorldFrameDoesNot) {
  const double omega = 2.0, m = 1.5, F = 3.0, T = 1.0;
  const Eigen::Vector3d v0(0.1, -0.2, 0.3);
  auto make = [&] {
    return makeWorld(makeScene({movingBody(
        "box", m, {0.3, 0.3, 0.3}, Eigen::Quaterniond::Identity(), {0, 0, 1}, {0, 0, omega}, v0)}));
  };
  auto body_fixed = make(), world_fixed = make();
  const double dt = body_fixed->config().dt;
  const int n = static_cast<int>(std::lround(T / dt));

  sim::WrenchInput thruster;
  thruster.body = "box";
  thruster.frame = "box";  // the root link, at the CoM with B's axes
  thruster.F = cga::Force(Eigen::Vector3d(F, 0, 0));
  thruster.duration = T;
  ASSERT_TRUE(body_fixed->applyWrench(thruster).ok());
  sim::WrenchInput push = thruster;
  push.frame = "world";
  push.point = Eigen::Vector3d(0, 0, 1);  // the CoM
  ASSERT_TRUE(world_fixed->applyWrench(push).ok());
  body_fixed->step(n);
  world_fixed->step(n);

  const Eigen::Vector3d dv_thruster =
      F / (m * omega) * Eigen::Vector3d(std::sin(omega * T), 1 - std::cos(omega * T), 0);
  const auto sb = body_fixed->getBodyState("box");
  EXPECT_LE((sb->linear_velocity - v0 - dv_thruster).norm(), 1e-5 * dv_thruster.norm())
      << sb->linear_velocity.transpose();
  EXPECT_NEAR(sb->angular_velocity.z(), omega, 1e-12 * omega);

  const Eigen::Vector3d dv_push(F * T / m, 0, 0);
  const auto sw = world_fixed->getBodyState("box");
  EXPECT_LE((sw->linear_velocity - v0 - dv_push).norm(), 4 * n * kEps * (v0 + dv_push).norm());
  EXPECT_NEAR(sw->angular_velocity.z(), omega, 1e-12 * omega);
}

// Truth: a wrench given in a link frame L is carried into B with the link's placement M_BL:
// f_B = R_BL f_L, x_B = M_BL x_L, τ_B = R_BL τ_L. Link "nozzle" is turned 90° about z and set
// at (0.5, 0.3, 0) in B, so the link point (−0.3, 0.5, 0) is the CoM. (a) A force there makes
// no torque: the body does not turn, Δp = R_WB R_BL f_L dt exactly and L stays 0 (the point
// taken unconverted would make a torque of 1.2 N m). (b) A couple along the link's z (= B's z) on a
// spherical body spins it about that fixed axis: ΔL = R_WB R_BL τ_L dt exactly. Tolerance: a
// few ε of the results.
TEST(WorldWrench, LinkFrameWrenchUsesTheLinkPlacement) {
  const Eigen::Quaterniond R_WB(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()));
  const Eigen::Quaterniond R_BL(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  auto make = [&] {
    scene::BodyModel b = movingBody("box", 2.0, {0.5, 0.5, 0.5}, R_WB, {1, 2, 3});
    b.links.push_back({"nozzle", cga::Motor::fromPose(R_BL, {0.5, 0.3, 0}, 1.0)});
    return makeWorld(makeScene({b}));
  };
  auto wf = make(), wc = make();
  const double dt = wf->config().dt;
  sim::WrenchInput in;
  in.body = "nozzle";  // any link names the body
  in.frame = "nozzle";
  in.F = cga::Force(Eigen::Vector3d(4.0, 0, 0));
  in.point = Eigen::Vector3d(-0.3, 0.5, 0);
  ASSERT_TRUE(wf->applyWrench(in).ok());
  wf->step();
  const auto mf = momentumOf(*wf, "box");
  const Eigen::Vector3d dp = (R_WB * R_BL) * in.F.f * dt;
  EXPECT_LE((mf.linear - dp).norm(), 8 * kEps * dp.norm()) << mf.linear.transpose();
  EXPECT_LE(mf.angular.norm(), 8 * kEps * dp.norm()) << mf.angular.transpose();

  in.F = cga::Force();
  in.couple = Eigen::Vector3d(0, 0, 0.25);
  ASSERT_TRUE(wc->applyWrench(in).ok());
  wc->step();
  const auto mc = momentumOf(*wc, "box");
  const Eigen::Vector3d dL = (R_WB * R_BL) * in.couple * dt;
  EXPECT_LE((mc.angular - dL).norm(), 8 * kEps * dL.norm()) << mc.angular.transpose();
  EXPECT_LE(mc.linear.norm(), 8 * kEps * dL.norm());
}

// Truth: concurrent wrenches add. (a) Through the CoM with different durations:
// Δp = (3 f1 + 5 f2) dt. (b) Two body-fixed wrenches off the CoM against one equivalent
// body-fixed wrench (their summed force at the CoM plus the couple r1×f1 + r2×f2): the body
// moment is the same at every pose, so the trajectories agree up to the round-off of summing
// (≈ ε per step, growing at most linearly over 200 smooth steps: 1e-12 relative is ample).
TEST(WorldWrench, ConcurrentWrenchesAdd) {
  {
    auto w = makeWorld(makeScene({movingBody("box", 1.0, {1, 1, 1})}));
    const double dt = w->config().dt;
    const Eigen::Vector3d f1(1, 0, 2), f2(0, -3, 1);
    ASSERT_TRUE(w->applyWrench(worldForceAtCom(*w, f1, 3 * dt)).ok());
    ASSERT_TRUE(w->applyWrench(worldForceAtCom(*w, f2, 5 * dt)).ok());
    w->step(10);
    const Eigen::Vector3d expected = (3 * f1 + 5 * f2) * dt;
    EXPECT_LE((momentumOf(*w, "box").linear - expected).norm(), 40 * kEps * expected.norm());
  }
  {
    auto two = makeWorld(tumbler()), one = makeWorld(tumbler());
    const Eigen::Vector3d f1(1, 0, 2), r1(0.1, 0.2, 0), f2(0, -3, 1), r2(-0.1, 0, 0.3);
    sim::WrenchInput a;
    a.body = a.frame = "box";
    a.duration = 0.2;
    sim::WrenchInput b = a, sum = a;
    a.F = cga::Force(f1);
    a.point = r1;
    b.F = cga::Force(f2);
    b.point = r2;
    sum.F = cga::Force(f1 + f2);
    sum.couple = r1.cross(f1) + r2.cross(f2);
    ASSERT_TRUE(two->applyWrench(a).ok());
    ASSERT_TRUE(two->applyWrench(b).ok());
    ASSERT_TRUE(one->applyWrench(sum).ok());
    two->step(300);
    one->step(300);
    const auto m2 = momentumOf(*two, "box"), m1 = momentumOf(*one, "box");
    EXPECT_LE((m2.linear - m1.linear).norm(), 1e-12 * m1.linear.norm());
    EXPECT_LE((m2.angular - m1.angular).norm(), 1e-12 * m1.angular.norm());
    const auto s2 = two->getBodyState("box"), s1 = one->getBodyState("box");
    EXPECT_LE((s2->com - s1->com).norm(), 1e-12 * s1->com.norm());
  }
}

// Truth (doc/conventions.md (E12)): α of F = f + αn drops out of the moment exactly, so α = 0
// and α = 1e3 give bit-identical trajectories (wrench in a link frame and in the world frame, and
// an impulse).
TEST(WorldWrench, AlphaNeverChangesTheMotion) {
  auto run = [](double alpha) {
    auto w = makeWorld(tumbler());
    sim::WrenchInput a;
    a.body = a.frame = "box";
    a.F = cga::Force(Eigen::Vector3d(1, 2, 3), alpha);
    a.point = Eigen::Vector3d(0.1, 0, 0);
    a.duration = 0.05;
    sim::WrenchInput b = a;
    b.frame = "world";
    sim::ImpulseInput j;
    j.body = "box";
    j.frame = "box";
    j.J = cga::Force(Eigen::Vector3d(0, 0.5, 0), alpha);
    j.point = Eigen::Vector3d(0, 0, 0.2);
    j.start_time = 0.01;
    EXPECT_TRUE(w->applyWrench(a).ok());
    EXPECT_TRUE(w->applyWrench(b).ok());
    EXPECT_TRUE(w->applyImpulse(j).ok());
    w->step(100);
    return w;
  };
  EXPECT_TRUE(testing::sameStates(*run(0.0), *run(1e3)));
}

// Truth: a force of 2.3e-159 N applied 1 m from the centre of mass for one step of 1 ms gives an
// asymmetric body an angular momentum of about 2e-162 N m s, so |L|² is at the bottom of the
// doubles (subnormal or 0) and the body turns by less than 1e-155 rad in the 20 steps after:
// the state stays finite and the rotor within 1e-150 of where it was (0 would be exact up to
// that turn; 1e-150 is far below any round-off of a unit rotor, 1e-16, and far above the turn).
// Before, the exact flow of the next step made the state NaN (found by
// fuzz/fuzz_world_inputs.cc on the box of test/ros/bodies.urdf with `auto`; the reproducer is
// fuzz/corpus/world_inputs/regression_tiny_force_exact_flow_nan). Several magnitudes and
// directions, since which one lands |L|² on a subnormal depends on the last bits.
TEST(WorldWrench, TinyForceOffTheCentreOfMassLeavesAFiniteState) {
  for (const double f : {2.2761049594727193e-159, 1e-159, 5e-160, 3e-159, 1e-158}) {
    for (const Eigen::Vector3d& dir :
         {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0.6, 0.0, 0.8)}) {
      for (const char* integrator : {"auto", "exact", "cga2", "cga4"}) {
        auto w =
            makeWorld(makeScene({movingBody("box", 2.0, {0.0083, 0.0166, 0.0216},
                                            Eigen::Quaterniond(Eigen::AngleAxisd(
                                                0.4, Eigen::Vector3d(1, 2, 3).normalized())))}),
                      1e-3, integrator);
        ASSERT_TRUE(w);
        const Eigen::Quaterniond R0 = w->getBodyState("box")->state.M_WB.rotation();
        sim::WrenchInput in;
        in.body = "box";
        in.frame = "world";
        in.F = cga::Force(f * dir);
        in.point = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();  // 1 m from the CoM
        ASSERT_TRUE(w->applyWrench(in).ok());
        for (int k = 0; k < 21; ++k) {
          w->step();
          const dynamics::BodyState s = w->getBodyState("box")->state;
          ASSERT_TRUE(s.allFinite())
              << "f " << f << " along " << dir.transpose() << ", " << integrator << ", step " << k;
          EXPECT_LE((s.M_WB.rotation().coeffs() - R0.coeffs()).norm(), 1e-150) << integrator;
        }
      }
    }
  }
}

}  // namespace world_wrench_test
}  // namespace cga_rigid_sim
