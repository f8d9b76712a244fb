// Contacts against analytic solutions (doc/contacts.md): bounces, slopes, sliding, rolling,
// a stack, collisions between moving bodies, and a pile whose energy must never rise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/input/inputs.h"
#include "contact/contact_fixtures.h"

namespace cga_rigid_sim {
namespace contacts_test {

using testing::ball;
using testing::block;
using testing::contactWorld;
using testing::makeScene;
using testing::momentumOf;
using testing::slopeGravity;

constexpr double kG = 9.81;

sim::BodyStateReport stateNamed(const sim::World& w, const std::string& name) {
  for (const auto& s : w.bodyStates())
    if (s.name == name) return s;
  ADD_FAILURE() << "no body " << name;
  return {};
}

// Truth: a ball dropped from h0 onto a plane with restitution e rises to e^{2k} h0 after its
// k-th bounce, and comes to rest at √(2h0/g)(1+e)/(1−e). Each flight is the exact parabola and
// each bounce happens at the instant of touch (a landing), so the apexes are exact; measured at
// the steps, an apex is missed by at most ½ g h² = 4.9e-6 m: tolerance 1e-5 m. The bounces stop
// once the impact speed is below the resting threshold 2 g h: the flights left out last at most
// 2·(2 g h)/(g (1 − e)) = 8 ms (e = 1/2), plus a step: tolerance 10 ms.
TEST(Contacts, BouncingBallApexesAndTimeToRest) {
  const double h0 = 1.0, r = 0.1, e = 0.5;
  auto w = contactWorld(makeScene({ball("ball", 1.0, r, {0, 0, h0 + r})}, {0, 0, -kG}), 0.5, e);
  double prev_vz = 0.0, last_moving = 0.0;
  int k = 0;
  for (int s = 0; s < 3000; ++s) {
    w->step();
    const auto b = stateNamed(*w, "ball");
    const double vz = b.linear_velocity.z();
    if (prev_vz > 0 && vz <= 0 && k < 4) {
      ++k;
      EXPECT_NEAR(b.com.z() - r, std::pow(e, 2 * k) * h0, 1e-5) << "apex " << k;
    }
    if (std::abs(vz) > 1e-12) last_moving = w->time();
    prev_vz = vz;
  }
  EXPECT_EQ(k, 4);
  const double t_rest = std::sqrt(2 * h0 / kG) * (1 + e) / (1 - e);
  EXPECT_NEAR(last_moving, t_rest, 0.01);
  // At rest on the plane: exactly touching, and the energy book balances.
  const auto m = momentumOf(*w, "total");
  EXPECT_NEAR(stateNamed(*w, "ball").com.z(), r, 1e-9);
  EXPECT_NEAR(m.kinetic_energy + m.potential_energy + m.dissipated_energy, 1.0 * kG * (h0 + r),
              1e-9);
  std::printf("[ info ] bounce: at rest after %.4f s (analytic %.4f s)\n", last_moving, t_rest);
}

// Truth: a block on a slope of angle θ sticks iff tan θ ≤ μ; otherwise it slides with
// a = g (sin θ − μ cos θ). The slope is the plane under gravity tilted by θ. Sliding along one
// contact normal is integrated by the trapezoidal rule, exact for a constant acceleration:
// round-off only, tolerance 1e-9 relative. Sticking: the friction impulse balances the
// tangential kick exactly each step: drift below 1e-12 m in 2 s. Normal to the plane the block
// stays within 1e-10 m of it: the first step's solve stops once a sweep changes the velocity by
// less than 1.1e-12 m/s (contact/contact_solver.h), which lifts it by ~1e-11 m.
TEST(Contacts, BlockOnSlopeSticksIffTanThetaAtMostMuElseSlides) {
  const double mu = 0.4;
  for (const double tan_theta : {0.9 * mu, 1.1 * mu, 2.0 * mu}) {
    const double theta = std::atan(tan_theta);
    auto w = contactWorld(
        makeScene({block("b", 1.0, {0.2, 0.2, 0.2}, {0, 0, 0.1})}, slopeGravity(kG, theta)), mu,
        0.0);
    w->step(2000);
    const auto b = stateNamed(*w, "b");
    const double a = kG * (std::sin(theta) - mu * std::cos(theta));
    if (tan_theta <= mu) {
      EXPECT_LE(std::abs(b.com.x()), 1e-12) << "tan θ = " << tan_theta;
    } else {
      EXPECT_NEAR(b.com.x(), 0.5 * a * 4.0, 1e-9 * 2.0 * a) << "tan θ = " << tan_theta;
    }
    EXPECT_NEAR(b.com.z(), 0.1, 1e-10);  // on the plane, never into it
  }
}

// Truth: a block sliding at v0 on flat ground stops after v0²/(2 μ g), whatever the direction
// of the push (the friction cone is round, not a pyramid). The deceleration μ g is exact each
// step and the sliding trapezoidal; the last step, where the block stops within it, is off by
// at most ½ μ g h² = 1.5e-6 m: tolerance 1e-5 m.
TEST(Contacts, SlidingBlockStopsAfterV0SquaredOverTwoMuG) {
  const double mu = 0.3, v0 = 2.0;
  for (const double angle : {0.0, M_PI / 4, 1.0}) {
    const Eigen::Vector3d v(v0 * std::cos(angle), v0 * std::sin(angle), 0.0);
    auto w = contactWorld(
        makeScene({block("b", 1.0, {0.2, 0.2, 0.2}, {0, 0, 0.1}, v)}, {0, 0, -kG}), mu, 0.0);
    w->step(2000);
    const auto b = stateNamed(*w, "b");
    EXPECT_NEAR(b.com.head<2>().norm(), v0 * v0 / (2 * mu * kG), 1e-5) << "angle " << angle;
    EXPECT_LE(b.linear_velocity.norm(), 1e-12);
    // Along the push: the path is straight.
    EXPECT_LE(std::abs(b.com.head<2>().normalized().dot(Eigen::Vector2d(-v.y(), v.x()) / v0)),
              1e-9);
  }
}

// Truth: a ball launched sliding at v0 without spin decelerates at μ g while its spin grows at
// 5 μ g/(2 r), until it rolls at t = 2 v0/(7 μ g) with v = 5 v0/7, and rolls on at that speed.
// The friction impulse is exact per step (v = v0 − μ g t to the round-off of ~500 additions,
// < 1e-10); the step in which it starts rolling ends rolling: v after it is 5 v0/7 to
// the solver's tolerance (its sweeps stop at changes below 1.1e-12 m/s, the residual is ~10×
// that: 1e-10), and the slip (< 1e-9 m/s) ends within one step of t.
TEST(Contacts, SlidingBallStartsRollingAtTwoV0OverSevenMuG) {
  const double mu = 0.2, v0 = 3.0, r = 0.1, h = 1e-3;
  auto w =
      contactWorld(makeScene({ball("s", 1.0, r, {0, 0, r}, {v0, 0, 0})}, {0, 0, -kG}), mu, 0.0, h);
  const double t_roll = 2 * v0 / (7 * mu * kG);
  double t_first_rolling = -1;
  for (int s = 0; s < 1000; ++s) {
    w->step();
    const auto b = stateNamed(*w, "s");
    const double slip = b.linear_velocity.x() - b.angular_velocity.y() * r;  // bottom point
    if (t_first_rolling < 0 && std::abs(slip) < 1e-9) t_first_rolling = w->time();
    if (t_first_rolling < 0) {
      EXPECT_NEAR(b.linear_velocity.x(), v0 - mu * kG * w->time(), 1e-10);
    }
  }
  EXPECT_NEAR(t_first_rolling, t_roll, h);
  EXPECT_NEAR(stateNamed(*w, "s").linear_velocity.x(), 5 * v0 / 7, 1e-10);
}

// Truth: a ball rolls down a slope with a = (5/7) g sin θ when μ ≥ (2/7) tan θ. Trapezoidal
// along the plane: round-off, tolerance 1e-9 relative.
TEST(Contacts, BallRollsDownSlopeAtFiveSeventhsGSinTheta) {
  const double theta = 0.3, r = 0.1;
  const double mu = 1.2 * (2.0 / 7.0) * std::tan(theta);
  auto w =
      contactWorld(makeScene({ball("s", 1.0, r, {0, 0, r})}, slopeGravity(kG, theta)), mu, 0.0);
  w->step(1000);
  const double x = 0.5 * (5.0 / 7.0) * kG * std::sin(theta);
  EXPECT_NEAR(stateNamed(*w, "s").com.x(), x, 1e-9 * x);
}

// Truth: a stack of ten boxes on the ground stays put. It settles once (each box falls into
// the one below until the contact holds it: ≈ g h² = 1e-5 m per box, so < 1e-4 m at the top)
// and then must not move: drift < 0.1 mm over 10 s, and from 5 s on the kinetic energy at the
// solver's tolerance (its sweeps stop at changes below 1.1e-12 m/s, a column of boxes keeps a
// slow Gauss–Seidel mode at that level: velocities below 1e-8 m/s, six orders under the
// step's kick g h = 1e-2 m/s, give < 1e-15 J for the ten boxes).
TEST(Contacts, StackOfTenBoxesStaysPut) {
  std::vector<scene::BodyModel> bodies;
  for (int i = 0; i < 10; ++i)
    bodies.push_back(block("b" + std::to_string(i), 1.0, {0.2, 0.2, 0.2}, {0, 0, 0.1 + 0.2 * i}));
  auto w = contactWorld(makeScene(bodies, {0, 0, -kG}), 0.5, 0.0);
  const auto s0 = w->bodyStates();
  double drift = 0.0, late_ke = 0.0;
  for (int s = 0; s < 10000; ++s) {
    w->step();
    if (s % 100 == 99) {
      const auto st = w->bodyStates();
      for (std::size_t i = 0; i < st.size(); ++i)
        drift = std::max(drift, (st[i].com - s0[i].com).norm());
      if (w->time() >= 5.0) late_ke = std::max(late_ke, momentumOf(*w, "total").kinetic_energy);
    }
  }
  EXPECT_LT(drift, 1e-4);
  EXPECT_LT(late_ke, 1e-15);
  std::printf("[ info ] stack of 10: drift %.2e m, kinetic energy after 5 s ≤ %.1e J\n", drift,
              late_ke);
}

// Truth: contact impulses are internal: two balls colliding obliquely with friction keep their
// total linear momentum (round-off, 1e-14 relative) and lose kinetic energy, never gain it.
// Head on, frictionless, e = 1, equal masses: they exchange velocities exactly.
TEST(Contacts, CollisionsBetweenMovingBodiesConserveMomentum) {
  auto w = contactWorld(makeScene({ball("a", 1.0, 0.1, {0, 0, 0}, {1, 0, 0}, {0, 0, 3}),
                                   ball("b", 2.0, 0.1, {0.5, 0.05, 0}, {-1, 0, 0})}),
                        0.3, 1.0, 1e-3, false);
  const auto p0 = momentumOf(*w, "total");
  w->step(1000);
  const auto p1 = momentumOf(*w, "total");
  EXPECT_LE((p1.linear - p0.linear).norm(), 1e-14 * p0.linear.norm() + 1e-15);
  EXPECT_LE(p1.kinetic_energy, p0.kinetic_energy);
  EXPECT_GT(p1.dissipated_energy, 0.0);

  auto h = contactWorld(makeScene({ball("a", 1.0, 0.1, {0, 0, 0}, {1, 0, 0}),
                                   ball("b", 1.0, 0.1, {0.5, 0, 0}, {-1, 0, 0})}),
                        0.0, 1.0, 1e-3, false);
  h->step(1000);
  EXPECT_NEAR(stateNamed(*h, "a").linear_velocity.x(), -1.0, 1e-12);
  EXPECT_NEAR(stateNamed(*h, "b").linear_velocity.x(), 1.0, 1e-12);
}

// Truth (the documented impulse ordering, doc/contacts.md#impacts): the contacts of a step are
// solved together, Gauss–Seidel in detection order, and only an approaching contact bounces.
// Newton's cradle of five equal touching balls (e = 1, frictionless) struck by a sixth: the
// row's momentum is kept (round-off, 1e-14), kinetic energy never rises, the balls leave in
// order (none overtakes the one ahead, so none passes through another) and the last leaves
// fastest. Simultaneous impulses share the blow along the row rather than passing it on ball
// by ball (which needs a sequence of impacts within the step): the doc shows the numbers.
TEST(Contacts, NewtonsCradleFollowsTheSimultaneousOrdering) {
  std::vector<scene::BodyModel> balls;
  balls.push_back(ball("b0", 1.0, 0.1, {-0.3, 0, 0}, {1, 0, 0}));
  for (int i = 1; i < 6; ++i)
    balls.push_back(ball("b" + std::to_string(i), 1.0, 0.1, {0.2 * i - 0.2, 0, 0}));
  auto w = contactWorld(makeScene(balls), 0.0, 1.0, 1e-3, false);
  const auto m0 = momentumOf(*w, "total");
  double ke_max = m0.kinetic_energy;
  for (int s = 0; s < 500; ++s) {
    w->step();
    ke_max = std::max(ke_max, momentumOf(*w, "total").kinetic_energy);
  }
  const auto m1 = momentumOf(*w, "total");
  EXPECT_NEAR(m1.linear.x(), m0.linear.x(), 1e-14);
  EXPECT_LE(ke_max, m0.kinetic_energy * (1 + 1e-12));
  std::printf("[ info ] cradle velocities:");
  for (int i = 0; i < 6; ++i) {
    const double v = stateNamed(*w, "b" + std::to_string(i)).linear_velocity.x();
    std::printf(" %.4f", v);
    if (i > 0) {
      EXPECT_GE(v, stateNamed(*w, "b" + std::to_string(i - 1)).linear_velocity.x() - 1e-12);
    }
  }
  std::printf("\n");
}

// Truth: energy is never created: in a random pile of 100 boxes and balls dropped on the ground
// (e up to 0.5, μ 0.5), kinetic + potential energy never rises from one step to the next over
// 10 s beyond round-off of the total (1e-9 J of ~1e3 J), and the book balances:
// kinetic + potential + dissipated = initial (1e-6 relative: the contacts' position
// correction and the splitting's first-order terms are booked, not lost).
TEST(Contacts, EnergyNeverRisesInARandomPile) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<scene::BodyModel> bodies;
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d x(0.5 * u(rng), 0.5 * u(rng), 0.5 + 0.25 * i);
    const Eigen::Vector3d v(u(rng), u(rng), u(rng));
    const std::string name = "p" + std::to_string(i);
    if (i % 2) {
      bodies.push_back(ball(name, 1.0 + 0.5 * u(rng), 0.1, x, v, {u(rng), u(rng), u(rng)}));
    } else {
      const Eigen::Quaterniond R(
          Eigen::AngleAxisd(3 * u(rng), Eigen::Vector3d(u(rng), u(rng), 1).normalized()));
      bodies.push_back(block(name, 1.0 + 0.5 * u(rng), {0.2, 0.15, 0.1}, x, v, R));
    }
  }
  auto w = contactWorld(makeScene(bodies, {0, 0, -kG}), 0.5, 0.3);
  const auto m0 = momentumOf(*w, "total");
  const double e0 = m0.kinetic_energy + m0.potential_energy;
  double prev = e0, worst_rise = 0.0;
  for (int s = 0; s < 10000; ++s) {
    w->step();
    const auto m = momentumOf(*w, "total");
    const double e = m.kinetic_energy + m.potential_energy;
    worst_rise = std::max(worst_rise, e - prev);
    prev = e;
  }
  const auto m1 = momentumOf(*w, "total");
  EXPECT_LE(worst_rise, 1e-9);
  EXPECT_NEAR(m1.kinetic_energy + m1.potential_energy + m1.dissipated_energy, e0,
              1e-6 * std::abs(e0));
  std::printf("[ info ] pile of 100: largest one-step energy rise %.2e J, energy %.3f → %.3f J\n",
              worst_rise, e0, prev);
}

