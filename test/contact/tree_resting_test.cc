// A resting tree's contacts solved by Newton's method (doc/contacts.md#resting-trees,
// src/contact/contact_resting_tree.h): the solver itself against a problem with a known answer,
// and a humanoid-like robot of this repository's own (test/common/real_like_robots.h) that
// falls onto the ground plane, lies there still, sleeps, and keeps its energy book.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>
#include <vector>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/world.h"
#include "common/real_like_robots.h"
#include "contact/contact_resting_tree.h"
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

// A contact's warm start on its friction pyramid's edges (pyramidEdges): from edges b (the
// truth), λ_n = Σ b, λ_t = μ (b0 − b1, b2 − b3) and the share b0 + b1 it must give b back, to
// the rounding of those sums (4e-16 λ_n each; 1e-14 λ_n asserted), and an edge that was 0
// exactly 0 (it starts inactive). Cases: all four loaded with the slack split unequally; one
// edge 0 with slack left on the other pair; sliding, one edge of each pair 0 (no slack); 0 by
// rounding only (an edge of 1e-17 λ_n). Without the share (NaN), or with one that does not fit,
// the slack is shared equally: s_1 − |λ_t1|/μ = s_2 − |λ_t2|/μ, and λ_n, λ_t are still given
// back. Friction outside the pyramid is scaled onto its rim: λ_t's direction kept, its edges'
// total μ λ_n.
TEST(TreeResting, PyramidEdgesGiveBackTheEdgesTheyWereMadeFrom) {
  const double mu = 0.7;
  const std::vector<Eigen::Vector4d> cases = {
      {0.3, 0.1, 0.45, 0.05}, {0.3, 0.0, 0.2, 0.15}, {0.4, 0.0, 0.0, 0.25}, {0.5, 1e-17, 0.2, 0.2}};
  for (const Eigen::Vector4d& b : cases) {
    const double ln = b.sum();
    const Eigen::Vector2d lt(mu * (b[0] - b[1]), mu * (b[2] - b[3]));
    const Eigen::Vector4d e = pyramidEdges(ln, lt, mu, b[0] + b[1]);
    for (int k = 0; k < 4; ++k) {
      if (b[k] < 1e-12 * ln)
        EXPECT_EQ(e[k], 0.0) << b.transpose();
      else
        EXPECT_NEAR(e[k], b[k], 1e-14 * ln) << b.transpose();
    }
    for (const double share : {std::nan(""), -1.0, ln + 1.0}) {
      const Eigen::Vector4d h = pyramidEdges(ln, lt, mu, share);
      EXPECT_NEAR(h.sum(), ln, 1e-14 * ln);
      EXPECT_NEAR(mu * (h[0] - h[1]), lt[0], 1e-14 * ln);
      EXPECT_NEAR(mu * (h[2] - h[3]), lt[1], 1e-14 * ln);
      EXPECT_NEAR(h[0] + h[1] - std::abs(lt[0]) / mu, h[2] + h[3] - std::abs(lt[1]) / mu,
                  1e-14 * ln);
    }
  }
  // λ_t twice the pyramid's rim: scaled by one half.
  const Eigen::Vector4d e = pyramidEdges(1.0, Eigen::Vector2d(0.6 * mu, -1.4 * mu), mu, 0.5);
  EXPECT_NEAR(e.sum(), 1.0, 1e-15);
  EXPECT_NEAR(mu * (e[0] - e[1]), 0.3 * mu, 1e-15);
  EXPECT_NEAR(mu * (e[2] - e[3]), -0.7 * mu, 1e-15);
}

