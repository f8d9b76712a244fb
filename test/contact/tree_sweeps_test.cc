// The velocity sweeps of an island with a tree (doc/contacts.md#trees, SolverWork::TreeSweeps):
// they move the tree's ν in its factor's coordinates, ν = ν₀ + L⁻¹ z, each contact and each joint
// stop over its path to the base alone, and make ν once after the sweeps. Whatever the sweeps
// leave unconverged, the ν they hand back must be the one their impulses give:
// ν = ν₀ + M⁻¹ (Σ Jᵀ P + Σ e_k y), with M⁻¹ from Eigen's dense LLT of M, not from the factor; and
// the sparse factor's coordinates must give the sweeps of the dense one (mimic joints' path).
#include <gtest/gtest.h>

#include <random>

#include "common/random_trees.h"
#include "contact/contact_solver.h"

namespace cga_rigid_sim {
namespace sim {
namespace tree_sweeps_test {

constexpr double kLambda = 1.0;
constexpr int kJoints = 14;

struct Problem {
  std::vector<SolverBody> bodies;
  std::vector<SolverTree> trees;
  std::vector<Contact> contacts;
  std::vector<int> slot_a, slot_b;
};

// A random floating tree at a random pose with random rates of ~1 rad/s or m/s, eight contacts on
// random links against the ground, each approaching it, and four joints with stops within
// ±0.1 mm of their position (so that their rates meet them within the step).
// `sparse`: the factor on the tree's sparsity, else dense (as with mimic joints).
Problem makeProblem(std::mt19937& rng, bool sparse) {
  Problem p;
  const dynamics::ArticulatedBody tree = testing::randomTree(rng, kJoints, true, kLambda);
  dynamics::TreeState s;
  s.M_W0 = testing::randomMotor(rng, 1.0, kLambda);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  s.q = Eigen::VectorXd::NullaryExpr(tree.jointCount(), [&] { return 2.0 * unit(rng); });
  s.v.setZero(tree.jointCount());
  dynamics::TreeKinematics kin;
  dynamics::treeKinematics(tree, s, kin);
  SolverTree t;
  dynamics::massMatrix(tree, kin, t.M);
  const int n = tree.velocityCount();
  t.floating = true;
  // Per coordinate a random screw: the solver reads J from it and needs no more of it.
  t.twist = Eigen::Matrix<double, 6, Eigen::Dynamic>::NullaryExpr(6, n, [&] { return unit(rng); });
  t.parent.resize(tree.bodyCount());
  t.parent[0] = -1;
  for (int b = 1; b < tree.bodyCount(); ++b) t.parent[b] = tree.parentOf(b);
  for (int k = 0; k < tree.jointCount(); ++k) {
    t.column.push_back(tree.velocityIndex(k));
    t.multiplier.push_back(1.0);
  }
  if (sparse) {
    t.coordinate_parent.resize(n);
    for (int j = 0; j < 6; ++j) t.coordinate_parent[j] = j - 1;
    for (int k = 0; k < tree.jointCount(); ++k) {
      const int parent = tree.parentOf(k + 1);
      t.coordinate_parent[tree.velocityIndex(k)] = parent == 0 ? 5 : tree.velocityIndex(parent - 1);
    }
  }
  EXPECT_TRUE(t.factor.compute(t.M, t.coordinate_parent));
  t.nu = Eigen::VectorXd::NullaryExpr(n, [&] { return unit(rng); });
  for (int k = 0; k < 4; ++k) {
    SolverTree::LimitRow r;
    r.index = tree.velocityIndex(3 * k + 1);
    r.q = s.q[3 * k + 1];
    r.lower = r.q - 1e-4;
    r.upper = r.q + 1e-4;
    t.limits.push_back(r);
  }
  p.trees.push_back(t);
  for (int b = 0; b < tree.bodyCount(); ++b) {
    SolverBody body;
    body.tree = 0;
    body.tree_body = b;
    body.x = kin.M_W[b].translation(kLambda);
    p.bodies.push_back(body);
  }
  for (int k = 0; k < 8; ++k) {
    Contact c;
    const int b = std::uniform_int_distribution<int>(0, tree.bodyCount() - 1)(rng);
    c.point_W = p.bodies[b].x + testing::randomVector(rng, 0.2);
    c.depth = 1e-3;
    c.mu = 0.5;
    p.contacts.push_back(c);
    p.slot_a.push_back(b);
    p.slot_b.push_back(-1);
  }
  // Each contact's normal against its point's velocity, so that every one approaches (the
  // screws are random: "down" means nothing to them).
  std::vector<ContactRow> rows;
  prepareRows(p.contacts, p.bodies, p.trees, p.slot_a, p.slot_b, rows);
  for (std::size_t k = 0; k < rows.size(); ++k)
    p.contacts[k].normal_W = -(rows[k].ja * p.trees[0].nu).normalized();
  return p;
}

// The swept solve (Newton's resting solve off), 30 sweeps at most as for any tree's island.
std::vector<ContactRow> solve(Problem& p) {
  SolverSettings st;
  st.resting_tree_speed = 0.0;
  std::vector<ContactRow> rows;
  prepareRows(p.contacts, p.bodies, p.trees, p.slot_a, p.slot_b, rows);
  SolverWork work;
  solveVelocities(st, p.bodies, p.trees, rows, work);
  return rows;
}

class TreeSweepsTest : public ::testing::TestWithParam<bool> {};

// ν − ν₀ against M⁻¹ times the generalized impulse of the rows' and the stops' accumulated
// impulses. Both are sums of the same impulses through M⁻¹ (the sweeps' through the factor, one
// by one; the truth's through Eigen's LLT, once), backward stable, so they differ by a few
// cond(M) ε relative: measured ≤ 1.2e-14 of |ν − ν₀| over these 20 problems, asserted 1e-12; a
// lost impulse or a stop's column off its path is O(1) (0.6–0.8 with coordinate 0 left out).
TEST_P(TreeSweepsTest, VelocityIsTheOneTheImpulsesGive) {
  std::mt19937 rng(GetParam() ? 5 : 11);
  for (int trial = 0; trial < 10; ++trial) {
    Problem p = makeProblem(rng, GetParam());
    const Eigen::VectorXd nu0 = p.trees[0].nu;
    const std::vector<ContactRow> rows = solve(p);
    const SolverTree& t = p.trees[0];
    Eigen::VectorXd f = Eigen::VectorXd::Zero(nu0.size());
    int pushing = 0, stopped = 0;
    for (const ContactRow& c : rows) {
      ASSERT_EQ(c.ta, 0);
      f += c.ja.transpose() * (c.lambda_n * c.n + c.lambda_t.x() * c.t1 + c.lambda_t.y() * c.t2);
      pushing += c.lambda_n > 0;
    }
    for (const SolverTree::LimitRow& r : t.limits) {
      f[r.index] += r.y_lower + r.y_upper;
      stopped += r.y_lower != 0.0 || r.y_upper != 0.0;
    }
    EXPECT_GT(pushing, 0);  // the problem exercises both kinds of rows
    EXPECT_GT(stopped, 0);
    const Eigen::VectorXd expected = t.M.llt().solve(f);
    const Eigen::VectorXd moved = t.nu - nu0;
    EXPECT_LE((moved - expected).cwiseAbs().maxCoeff(), 1e-12 * moved.cwiseAbs().maxCoeff())
        << "trial " << trial;
  }
}

// The sparse factor's sweeps against the dense factor's on the same problems: the same updates
// in a different basis of z (L⁻ᵀ of M = Lᵀ L against L⁻¹ of M = L Lᵀ), so the same ν up to
// round-off, which the sweeps' projections do not amplify: measured ≤ 2.9e-15 of |ν|, asserted
// 1e-12.
TEST(TreeSweeps, SparseCoordinatesSweepAsTheDenseFactor) {
  for (int trial = 0; trial < 10; ++trial) {
    std::mt19937 rng_sparse(100 + trial), rng_dense(100 + trial);
    Problem sparse = makeProblem(rng_sparse, true), dense = makeProblem(rng_dense, false);
    solve(sparse);
    solve(dense);
    const Eigen::VectorXd& a = sparse.trees[0].nu;
    const Eigen::VectorXd& b = dense.trees[0].nu;
    EXPECT_LE((a - b).cwiseAbs().maxCoeff(), 1e-12 * a.cwiseAbs().maxCoeff()) << "trial " << trial;
  }
}

INSTANTIATE_TEST_SUITE_P(SparseAndDense, TreeSweepsTest, ::testing::Bool());

}  // namespace tree_sweeps_test
}  // namespace sim
}  // namespace cga_rigid_sim