// Truth: two balls created 2 cm into each other (zero gravity, at rest) are reported once by
// name, and pushed apart without gaining kinetic energy: after 1 s they no longer overlap
// (deeper than the 50 µm slop) and the kinetic energy is still zero.
TEST(Contacts, BodiesStartingToOverlapAreReportedAndSeparatedWithoutEnergy) {
  auto w =
      contactWorld(makeScene({ball("a", 1.0, 0.1, {0, 0, 0}), ball("b", 1.0, 0.1, {0.18, 0, 0})}),
                   0.5, 0.5, 1e-3, false);
  const auto& warnings = w->scene().warnings;
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("body 'a' (link 'a') and body 'b' (link 'b') overlap by 0.02"),
            std::string::npos)
      << warnings[0];
  w->step(1000);
  const double gap = (stateNamed(*w, "b").com - stateNamed(*w, "a").com).norm() - 0.2;
  EXPECT_GE(gap, -6e-5);
  EXPECT_EQ(momentumOf(*w, "total").kinetic_energy, 0.0);
}

// Truth (doc/contacts.md#solver, SolverSettings::correction_onset): an overlap is corrected once
// it passes the 50 µm slop by more than 1 µm, then by 20 % of its part beyond the slop per step.
// Two balls at rest in zero gravity, one contact, nothing else moving them: 0.5 µm past the slop
// they stay exactly where they are; 20 µm past it one step removes 4 µm (a single row is solved
// exactly by the sweep; round-off of the 0.2 m coordinates, ~1e-16 m, allowed as 1e-12).
TEST(Contacts, OverlapIsCorrectedFromItsOnsetByAFifthPerStep) {
  const double slop = 5e-5;
  for (const double past : {0.5e-6, 20e-6}) {
    const double depth = slop + past;
    auto w = contactWorld(
        makeScene({ball("a", 1.0, 0.1, {0, 0, 0}), ball("b", 1.0, 0.1, {0.2 - depth, 0, 0})}), 0.5,
        0.0, 1e-3, false);
    const Eigen::Vector3d a0 = stateNamed(*w, "a").com, b0 = stateNamed(*w, "b").com;
    w->step(1);
    const Eigen::Vector3d a1 = stateNamed(*w, "a").com, b1 = stateNamed(*w, "b").com;
    const double depth1 = 0.2 - (b1 - a1).norm();
    if (past < 1e-6) {
      EXPECT_EQ(a1, a0);
      EXPECT_EQ(b1, b0);
    } else {
      EXPECT_NEAR(depth1 - slop, 0.8 * past, 1e-12);
    }
    EXPECT_EQ(momentumOf(*w, "total").kinetic_energy, 0.0) << past;
  }
}