// The Hessian's factor kept by rank-one updates as rows enter and leave the active set
// (TreeNewton::max_rank_updates) against the same solve factoring every Hessian whole, on a
// problem on a tree's sparsity (`parent`, each coordinate's): M = Lᵀ L with L nonzero on a
// coordinate's ancestors only, rows on paths from the `leaves` to the base and across two
// branches (a contact between two links, `across`), and `stops`, their targets spread so that
// the Newton steps move rows in and out a few at a time, solved cold over several augmented
// Lagrangian rounds. Both must end at the same minimiser: the updates' factor differs from a
// whole one by round-off amplified by the Hessian's condition (D = 1e3 on rows of norm ~1–10
// against M's eigenvalues ~0.1–10: ≲ 1e6) times ~1e-16 per update, and both solves stop at the
// same tolerance, 1e-12 m/s on every row; 1e-10 of the answer's scale bounds both. The updated
// solve must have updated (a test of the path, not only of its answer) and factored fewer
// Hessians whole.
void expectUpdatesReachTheWholeFactorsMinimiser(const std::vector<int>& parent,
                                                const std::vector<int>& leaves,
                                                const std::vector<std::pair<int, int>>& across,
                                                const std::vector<TreeNewton::Single>& stops,
                                                unsigned seed) {
  const int n = static_cast<int>(parent.size());
  unsigned state = seed;  // deterministic values in [−1, 1]
  const auto value = [&] {
    state = state * 1103515245u + 12345u;
    return static_cast<double>((state >> 8) & 0xffff) / 32767.5 - 1.0;
  };
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < n; ++k) {
    L(k, k) = 1.0 + 0.5 * std::abs(value());
    int depth = 0;
    for (int j = parent[k]; j >= 0; j = parent[j]) ++depth;
    // Off the diagonal ~0.3 / √depth, so that a deep chain's M stays well conditioned.
    for (int j = parent[k]; j >= 0; j = parent[j]) L(k, j) = 0.3 * value() / std::sqrt(depth);
  }
  const Eigen::MatrixXd M = L.transpose() * L;
  const auto pathRow = [&](int leaf) {
    Eigen::RowVectorXd g = Eigen::RowVectorXd::Zero(n);
    for (int k = leaf; k >= 0; k = parent[k]) g[k] = value();
    return g;
  };
  const int m = static_cast<int>(leaves.size() + across.size());
  const int s = static_cast<int>(stops.size());
  Eigen::MatrixXd G(m, n);
  int i = 0;
  for (const int leaf : leaves) G.row(i++) = pathRow(leaf);
  for (const auto& [a, b] : across) G.row(i++) = pathRow(a) - pathRow(b);
  Eigen::VectorXd r(m), nu_f(n);
  for (int k = 0; k < m; ++k) r[k] = 0.5 * value();
  for (int k = 0; k < n; ++k) nu_f[k] = value();
  struct Result {
    Eigen::VectorXd nu, beta;
    long factorisations, updates;
  };
  const auto solve = [&](int max_rank_updates) {
    TreeNewton N;
    N.max_rank_updates = max_rank_updates;
    N.resize(m, s, n);
    N.g.topRows(m) = G;
    N.r.head(m) = r;
    N.D.head(m).setConstant(1e3);
    N.beta.head(m).setZero();
    for (int j = 0; j < s; ++j) N.single[j] = stops[j];
    Eigen::VectorXd nu = nu_f;
    EXPECT_GT(N.solve(M, nu_f, nu, 1e-12, 30, 20), 0);
    Eigen::VectorXd beta(m + s);
    beta.head(m) = N.beta.head(m);
    for (int j = 0; j < s; ++j) beta[m + j] = N.single[j].beta;
    return Result{nu, beta, N.factorisations, N.rank_updates};
  };
  const Result whole = solve(0), updated = solve(8);
  EXPECT_EQ(whole.updates, 0);
  EXPECT_GT(updated.updates, 0);
  EXPECT_LT(updated.factorisations, whole.factorisations);
  const double nu_scale = whole.nu.cwiseAbs().maxCoeff(),
               beta_scale = whole.beta.cwiseAbs().maxCoeff();
  ASSERT_GT(beta_scale, 0.0);
  EXPECT_LE((updated.nu - whole.nu).cwiseAbs().maxCoeff(), 1e-10 * nu_scale);
  EXPECT_LE((updated.beta - whole.beta).cwiseAbs().maxCoeff(), 1e-10 * beta_scale);
  // Every stop acts: the single rows' updates are exercised too.
  for (int j = 0; j < s; ++j) EXPECT_GT(whole.beta[m + j], 0.0) << "stop " << j;
}

// Twelve coordinates, a base chain 0-5 and branches 6-7-8, 7-11 and 9-10 off 5: sixteen rows
// on paths, two across branches, four stops (measured: ν 7e-16, β 2e-14 relative; one whole
// factor and 21 updates against 8 whole factors).
TEST(TreeResting, NewtonRankUpdatesReachTheWholeFactorsMinimiser) {
  std::vector<int> leaves;
  for (int i = 0; i < 16; ++i) leaves.push_back(std::vector<int>{8, 11, 10, 6, 3, 7}[i % 6]);
  expectUpdatesReachTheWholeFactorsMinimiser({-1, 0, 1, 2, 3, 4, 5, 6, 7, 5, 9, 7}, leaves,
                                             {{8, 10}, {11, 9}},
                                             {{10, -1.0, -0.5, 1e3, 0.0},  // ν_10 ≤ 0.5
                                              {4, 1.0, -0.1, 1e3, 0.0},    // ν_4 ≥ −0.1
                                              {0, 1.0, 0.3, 1e3, 0.0},     // ν_0 ≥ 0.3
                                              {11, -1.0, 0.0, 1e3, 0.0}},  // ν_11 ≤ 0
                                             2468u);
}

