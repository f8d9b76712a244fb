// The midpoint's factor of a tree's mass matrix on its sparsity (src/tree/tree_factor.h) against
// the equations it solves: M x = b on random trees, fixed and floating, with and without a
// diagonal added (the iteration's M + ½hC has M's sparsity).
#include "tree/tree_factor.h"

#include <gtest/gtest.h>

#include <random>

#include "common/random_trees.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace tree_factor_test {

using Eigen::MatrixXd;
using Eigen::VectorXd;

// A solve is backward stable: |M x − b| ≤ c ε |M| |x| with c a small multiple of n; 1e-13 is
// c ≈ 450 for n ≤ 18, generous, and a wrong parent (a coupling left out of the factor) leaves
// O(|M| |x|).
TEST(TreeCholesky, SolvesTheMassMatrixOfRandomTreesOnItsSparsity) {
  std::mt19937 rng(2029);
  for (const bool floating : {false, true}) {
    for (const int n : {1, 2, 7, 12}) {
      for (int trial = 0; trial < 5; ++trial) {
        const ArticulatedBody tree = testing::randomTree(rng, n, floating, 0.7);
        TreeState state;
        state.q = VectorXd::Random(n) * 3.0;
        state.v = VectorXd::Zero(n);  // (M depends on the poses alone)
        if (floating)
          state.M_W0 = cga::Motor::fromPose(Eigen::Quaterniond::UnitRandom(),
                                            Eigen::Vector3d::Random(), 0.7);
        TreeKinematics kin;
        treeKinematics(tree, state, kin);
        MatrixXd M;
        massMatrix(tree, kin, M);
        const std::vector<int> parent = tree_math::coordinateParents(tree);
        ASSERT_EQ(static_cast<int>(parent.size()), M.rows());
        for (const double damping : {0.0, 0.05}) {
          MatrixXd A = M;
          A.diagonal().tail(n).array() += damping;
          tree_math::TreeCholesky factor;
          factor.setParents(parent);
          ASSERT_TRUE(factor.sparse());
          factor.compute(A);
          const VectorXd b = VectorXd::Random(A.rows());
          VectorXd x = b;
          factor.solveInPlace(x);
          const double residual = (A * x - b).cwiseAbs().maxCoeff();
          EXPECT_LE(residual, 1e-13 * A.cwiseAbs().maxCoeff() * x.cwiseAbs().maxCoeff())
              << (floating ? "floating, " : "fixed, ") << n << " joints";
        }
      }
    }
  }
}

}  // namespace tree_factor_test
}  // namespace dynamics
}  // namespace cga_rigid_sim
