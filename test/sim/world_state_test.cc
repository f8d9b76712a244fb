// Body states, frames, momentum reports, static bodies, conservation in free flight.
#include <gtest/gtest.h>

#include <random>

#include "sim/world_fixtures.h"

namespace cga_rigid_sim {
namespace world_state_test {

using testing::kEps;
using testing::makeScene;
using testing::makeWorld;
using testing::momentumOf;
using testing::movingBody;
using testing::staticBody;

Eigen::Quaterniond randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized();
}
Eigen::Vector3d randomVector(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return {u(rng), u(rng), u(rng)};
}

// A body whose root link is neither at the CoM nor along the principal axes, plus a second
// merged link, and a static table with a leg.
scene::Scene offsetScene(const Eigen::Vector3d& g_W = Eigen::Vector3d(0, 0, -9.81)) {
  scene::BodyModel box =
      movingBody("box", 2.5, {0.1, 0.2, 0.25},
                 Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ())),
                 {0.3, 0.2, 1.0}, {0.5, 1.0, -0.7}, {0.2, 0, 0.4});
  box.links[0].M_BL = cga::Motor::fromPose(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.6, Eigen::Vector3d(1, -1, 2).normalized())),
      {-0.05, 0.1, -0.2}, 1.0);
  box.links.push_back({"lid", cga::Motor::fromPose(Eigen::Quaterniond(Eigen::AngleAxisd(
                                                       -0.3, Eigen::Vector3d::UnitX())),
                                                   {0.0, 0.0, 0.15}, 1.0)});
  scene::BodyModel table = staticBody(
      "table", Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ())), {2, 0, 0.5});
  table.links.push_back({"leg", cga::Motor::translator({0.4, 0.4, -0.25}, 1.0)});
  return makeScene({box,
                    movingBody("ball", 1.0, {0.4, 0.4, 0.4}, Eigen::Quaterniond::Identity(),
                               {-1, 0, 2}, {0, 0, 3}, {0, 1, 0}),
                    table},
                   g_W);
}

void expectIsometryNear(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double tol) {
  EXPECT_LE((a.linear() - b.linear()).cwiseAbs().maxCoeff(), tol);
  EXPECT_LE((a.translation() - b.translation()).cwiseAbs().maxCoeff(), tol);
}

// Truth: setBodyState and getBodyState are inverse maps (pose of the root link, CoM velocity
// and angular velocity, world axes), for a root link that is offset and turned from B, at
// random poses and velocities (fixed seed). Tolerance 1e-12: a handful of motor products and
// quaternion↔matrix conversions, each a few ε, on quantities of order 1–10.
TEST(WorldState, SetAndGetBodyStateRoundTrip) {
  auto w = makeWorld(offsetScene());
  std::mt19937 rng(2024);
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = randomRotation(rng).toRotationMatrix();
    pose.translation() = randomVector(rng, 10.0);
    const Eigen::Vector3d v = randomVector(rng, 5.0), omega = randomVector(rng, 5.0);
    ASSERT_TRUE(w->setBodyState("box", pose, v, omega).ok());
    const auto s = w->getBodyState("box");
    ASSERT_TRUE(s.ok());
    expectIsometryNear(s->pose_root, pose, 1e-12);
    EXPECT_LE((s->linear_velocity - v).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LE((s->angular_velocity - omega).cwiseAbs().maxCoeff(), 1e-12);
    // The CoM is where B's origin is: pose_root · M_BL0⁻¹ · 0.
    const Eigen::Isometry3d M_BL0 = w->scene().bodies[0].links[0].M_BL.toIsometry(1.0);
    EXPECT_LE((s->com - (pose * M_BL0.inverse()).translation()).cwiseAbs().maxCoeff(), 1e-12);
    // A unit motor: M M̃ = 1 to round-off, which scales with the dual part |q| = |x|/(2λ).
    EXPECT_LE(s->state.M_WB.normDrift(), 4 * kEps * (1 + s->com.norm()));
  }
}

