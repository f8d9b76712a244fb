// A resting tree's contacts solved by Newton's method (doc/contacts.md#resting-trees,
// src/contact/contact_resting_tree.h): the solver itself against a problem with a known answer,
// and a humanoid-like robot of this repository's own (test/common/real_like_robots.h) that
// falls onto the ground plane, lies there still, sleeps, and keeps its energy book.
#include <gtest/gtest.h>

#include <cmath>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/world.h"
#include "common/real_like_robots.h"
#include "contact/contact_tree_newton.h"

namespace cga_rigid_sim {
namespace sim {
namespace tree_resting_test {

// Two coordinates with masses 2 and 3 kg, pulled to ν_f = (−1, −2) m/s; rows ν_0 ≥ 0 (twice:
// redundant, as a lying robot's are), ν_1 ≥ 0.5 and ν_0 + ν_1 ≥ −5 (inactive). The exact answer:
// ν = (0, 0.5), the first pair's impulses summing to m_0 · 1 = 2 N s, the third's m_1 · 2.5 =
// 7.5 N s, the last none. Started cold (no impulse), the augmented Lagrangian rounds bring every
// row to its target (1e-11 m/s asked; 1e-10 allowed for the compliance's last round).
TEST(TreeResting, NewtonSolvesRedundantRowsExactly) {
  TreeNewton N;
  N.resize(4, 0, 2);
  N.g.topRows(4) << 1, 0, 1, 0, 0, 1, 1, 1;
  N.r.head(4) << 0, 0, 0.5, -5;
  N.D.head(4) << 1e6 / 0.5, 1e6 / 0.5, 1e6 / (1.0 / 3), 1e6 / (0.5 + 1.0 / 3);
  N.beta.head(4).setZero();
  Eigen::MatrixXd M = Eigen::Vector2d(2, 3).asDiagonal();
  const Eigen::VectorXd nu_f = Eigen::Vector2d(-1, -2);
  Eigen::VectorXd nu = nu_f;
  ASSERT_GT(N.solve(M, nu_f, nu, 1e-11, 20, 20), 0);
  EXPECT_NEAR(nu[0], 0.0, 1e-10);
  EXPECT_NEAR(nu[1], 0.5, 1e-10);
  // Impulses: their scale times the velocity tolerance, and the redundant pair shares equally
  // (the minimiser is symmetric in them).
  EXPECT_NEAR(N.beta[0] + N.beta[1], 2.0, 1e-9);
  EXPECT_NEAR(N.beta[0], N.beta[1], 1e-9);
  EXPECT_NEAR(N.beta[2], 7.5, 1e-9);
  EXPECT_EQ(N.beta[3], 0.0);
  // The same with the stops as single rows (on one coordinate each): the same answer.
  TreeNewton S;
  S.resize(0, 2, 2);
  S.single[0] = {0, 1.0, 0.0, 1e6 / 0.5, 0.0};
  S.single[1] = {1, 1.0, 0.5, 1e6 * 3, 0.0};
  nu = nu_f;
  ASSERT_GT(S.solve(M, nu_f, nu, 1e-11, 20, 20), 0);
  EXPECT_NEAR(nu[0], 0.0, 1e-10);
  EXPECT_NEAR(nu[1], 0.5, 1e-10);
  EXPECT_NEAR(S.single[0].beta, 2.0, 1e-9);
  EXPECT_NEAR(S.single[1].beta, 7.5, 1e-9);
}

// The generated humanoid (~35 kg, 10 mesh links, ±2.5 rad stops) 1 cm above the plane: it lands
// on its soles, stands, topples and lies on its joints' stops and its own limbs.
TEST(TreeResting, LyingHumanoidComesToRestAndSleeps) {
  const std::string dir = test::meshFolder("humanoid_resting");
  auto scene = scene::loadUrdfString(test::humanoidUrdf(dir), "robot", scene::SceneOptions());
  ASSERT_TRUE(scene.ok()) << scene.error();
  WorldConfig config;
  config.dt = 1e-3;
  config.threads = 1;
  config.ground_plane = GroundPlane{-0.70, {}};
  auto made = World::create(std::move(scene.value()), config);
  ASSERT_TRUE(made.ok()) << made.error();
  World& w = *made.value();
  const auto book = [&] {
    const MomentumReport t = w.momentum().back();
    return t.kinetic_energy + t.potential_energy + t.dissipated_energy;
  };
  const double E0 = book();
  double asleep_at = -1, deepest_lying = 0;
  for (int k = 0; k < 8000; ++k) {
    w.step();
    if (asleep_at < 0 && w.data().trees[0].asleep) asleep_at = w.time();
    // From the first second on the ground (it lies from ~3.5 s), no contact sinks beyond the
    // slop the position correction leaves (5e-5 m) by more than one step's gravity presses
    // in before the next correction (g h² ≈ 1e-5 m): a limb pressed by the robot's own weight
    // stays where the correction put it (measured: 4.2e-5 to 5.0e-5 m).
    if (w.time() > 4.0)
      for (const ContactReport& c : w.contacts()) deepest_lying = std::max(deepest_lying, c.depth);
    // The book: no input, so kinetic + potential + dissipated stays what it was; the solve's
    // impulses are exact to round-off and the tree integrator's own error is ~1e-14 J here
    // (measured: 3e-14 J of ~240 J potential); 1e-9 J would show any leak.
    ASSERT_NEAR(book(), E0, 1e-9) << "t " << w.time();
  }
  EXPECT_EQ(w.treeFaultCount(), 0u);
  // It lies: the pelvis came down from its standing height (the plane is 0.70 m below it).
  EXPECT_LT(w.getBodyState("pelvis").value().pose_root.translation().z(), -0.4);
  // Asleep within a second of lying down (measured: 4.0-4.5 s; Gauss–Seidel's 30 sweeps left it
  // creeping at 3e-3 m/s and sinking 0.4 mm/s, never asleep): every link still below
  // kSleepSpeed (1e-6 m/s) for kSleepTime (0.2 s) needs the contacts solved to well below it.
  EXPECT_GT(asleep_at, 0.0);
  EXPECT_LT(asleep_at, 5.0);
  EXPECT_LE(deepest_lying, 5e-5 + 1e-5);
  // The stops held: ±2.5 rad, with the solver's tolerance on a rate times h (1e-12 rad).
  for (const JointStateReport& j : w.jointStates()) EXPECT_LE(std::abs(j.position), 2.5 + 1e-9);
}

}  // namespace tree_resting_test
}  // namespace sim
}  // namespace cga_rigid_sim