// Sleeping (doc/contacts.md#sleeping). Truth: a stack of three boxes settles and then falls
// asleep: once its contact points have moved slower than 1e-6 m/s for 0.2 s its velocities are
// exactly zero, no contact is solved (no sweep), its contacts are still reported (4 corners per
// face: 12), its poses do not change by a bit for the next 5 s, and the energy book balances
// (kinetic + potential + dissipated = initial, round-off of the ~60 J: 1e-9 J). A wrench that
// friction cannot hold then wakes it and moves the box it pushes (½ (F/m − μ g) t² = 2.5 cm in
// 0.1 s alone; > 1 mm whatever the box above it does).
TEST(Contacts, SettledStackFallsAsleepAndStaysPutExactly) {
  std::vector<scene::BodyModel> bodies;
  for (int i = 0; i < 3; ++i)
    bodies.push_back(block("b" + std::to_string(i), 1.0, {0.2, 0.2, 0.2}, {0, 0, 0.1 + 0.2 * i}));
  auto w = contactWorld(makeScene(bodies, {0, 0, -kG}), 0.5, 0.0);
  const auto m0 = momentumOf(*w, "total");
  w->step(1000);
  const auto s1 = w->bodyStates();
  for (const auto& b : s1) {
    EXPECT_EQ(b.linear_velocity.norm(), 0.0) << b.name;
    EXPECT_EQ(b.angular_velocity.norm(), 0.0) << b.name;
  }
  EXPECT_EQ(w->data().contact_sweeps, 0);
  EXPECT_EQ(w->contacts().size(), 12u);
  w->step(5000);
  const auto s2 = w->bodyStates();
  for (std::size_t i = 0; i < s1.size(); ++i) {
    EXPECT_EQ(s2[i].com, s1[i].com) << s1[i].name;
    EXPECT_EQ(s2[i].pose_root.matrix(), s1[i].pose_root.matrix()) << s1[i].name;
  }
  const auto m = momentumOf(*w, "total");
  EXPECT_NEAR(m.kinetic_energy + m.potential_energy + m.dissipated_energy,
              m0.kinetic_energy + m0.potential_energy, 1e-9);
  // A wrench wakes it: 10 N sideways on the top box for 0.1 s, more than μ m g = 4.9 N holds.
  sim::WrenchInput push;
  push.body = "b2";
  push.F = cga::Force(Eigen::Vector3d(10, 0, 0), 0.0);
  push.point = s2[2].com;
  push.duration = 0.1;
  ASSERT_TRUE(w->applyWrench(push).ok());
  w->step(100);
  EXPECT_GT(stateNamed(*w, "b2").com.x() - s2[2].com.x(), 1e-3);
}

