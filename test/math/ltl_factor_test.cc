// math::LtlFactor against a second method: Eigen's dense LLT of the same matrix, on random
// trees of coordinates (a parent's index below its child's) whose matrices have the trees'
// sparsity; and its refusal of a matrix that is not positive definite.
#include "cga_rigid_sim/math/ltl_factor.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>
#include <vector>

namespace cga_rigid_sim {
namespace math {
namespace ltl_factor_test {

// A random tree of n coordinates: each one's parent drawn from those before it, or none.
std::vector<int> randomParents(std::mt19937& rng, int n) {
  std::vector<int> parent(n, -1);
  for (int i = 1; i < n; ++i) parent[i] = std::uniform_int_distribution<int>(-1, i - 1)(rng);
  return parent;
}

// Lᵀ L for a random L with the tree's sparsity and a diagonal away from zero: symmetric,
// positive definite, zero off the pairs of a coordinate and its ancestors.
Eigen::MatrixXd randomTreeMatrix(std::mt19937& rng, const std::vector<int>& parent) {
  const int n = static_cast<int>(parent.size());
  std::normal_distribution<double> normal;
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    L(i, i) = 0.5 + std::abs(normal(rng));
    for (int j = parent[i]; j >= 0; j = parent[j]) L(i, j) = 0.5 * normal(rng);
  }
  return L.transpose() * L;
}

TEST(LtlFactor, SolvesAsTheDenseFactorOnRandomTrees) {
  std::mt19937 rng(7);
  LtlFactor factor;  // one object across trees: setParents rebuilds its paths
  for (int trial = 0; trial < 200; ++trial) {
    const int n = std::uniform_int_distribution<int>(1, 40)(rng);
    const std::vector<int> parent = randomParents(rng, n);
    const Eigen::MatrixXd M = randomTreeMatrix(rng, parent);
    factor.setParents(parent);
    ASSERT_TRUE(factor.compute(M, true));
    const Eigen::VectorXd b = Eigen::VectorXd::Random(n);
    const Eigen::VectorXd x_ref = M.llt().solve(b);
    Eigen::VectorXd x = b;
    factor.solveInPlace(x.data());
    // Both solve the same system with M's condition number below ~1e4 here: the two answers
    // agree to that times a few ulps of |x|.
    EXPECT_LE((x - x_ref).cwiseAbs().maxCoeff(), 1e-10 * (1.0 + x_ref.cwiseAbs().maxCoeff()))
        << "trial " << trial << ", n = " << n;
    // Three columns at once, by the coordinate steps, as the contact solve uses them.
    Eigen::Matrix<double, Eigen::Dynamic, 3> Y =
        Eigen::Matrix<double, Eigen::Dynamic, 3>::Random(n, 3);
    const Eigen::Matrix<double, Eigen::Dynamic, 3> Y_ref = M.llt().solve(Y);
    for (int i = n - 1; i >= 0; --i) factor.eliminate<3>(Y.data(), 1, Y.rows(), i);
    for (int i = 0; i < n; ++i) factor.finish<3>(Y.data(), 1, Y.rows(), i);
    EXPECT_LE((Y - Y_ref).cwiseAbs().maxCoeff(), 1e-10 * (1.0 + Y_ref.cwiseAbs().maxCoeff()))
        << "trial " << trial;
  }
}

// A unit vector's solve skips the coordinates off its path in the first half, where a full
// solve only subtracts zeros: the same bits.
TEST(LtlFactor, AUnitVectorsSolveIsTheFullSolveToTheBit) {
  std::mt19937 rng(3);
  LtlFactor factor;
  for (int trial = 0; trial < 50; ++trial) {
    const int n = std::uniform_int_distribution<int>(1, 40)(rng);
    const std::vector<int> parent = randomParents(rng, n);
    factor.setParents(parent);
    ASSERT_TRUE(factor.compute(randomTreeMatrix(rng, parent), true));
    for (int k = 0; k < n; ++k) {
      Eigen::VectorXd full = Eigen::VectorXd::Unit(n, k), unit = Eigen::VectorXd::Constant(n, 7.0);
      factor.solveInPlace(full.data());
      factor.solveUnit(k, unit.data());
      for (int i = 0; i < n; ++i) ASSERT_EQ(unit[i], full[i]) << "n " << n << " k " << k;
    }
  }
}

TEST(LtlFactor, RefusesAMatrixThatIsNotPositiveDefinite) {
  std::mt19937 rng(11);
  const std::vector<int> parent = randomParents(rng, 12);
  Eigen::MatrixXd M = randomTreeMatrix(rng, parent);
  LtlFactor factor;
  factor.setParents(parent);
  ASSERT_TRUE(factor.compute(M, true));
  // A negative pivot at the root: the last one eliminated (leaves first) is the root's.
  M(0, 0) = -1.0;
  EXPECT_FALSE(factor.compute(M, true));
  // Without the check the factor holds NaN and so does a solve with it.
  EXPECT_TRUE(factor.compute(M, false));
  Eigen::VectorXd x = Eigen::VectorXd::Ones(12);
  factor.solveInPlace(x.data());
  EXPECT_FALSE(x.allFinite());
}

}  // namespace ltl_factor_test
}  // namespace math
}  // namespace cga_rigid_sim