// Truth: static bodies are never stepped. With gravity, wrenches and impulses on the moving
// bodies, 1000 steps leave the table's reported state and its frames bit-identical, while the
// moving bodies do fall.
TEST(WorldState, StaticBodiesNeverMove) {
  auto w = makeWorld(offsetScene());
  const auto table0 = w->getBodyState("table");
  const auto frames0 = w->staticFrames();
  sim::ImpulseInput j;
  j.body = "box";
  j.J = cga::Force(Eigen::Vector3d(1, 2, 3));
  j.start_time = 0.1;
  ASSERT_TRUE(w->applyImpulse(j).ok());
  const double z0 = w->getBodyState("ball")->com.z();
  w->step(1000);
  const auto table1 = w->getBodyState("table");
  EXPECT_TRUE(testing::bitwiseEqual(table0->state, table1->state));
  EXPECT_TRUE(table1->pose_root.matrix() == table0->pose_root.matrix());
  EXPECT_EQ(table1->linear_velocity, Eigen::Vector3d::Zero());
  const auto frames1 = w->staticFrames();
  ASSERT_EQ(frames0.size(), frames1.size());
  for (std::size_t i = 0; i < frames0.size(); ++i)
    EXPECT_TRUE(frames0[i].pose.matrix() == frames1[i].pose.matrix()) << frames0[i].child;
  EXPECT_LT(w->getBodyState("ball")->com.z(), z0 - 1.0);
  for (const auto& m : w->momentum()) EXPECT_NE(m.body, "table");
}

// Truth: the frame lists. movingFrames: world → root link at the reported pose_root.
// staticFrames: world → the static root link at its pose; root link → each other merged link
// at M_BL0⁻¹ M_BL (checked with Eigen isometries, 1e-12).
TEST(WorldState, FramesGiveRootPosesAndMergedLinksRelativeToTheRoot) {
  auto w = makeWorld(offsetScene());
  w->step(10);
  const auto moving = w->movingFrames();
  ASSERT_EQ(moving.size(), 2u);
  EXPECT_EQ(moving[0].parent, "world");
  EXPECT_EQ(moving[0].child, "box");
  EXPECT_TRUE(moving[0].pose.matrix() == w->getBodyState("box")->pose_root.matrix());
  EXPECT_EQ(moving[1].child, "ball");

  const auto& bodies = w->scene().bodies;
  const auto fixed = w->staticFrames();
  ASSERT_EQ(fixed.size(), 3u);  // box → lid, world → table, table → leg
  EXPECT_EQ(fixed[0].parent, "box");
  EXPECT_EQ(fixed[0].child, "lid");
  expectIsometryNear(
      fixed[0].pose,
      bodies[0].links[0].M_BL.toIsometry(1).inverse() * bodies[0].links[1].M_BL.toIsometry(1),
      1e-12);
  EXPECT_EQ(fixed[1].parent, "world");
  EXPECT_EQ(fixed[1].child, "table");
  expectIsometryNear(fixed[1].pose, bodies[2].M_WB0.toIsometry(1), 1e-12);
  EXPECT_EQ(fixed[2].parent, "table");
  EXPECT_EQ(fixed[2].child, "leg");
  EXPECT_LE((fixed[2].pose.translation() - Eigen::Vector3d(0.4, 0.4, -0.25)).norm(), 1e-15);
}