// Truth: a sleeping island wakes as a whole. An impulse J on the middle box of a sleeping
// stack of three moves it at once (J/m in the step it acts, as for any body) and wakes the
// boxes it rests on and carries: in the next steps their contacts are solved again; a box
// struck sideways by 0.5 N s slides (μ = 0.5 cannot hold it), the two others stay on it or
// under it. With sleeping off (WorldConfig::contact_sleeping = false) the same stack is solved
// every step and never frozen.
TEST(Contacts, SleepingIslandWakesOnAnImpulseAndSleepingCanBeTurnedOff) {
  std::vector<scene::BodyModel> bodies;
  for (int i = 0; i < 3; ++i)
    bodies.push_back(block("b" + std::to_string(i), 1.0, {0.2, 0.2, 0.2}, {0, 0, 0.1 + 0.2 * i}));
  auto w = contactWorld(makeScene(bodies, {0, 0, -kG}), 0.5, 0.0);
  w->step(1000);
  ASSERT_EQ(w->data().contact_sweeps, 0);  // asleep
  sim::ImpulseInput imp;
  imp.body = "b1";
  imp.J = cga::Force(Eigen::Vector3d(0.5, 0, 0), 0.0);
  imp.point = stateNamed(*w, "b1").com;
  ASSERT_TRUE(w->applyImpulse(imp).ok());
  w->step();
  EXPECT_GT(w->data().contact_sweeps, 0);
  EXPECT_GT(stateNamed(*w, "b1").linear_velocity.x(), 0.1);
  w->step(50);
  EXPECT_GT(w->data().contact_sweeps, 0);
  EXPECT_GT(stateNamed(*w, "b1").com.x(), 0.005);  // it slid
  EXPECT_GT(stateNamed(*w, "b2").com.x(), 0.0);    // carried along (or tipped), not frozen

  sim::WorldConfig config;
  config.contact_mu = 0.5;
  config.ground_plane = sim::GroundPlane{};
  config.contact_sleeping = false;
  auto awake = sim::World::create(makeScene(bodies, {0, 0, -kG}), config);
  ASSERT_TRUE(awake.ok()) << awake.error();
  for (int s = 0; s < 2000; ++s) {
    (*awake)->step();
    ASSERT_GT((*awake)->data().contact_sweeps, 0) << "step " << s;
  }
}

