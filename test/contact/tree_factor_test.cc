// The contact solve's factor of a tree's mass matrix (src/contact/contact_tree_factor.h):
// Featherstone's LTL factorisation on the tree's sparsity against Eigen's dense LLT of the same
// M(q), on random branched trees (floating and fixed), for the full solve, the half solve that
// gives a contact's Delassus block J M⁻¹ Jᵀ from the coordinates on its link's path alone, and
// its completion to M⁻¹ Jᵀ.
#include <gtest/gtest.h>

#include <random>

#include "common/random_trees.h"
#include "contact/contact_tree_factor.h"

namespace cga_rigid_sim {
namespace sim {
namespace tree_factor_test {

constexpr double kLambda = 1.0;

// The coordinates' parents as the contact solve makes them (contact_trees.cc): the floating
// base's six a chain, a joint's the coordinate of its parent link's joint or the base's last.
std::vector<int> coordinateParents(const dynamics::ArticulatedBody& tree) {
  const int base = tree.floating() ? 6 : 0;
  std::vector<int> parent(tree.velocityCount());
  for (int j = 0; j < base; ++j) parent[j] = j - 1;
  for (int k = 0; k < tree.jointCount(); ++k) {
    const int p = tree.parentOf(k + 1);
    parent[tree.velocityIndex(k)] = p == 0 ? base - 1 : tree.velocityIndex(p - 1);
  }
  return parent;
}

// A random pose's M(q).
Eigen::MatrixXd massAtRandomPose(std::mt19937& rng, const dynamics::ArticulatedBody& tree) {
  dynamics::TreeState s;
  s.M_W0 = testing::randomMotor(rng, 1.0, kLambda);
  s.q = Eigen::VectorXd::NullaryExpr(
      tree.jointCount(), [&] { return std::uniform_real_distribution<double>(-2.0, 2.0)(rng); });
  s.v.setZero(tree.jointCount());
  dynamics::TreeKinematics kin;
  dynamics::treeKinematics(tree, s, kin);
  Eigen::MatrixXd M;
  dynamics::massMatrix(tree, kin, M);
  return M;
}

// A random point Jacobian's transpose (n × 3) with nonzeros only on the path from `leaf` to the
// root (a point on the link of that joint), as pointJacobian makes them.
TreeFactor::Columns pathColumns(std::mt19937& rng, const std::vector<int>& parent, int leaf) {
  TreeFactor::Columns J = TreeFactor::Columns::Zero(parent.size(), 3);
  for (int i = leaf; i >= 0; i = parent[i]) J.row(i) = testing::randomVector(rng, 1.0).transpose();
  return J;
}

// Relative to the answer's largest entry: both factorisations are backward stable, so they
// differ by about cond(M) · ε (ε = 2.2e-16); 1e-10 allows cond(M) up to ~1e5, far above that of
// these trees of boxes of 0.2–1.5 kg and m, and far below any error of a wrong factor (O(1)).
constexpr double kRelative = 1e-10;

class TreeFactorTest : public ::testing::TestWithParam<bool> {};

TEST_P(TreeFactorTest, SparseSolvesMatchTheDenseFactor) {
  std::mt19937 rng(GetParam() ? 17 : 29);
  for (int trial = 0; trial < 20; ++trial) {
    const dynamics::ArticulatedBody tree = testing::randomTree(rng, 14, GetParam(), kLambda);
    const Eigen::MatrixXd M = massAtRandomPose(rng, tree);
    const std::vector<int> parent = coordinateParents(tree);
    TreeFactor sparse, dense;
    ASSERT_TRUE(sparse.compute(M, parent));
    ASSERT_TRUE(dense.compute(M, {}));
    ASSERT_TRUE(sparse.sparse());
    const Eigen::LLT<Eigen::MatrixXd> llt(M);

    // x ← M⁻¹ x.
    Eigen::VectorXd b = Eigen::VectorXd::NullaryExpr(
        M.rows(), [&] { return std::uniform_real_distribution<double>(-1.0, 1.0)(rng); });
    const Eigen::VectorXd x_ref = llt.solve(b);
    Eigen::VectorXd x = b;
    sparse.solveInPlace(x);
    EXPECT_LE((x - x_ref).cwiseAbs().maxCoeff(), kRelative * x_ref.cwiseAbs().maxCoeff());

    // A contact between two links (two paths) and one on a single link: Yᵀ Y = J M⁻¹ Jᵀ, Y
    // zero off the paths, and its completion M⁻¹ Jᵀ; the dense stand-in gives the same.
    const int n = static_cast<int>(M.rows());
    const int leaf_a = std::uniform_int_distribution<int>(0, n - 1)(rng);
    const int leaf_b = std::uniform_int_distribution<int>(0, n - 1)(rng);
    for (const int second : {-1, leaf_b}) {
      TreeFactor::Columns J = pathColumns(rng, parent, leaf_a);
      if (second >= 0) J -= pathColumns(rng, parent, second);
      const TreeFactor::Columns W_ref = llt.solve(J);
      const Eigen::Matrix3d K_ref = J.transpose() * W_ref;
      for (const TreeFactor* f : {&sparse, &dense}) {
        TreeFactor::Columns Y = J;
        f->halfSolve(Y, leaf_a, second);
        const Eigen::Matrix3d K = Y.transpose() * Y;
        EXPECT_LE((K - K_ref).cwiseAbs().maxCoeff(), kRelative * K_ref.cwiseAbs().maxCoeff());
        for (int i = 0; f == &sparse && i < n; ++i) {
          bool on_path = false;
          for (int l : {leaf_a, second})
            for (int j = l; j >= 0 && !on_path; j = parent[j]) on_path = j == i;
          if (!on_path) {
            EXPECT_TRUE(Y.row(i).isZero(0.0)) << "coordinate " << i;
          }
        }
        // One column's second half (the sweeps' change of ν) is the first of the three's: the
        // same operations on the sparse factor, Eigen's triangular solves (blocked for three
        // columns) to round-off on the dense one.
        Eigen::VectorXd y0 = Y.col(0);
        f->finishSolve(Y);
        EXPECT_LE((Y - W_ref).cwiseAbs().maxCoeff(), kRelative * W_ref.cwiseAbs().maxCoeff());
        f->finishSolve(y0);
        const double w = Y.col(0).cwiseAbs().maxCoeff();
        EXPECT_LE((y0 - Y.col(0)).cwiseAbs().maxCoeff(), f == &sparse ? 0.0 : kRelative * w);
        TreeFactor::Columns W = J;
        f->solveInPlace(W);
        EXPECT_LE((W - W_ref).cwiseAbs().maxCoeff(), kRelative * W_ref.cwiseAbs().maxCoeff());
      }
    }
  }
}

// A matrix that is not positive definite is refused, sparse and dense.
TEST_P(TreeFactorTest, RefusesIndefiniteMatrices) {
  std::mt19937 rng(5);
  const dynamics::ArticulatedBody tree = testing::randomTree(rng, 6, GetParam(), kLambda);
  Eigen::MatrixXd M = massAtRandomPose(rng, tree);
  M(0, 0) = -1.0;
  TreeFactor f;
  EXPECT_FALSE(f.compute(M, coordinateParents(tree)));
  EXPECT_FALSE(f.ok());
  EXPECT_FALSE(f.compute(M, {}));
  M(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(f.compute(M, coordinateParents(tree)));
}

INSTANTIATE_TEST_SUITE_P(FloatingAndFixed, TreeFactorTest, ::testing::Bool());

}  // namespace tree_factor_test
}  // namespace sim
}  // namespace cga_rigid_sim