// Truth: the definitions of the "total" report, recomputed independently from the body
// reports: sums of p, L_origin, T, V; and L about the system's centre of mass as
// Σ (x_i − x_cm) × p_i + L_i (not the plain sum of spins). Tolerance 1e-12 of the magnitudes.
TEST(WorldState, TotalMomentumIsAboutTheSystemCentreOfMass) {
  auto w = makeWorld(offsetScene());
  w->step(20);
  const auto reports = w->momentum();
  ASSERT_EQ(reports.size(), 3u);
  EXPECT_EQ(reports.back().body, "total");
  double mass = 0;
  Eigen::Vector3d mx = Eigen::Vector3d::Zero(), P = Eigen::Vector3d::Zero(),
                  L0 = Eigen::Vector3d::Zero();
  double T = 0, V = 0;
  for (int i = 0; i < 2; ++i) {
    const auto& b = w->scene().bodies[i];
    const auto s = w->getBodyState(b.name);
    mass += b.inertia->mass();
    mx += b.inertia->mass() * s->com;
    P += reports[i].linear;
    L0 += reports[i].angular_origin;
    T += reports[i].kinetic_energy;
    V += reports[i].potential_energy;
    EXPECT_LE(
        (reports[i].angular_origin - (s->com.cross(reports[i].linear) + reports[i].angular)).norm(),
        1e-12 * reports[i].angular_origin.norm());
  }
  const Eigen::Vector3d x_cm = mx / mass;
  Eigen::Vector3d L_cm = Eigen::Vector3d::Zero();
  for (int i = 0; i < 2; ++i)
    L_cm += (w->getBodyState(w->scene().bodies[i].name)->com - x_cm).cross(reports[i].linear) +
            reports[i].angular;
  const auto& total = reports.back();
  EXPECT_LE((total.linear - P).norm(), 1e-12 * P.norm());
  EXPECT_LE((total.angular_origin - L0).norm(), 1e-12 * L0.norm());
  EXPECT_LE((total.angular - L_cm).norm(), 1e-12 * L0.norm()) << total.angular.transpose();
  EXPECT_NEAR(total.kinetic_energy, T, 1e-12 * T);
  EXPECT_NEAR(total.potential_energy, V, 1e-12 * std::abs(V));
}

// Truth: conservation in free flight (no gravity, no input): each body's p and L_com and the
// total L_origin stay constant; the default integrator solves torque-free motion exactly, so
// 1e-12 relative over 10 s (10 000 steps, a few ε of round-off per step) is the budget.
TEST(WorldState, FreeFlightMomentumIsConstant) {
  auto w = makeWorld(offsetScene(Eigen::Vector3d::Zero()));
  const auto m0 = w->momentum();
  w->step(10000);
  EXPECT_DOUBLE_EQ(w->time(), 10.0);
  const auto m1 = w->momentum();
  ASSERT_EQ(m0.size(), m1.size());
  for (std::size_t i = 0; i < m0.size(); ++i) {
    EXPECT_LE((m1[i].linear - m0[i].linear).norm(), 1e-12 * m0[i].linear.norm()) << m0[i].body;
    EXPECT_LE((m1[i].angular - m0[i].angular).norm(), 1e-12 * m0[i].angular.norm())
        << m0[i].body << ": " << m0[i].angular.transpose() << " → " << m1[i].angular.transpose();
    EXPECT_LE((m1[i].angular_origin - m0[i].angular_origin).norm(),
              1e-12 * m0[i].angular_origin.norm())
        << m0[i].body;
  }
}

// Truth: a body with no load and no velocity stays exactly where it is (it is skipped, and the
// summary says "at-rest"); a push wakes it.
TEST(WorldState, BodiesAtRestStayBitwiseAndWakeOnInput) {
  auto w = makeWorld(makeScene({movingBody("box", 1.0, {0.1, 0.2, 0.3},
                                           Eigen::Quaterniond(0.5, 0.5, 0.5, 0.5), {1, 2, 3})}));
  const auto s0 = testing::stateOf(*w, "box");
  w->step(100);
  EXPECT_TRUE(testing::bitwiseEqual(s0, testing::stateOf(*w, "box")));
  EXPECT_NE(w->summary().find("at-rest"), std::string::npos) << w->summary();
  sim::ImpulseInput in;
  in.body = "box";
  in.J = cga::Force(Eigen::Vector3d(0, 0, 1));
  ASSERT_TRUE(w->applyImpulse(in).ok());
  w->step(10);
  EXPECT_NEAR(w->getBodyState("box")->com.z(), 3.0 + 10 * w->config().dt, 1e-14);
}

}  // namespace world_state_test
}  // namespace cga_rigid_sim