// Truth: the broad phase tests a sleeping body against the awake bodies on either side of it
// along the sweep axis (x) and never against other sleepers. Two boxes and two balls, each
// alone on the ground, all asleep after 1 s; an impulse then sends the left ball (+x, it comes
// before its box in the sweep) and the right ball (−x, after its box) at 2 m/s into their
// boxes, 0.3 m away. Both boxes are hit, so both must wake and be pushed away from their ball
// (by more than 1 mm: a 1 kg ball at ≥ 1 m/s against a 1 kg box), and no ball may pass into
// its box (its centre stays a radius from the face, within the 50 µm slop and a step's travel).
TEST(Contacts, SleepersAreFoundByAwakeBodiesOnEitherSideOfTheSweep) {
  auto w = contactWorld(
      makeScene({block("box_l", 1.0, {0.2, 0.2, 0.2}, {-1.0, 0, 0.1}),
                 block("box_r", 1.0, {0.2, 0.2, 0.2}, {1.0, 0, 0.1}),
                 ball("ball_l", 1.0, 0.1, {-1.5, 0, 0.1}), ball("ball_r", 1.0, 0.1, {1.5, 0, 0.1})},
                {0, 0, -kG}),
      0.5, 0.0);
  w->step(1000);
  ASSERT_EQ(w->data().contact_sweeps, 0);  // all asleep
  for (const auto& [name, dir] :
       {std::pair<std::string, double>{"ball_l", 1.0}, {"ball_r", -1.0}}) {
    sim::ImpulseInput imp;
    imp.body = name;
    imp.J = cga::Force(Eigen::Vector3d(2.0 * dir, 0, 0), 0.0);
    imp.point = stateNamed(*w, name).com;
    ASSERT_TRUE(imp.point.allFinite());
    ASSERT_TRUE(w->applyImpulse(imp).ok());
  }
  const double l0 = stateNamed(*w, "box_l").com.x(), r0 = stateNamed(*w, "box_r").com.x();
  for (int s = 0; s < 500; ++s) {
    w->step();
    EXPECT_LT(stateNamed(*w, "ball_l").com.x(), stateNamed(*w, "box_l").com.x() - 0.2 + 3e-3);
    EXPECT_GT(stateNamed(*w, "ball_r").com.x(), stateNamed(*w, "box_r").com.x() + 0.2 - 3e-3);
  }
  EXPECT_GT(stateNamed(*w, "box_l").com.x() - l0, 1e-3);
  EXPECT_LT(stateNamed(*w, "box_r").com.x() - r0, -1e-3);
}