// The same past the size up to which the Hessian is built over each row's nonzeros (256
// coordinates): a chain of 260 with a branch of 10 off coordinate 200, whose rows and factor
// are dense, updated by the same code with every row scanned whole (measured: ν 3e-16, β 3e-12
// relative; one whole factor and 7 updates against 4 whole factors).
TEST(TreeResting, NewtonRankUpdatesOnALargeTreeReachTheWholeFactorsMinimiser) {
  std::vector<int> parent(270);
  for (int k = 0; k < 270; ++k) parent[k] = k == 260 ? 200 : k - 1;
  std::vector<int> leaves;
  for (int i = 0; i < 40; ++i)
    leaves.push_back(std::vector<int>{259, 269, 230, 150, 265, 100, 262, 245}[i % 8]);
  expectUpdatesReachTheWholeFactorsMinimiser(
      parent, leaves, {{259, 269}}, {{255, 1.0, 0.2, 1e3, 0.0}, {268, -1.0, 0.1, 1e3, 0.0}}, 1357u);
}

// A downdate that would cancel its pivot away: one coordinate (M = 1) and one row ν ≥ −1 so
// stiff (D = 1e14) that removing it leaves 1/(1 + D) of the pivot's square, past the updates'
// bound (1e-9). Warm-started with an impulse, the row enters the first factor and leaves at the
// first Newton step (ν = 0 is the minimiser, where it is slack): that downdate must be refused
// and the Hessian factored whole again, and the answer is exact, ν = 0 and no impulse.
TEST(TreeResting, NewtonRefusesADowndateThatCancelsItsPivot) {
  TreeNewton N;
  N.resize(1, 0, 1);
  N.g(0, 0) = 1.0;
  N.r[0] = -1.0;
  N.D[0] = 1e14;
  N.beta[0] = 0.5e14;  // its target shifted to −1 + β / D = −0.5
  const Eigen::MatrixXd M = Eigen::MatrixXd::Identity(1, 1);
  const Eigen::VectorXd nu_f = Eigen::VectorXd::Zero(1);
  Eigen::VectorXd nu = nu_f;
  ASSERT_GT(N.solve(M, nu_f, nu, 1e-11, 20, 20), 0);
  EXPECT_EQ(nu[0], 0.0);
  EXPECT_EQ(N.beta[0], 0.0);
  EXPECT_EQ(N.rank_updates, 1);
  EXPECT_EQ(N.factorisations, 2);  // the warm start's, and the one that replaced the downdate
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
  double asleep_at = -1, deepest_lying = 0, free_steps_error = 0, before = E0;
  for (int k = 0; k < 8000; ++k) {
    w.step();
    // A step without a contact is the tree integrator's alone: what it changes in the book is
    // the midpoint's own energy error (second order), not the contacts'.
    if (w.contacts().empty()) free_steps_error += book() - before;
    before = book();
    if (asleep_at < 0 && w.data().trees[0].asleep) asleep_at = w.time();
    // From the first second on the ground (it lies from ~3.5 s), no contact sinks beyond the
    // slop the position correction leaves (5e-5 m) by more than one step's gravity presses
    // in before the next correction (g h² ≈ 1e-5 m): a limb pressed by the robot's own weight
    // stays where the correction put it (measured: 4.2e-5 to 5.0e-5 m).
    if (w.time() > 4.0)
      for (const ContactReport& c : w.contacts()) deepest_lying = std::max(deepest_lying, c.depth);
    // The book: no input, so kinetic + potential + dissipated stays what it was, but for the
    // midpoint's own error in the steps without contacts; in contact steps the solve's
    // impulses are exact to round-off (measured: 3e-14 J of ~240 J potential); 1e-9 J would
    // show any leak.
    ASSERT_NEAR(book() - free_steps_error, E0, 1e-9) << "t " << w.time();
  }
  // The steps without contacts: a moment of the topple with every foot and limb off the plane
  // and the limbs swinging at a few rad/s (measured: one step, 2.1e-7 J of 36 J kinetic).
  EXPECT_LE(std::abs(free_steps_error), 1e-6);
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