// Truth: an awake body touching a sleeping one wakes it: a ball dropped onto a box asleep on
// the ground pushes it into the ground and off centre, so the box moves (it tilts or slides:
// its velocity is not zero in the steps after the impact), and the ball does not pass through
// it (it stays above the box's top face, within the 50 µm slop).
TEST(Contacts, AnAwakeBodyWakesTheSleepingBodyItTouches) {
  auto w = contactWorld(makeScene({block("box", 1.0, {0.2, 0.2, 0.2}, {0, 0, 0.1}),
                                   ball("ball", 5.0, 0.05, {0.08, 0.0, 2.0})},
                                  {0, 0, -kG}),
                        0.5, 0.0);
  w->step(500);  // the box sleeps; the ball is still falling (it lands at 0.6 s)
  ASSERT_EQ(stateNamed(*w, "box").linear_velocity.norm(), 0.0);
  ASSERT_GT(stateNamed(*w, "ball").com.z(), 0.4);
  double box_speed = 0.0, ball_low = 1.0;
  for (int s = 0; s < 600; ++s) {
    w->step();
    box_speed = std::max(box_speed, stateNamed(*w, "box").angular_velocity.norm());
    ball_low = std::min(ball_low, stateNamed(*w, "ball").com.z());
  }
  EXPECT_GT(box_speed, 1e-3);
  EXPECT_GT(ball_low, 0.2 + 0.05 - 2e-3);
}

// Truth: the contacts of a step are solved island by island (the bodies joined by their
// contacts; the ground joins nothing), each until its own sweeps converge, so nothing an island
// does can change another's motion. A column of three tilted boxes dropped with gaps (it
// lands, rocks and settles: many sweeps a step) must step to the bit as it does alone when, in
// the same world, a block slides at 3 m/s 3 m away (a fast island: a stopping rule over all
// contacts was looser for the column while it slid) and a second column lands 2 m away (its
// own impacts, sweeps and energy guard). Sleeping is off so every step is solved.
TEST(Contacts, AnIslandIsSolvedAsIfAloneInTheWorld) {
  const auto column = [](const std::string& name, double x, double z0) {
    std::vector<scene::BodyModel> c;
    for (int i = 0; i < 3; ++i)
      c.push_back(block(name + std::to_string(i), 1.0, {0.2, 0.2, 0.2},
                        {x, 0.01 * i, z0 + 0.25 * i}, {0, 0, 0},
                        Eigen::Quaterniond(Eigen::AngleAxisd(
                            0.05 * (i + 1), Eigen::Vector3d(1, 2, 0).normalized()))));
    return c;
  };
  const auto world = [](std::vector<scene::BodyModel> bodies) {
    return contactWorld(makeScene(bodies, {0, 0, -kG}), 0.5, 0.3, 1e-3, true, false);
  };
  auto alone = world(column("a", 0.0, 0.15));
  std::vector<scene::BodyModel> crowd = column("a", 0.0, 0.15);
  for (const auto& b : column("c", -2.0, 0.4)) crowd.push_back(b);
  crowd.push_back(block("slider", 1.0, {0.2, 0.2, 0.2}, {3.0, 0, 0.1}, {0, 3.0, 0}));
  auto with_others = world(crowd);
  int most_sweeps = 0;
  for (int s = 0; s < 800; ++s) {
    alone->step();
    with_others->step();
    most_sweeps = std::max(most_sweeps, alone->data().contact_sweeps);
    for (const std::string name : {"a0", "a1", "a2"}) {
      const auto x = stateNamed(*alone, name), y = stateNamed(*with_others, name);
      ASSERT_EQ(x.pose_root.matrix(), y.pose_root.matrix()) << name << " step " << s;
      ASSERT_EQ(x.linear_velocity, y.linear_velocity) << name << " step " << s;
      ASSERT_EQ(x.angular_velocity, y.angular_velocity) << name << " step " << s;
    }
  }
  EXPECT_GT(most_sweeps, 10);                                  // the column's solve is not trivial
  EXPECT_GT(stateNamed(*with_others, "slider").com.y(), 0.5);  // the slider slid
  EXPECT_LT(stateNamed(*with_others, "c2").com.z(), 0.6);      // the other column landed
}

// Truth: a column resting on the ground is solved as welded (doc/contacts.md#resting-islands):
// the exact solution of its contacts, every corner pushing and sticking, stops every box dead,
// and every face then carries the weight of the boxes above it: the impulse its corners give
// the box above (normal and friction, world) is (0, 0, (boxes above) m g h) per step. Ten
// 0.1 m boxes dropped with 5 cm gaps (the 1000-box pile's columns) land by 0.46 s (slightly
// tilted); from 0.5 s each box's speed |v| + 0.1 m |ω| must be below 1e-14 m/s (the step's kick
// g h = 1e-2 m/s cancelled to round-off, ~1e-17, with a margin of 100; Gauss–Seidel alone left
// the column creeping at 7e-10 … 5e-9 m/s through the next 0.5 s) and the faces' impulses equal
// the weights to 1e-12 relative (round-off of ten sums). Sleeping is off so every step is solved.
TEST(Contacts, RestingColumnIsWeldedAndCarriesItsWeight) {
  constexpr int kBoxes = 10;
  std::vector<scene::BodyModel> bodies;
  for (int i = 0; i < kBoxes; ++i)
    bodies.push_back(block("b" + std::to_string(i), 1.0, {0.1, 0.1, 0.1}, {0, 0, 0.55 + 0.15 * i}));
  const double h = 1e-3;
  auto w = contactWorld(makeScene(bodies, {0, 0, -kG}), 0.5, 0.2, h, true, false);
  ASSERT_TRUE(w);
  const auto index = [](const std::string& name) {
    return name == sim::kGroundPlaneName ? -1 : std::stoi(name.substr(1));
  };
  w->step(500);
  double fastest = 0.0, worst_weight = 0.0;
  for (int s = 0; s < 500; ++s) {
    w->step();
    for (const auto& b : w->bodyStates())
      fastest = std::max(fastest, b.linear_velocity.norm() + 0.1 * b.angular_velocity.norm());
    // The impulse of the face under box k on box k.
    std::vector<Eigen::Vector3d> carried(kBoxes, Eigen::Vector3d::Zero());
    for (const auto& c : w->contacts()) {
      const int a = index(c.body_a), b = index(c.body_b);
      const Eigen::Vector3d on_a = c.normal_impulse * c.normal + c.friction_impulse;
      carried[std::max(a, b)] += a > b ? on_a : Eigen::Vector3d(-on_a);
    }
    for (int k = 0; k < kBoxes; ++k) {
      const double weight = (kBoxes - k) * 1.0 * kG * h;
      worst_weight =
          std::max(worst_weight, (carried[k] - Eigen::Vector3d(0, 0, weight)).norm() / weight);
    }
  }
  EXPECT_LT(fastest, 1e-14);
  EXPECT_LT(worst_weight, 1e-12);
  std::printf("[ info ] resting column: speed <= %.1e m/s, weights to %.1e relative\n", fastest,
              worst_weight);
}

// Truth: the tabletop example scene (urdf/tabletop.urdf, started as config/tabletop.yaml does)
// comes to rest without gaining energy: the crate dropped on the table top rests on it (its
// centre 0.1 m above the top at z = 0.76 m, 1 mm: the settled overlap is far below), the
// bottle standing on the floor stays upright and still, nothing sinks below the floor, and the
// total energy never rises from one step to the next beyond round-off (1e-9 J).
TEST(Contacts, TabletopExampleSettlesWithoutGainingEnergy) {
  auto scene = scene::loadUrdfFile(std::string(CGA_RIGID_SIM_SOURCE_DIR) + "/urdf/tabletop.urdf",
                                   scene::SceneOptions());
  ASSERT_TRUE(scene.ok()) << scene.error();
  sim::WorldConfig config;
  config.ground_plane = sim::GroundPlane{};
  auto created = sim::World::create(std::move(*scene), config);
  ASSERT_TRUE(created.ok()) << created.error();
  sim::World& w = **created;
  const Eigen::Isometry3d crate_pose(Eigen::Translation3d(-0.2, 0.0, 1.2) *
                                     Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  ASSERT_TRUE(w.setBodyState("crate", crate_pose, Eigen::Vector3d::Zero(), {0, 0, 1}).ok());
  const Eigen::Isometry3d ball_pose(Eigen::Translation3d(-0.5, 0.2, 1.0));
  ASSERT_TRUE(w.setBodyState("ball", ball_pose, {1.5, -0.2, 0.0}, Eigen::Vector3d::Zero()).ok());
  double prev = 0.0, worst_rise = 0.0;
  for (int s = 0; s < 4000; ++s) {
    w.step();
    const auto m = momentumOf(w, "total");
    const double e = m.kinetic_energy + m.potential_energy;
    if (s > 0) worst_rise = std::max(worst_rise, e - prev);
    prev = e;
    for (const auto& b : w.bodyStates()) EXPECT_GT(b.com.z(), 0.0) << b.name;
  }
  EXPECT_LE(worst_rise, 1e-9);
  const auto crate = stateNamed(w, "crate");
  EXPECT_NEAR(crate.com.z(), 0.86, 1e-3);
  EXPECT_LT(crate.linear_velocity.norm(), 1e-9);
  const auto bottle = stateNamed(w, "bottle");
  EXPECT_GT((bottle.pose_root.rotation() * Eigen::Vector3d::UnitZ()).z(), 1.0 - 1e-9);
  EXPECT_NEAR(bottle.com.z(), 0.125, 1e-6);
}

}  // namespace contacts_test
}  // namespace cga_rigid_sim
