// The joint rows' solve (src/tree/joint_rows.h) against the linear complementarity problem it
// solves: for limit rows the impulses y found by the sweeps equal the solution found by
// enumerating every active set (G positive definite: exactly one is feasible), a solve started
// from the impulses of the previous one with the same matrix (the midpoint's iterations) equals a
// solve from zero, and where friction and a limit share a coordinate at its stop (only their sum
// is unique) the split does not depend on where the sweeps started.
#include "tree/joint_rows.h"

#include <gtest/gtest.h>

#include <random>

#include "common/random_trees.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace joint_rows_test {

using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr double kH = 0.01;

// A fixed-base tree of n joints (only their indices, limits and friction matter to the rows).
ArticulatedBody treeWith(std::mt19937& rng, int n, const std::vector<int>& limited,
                         int friction_joint = -1, double friction = 0.0) {
  const ArticulatedBody random = testing::randomTree(rng, n, false, 1.0);
  std::vector<TreeJoint> joints = random.joints();
  for (int k : limited) {
    joints[k].lower = -0.5;
    joints[k].upper = 0.5;
  }
  if (friction_joint >= 0) joints[friction_joint].friction = friction;
  return ArticulatedBody(std::nullopt, joints, 1.0);
}

// A random symmetric positive definite K (the step's A⁻¹) with eigenvalues in [0.5, 2.5].
MatrixXd randomSpd(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  MatrixXd B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = u(rng);
  const Eigen::HouseholderQR<MatrixXd> qr(B);
  const MatrixXd Q = qr.householderQ();
  VectorXd eig(n);
  for (int i = 0; i < n; ++i) eig[i] = 1.5 + u(rng);
  return Q * eig.asDiagonal() * Q.transpose();
}

struct LimitRow {
  int index;
  bool lower;
  double target;
};

// The LCP of limit rows by enumeration: G y + w0 = w, lower rows y ≥ 0, w ≥ t, y (w − t) = 0
// (upper rows the signs reversed). With G positive definite exactly one active set is feasible;
// the one with the least violation is returned.
VectorXd bruteForce(const MatrixXd& G, const VectorXd& w0, const std::vector<LimitRow>& rows) {
  const int m = static_cast<int>(rows.size());
  VectorXd best;
  double best_violation = INFINITY;
  for (int set = 0; set < (1 << m); ++set) {
    std::vector<int> active;
    for (int r = 0; r < m; ++r)
      if (set & (1 << r)) active.push_back(r);
    VectorXd y = VectorXd::Zero(m);
    if (!active.empty()) {
      const int a = static_cast<int>(active.size());
      MatrixXd Gaa(a, a);
      VectorXd rhs(a);
      for (int i = 0; i < a; ++i) {
        rhs[i] = rows[active[i]].target - w0[active[i]];
        for (int j = 0; j < a; ++j) Gaa(i, j) = G(active[i], active[j]);
      }
      const VectorXd ya = Gaa.llt().solve(rhs);
      for (int i = 0; i < a; ++i) y[active[i]] = ya[i];
    }
    const VectorXd w = w0 + G * y;
    double violation = 0.0;
    for (int r = 0; r < m; ++r) {
      const double sign = rows[r].lower ? 1.0 : -1.0;
      violation = std::max(violation, -sign * y[r]);
      violation = std::max(violation, -sign * (w[r] - rows[r].target));
    }
    if (violation < best_violation) {
      best_violation = violation;
      best = y;
    }
  }
  return best;
}

// Positions and rates with three limited joints each at or near a limit (inside or just past
// it) and moving into it, so that each has a row; the other rates random.
void pressIntoLimits(std::mt19937& rng, const std::vector<int>& limited, VectorXd& q, VectorXd& nu,
                     std::vector<LimitRow>& rows) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = static_cast<int>(q.size());
  for (int k = 0; k < n; ++k) {
    q[k] = 0.3 * u(rng);
    nu[k] = 2.0 * u(rng);
  }
  rows.clear();
  for (int k : limited) {
    const bool lower = u(rng) < 0.0;
    const double limit = lower ? -0.5 : 0.5, sign = lower ? 1.0 : -1.0;
    q[k] = limit + sign * 0.002 * u(rng);            // within 2 mm (rad) of it, either side
    nu[k] = -sign * (0.5 + 1.5 * std::abs(u(rng)));  // into it: it is passed within h
    rows.push_back({k, lower, (limit - q[k]) / kH});
  }
}

// Limit rows only: y and the rates they leave against the enumeration, and the conditions.
// Three distinct coordinates of n, drawn at random.
std::vector<int> threeOf(std::mt19937& rng, int n) {
  std::vector<int> k(n);
  for (int i = 0; i < n; ++i) k[i] = i;
  std::shuffle(k.begin(), k.end(), rng);
  k.resize(3);
  return k;
}

// The sweeps stop when no impulse changes a rate by more than 1e-14 (1 + |ν̄|∞); with G's
// condition below 5 their error is a few times that: 1e-12 of the rates is generous, and a wrong
// active set or a missed coupling errs by O(1).
TEST(JointRows, LimitImpulsesSolveTheComplementarityProblem) {
  std::mt19937 rng(51);
  constexpr int n = 8;
  for (int trial = 0; trial < 200; ++trial) {
    const std::vector<int> limited = threeOf(rng, n);
    const ArticulatedBody tree = treeWith(rng, n, limited);
    const MatrixXd K = randomSpd(rng, n);
    tree_math::TreeCholesky llt;  // without parents: dense
    llt.compute(K);
    const MatrixXd A = K.inverse();
    VectorXd q(n), nu0(n);
    std::vector<LimitRow> rows;
    pressIntoLimits(rng, limited, q, nu0, rows);

    JointRows joint_rows;
    joint_rows.newMatrix();
    VectorXd nu = nu0;
    joint_rows.solve(tree, llt, q, kH, nu);
    VectorXd y_all(n);
    joint_rows.impulses(y_all);

    const int m = static_cast<int>(rows.size());
    MatrixXd G(m, m);
    VectorXd w0(m), y(m);
    for (int r = 0; r < m; ++r) {
      w0[r] = nu0[rows[r].index];
      y[r] = y_all[rows[r].index];
      for (int s = 0; s < m; ++s) G(r, s) = A(rows[r].index, rows[s].index);
    }
    const VectorXd y_true = bruteForce(G, w0, rows);
    const double scale = 1.0 + nu0.cwiseAbs().maxCoeff();
    const double tol = 1e-12 * scale;
    EXPECT_LE((G * (y - y_true)).cwiseAbs().maxCoeff(), tol) << "trial " << trial;
    // ν̄ moved by A y (the impulses applied to every rate), to round-off.
    EXPECT_LE((nu - (nu0 + A * y_all)).cwiseAbs().maxCoeff(), 1e-13 * scale) << "trial " << trial;
    // Feasible (the signs exactly: they are projections) and complementary.
    for (int r = 0; r < m; ++r) {
      const double sign = rows[r].lower ? 1.0 : -1.0;
      const double gap = sign * (nu[rows[r].index] - rows[r].target);
      EXPECT_GE(sign * y[r], 0.0);
      EXPECT_GE(gap, -tol);
      EXPECT_LE(std::abs(y[r] * G(r, r) * gap), tol * tol + tol * std::abs(y[r] * G(r, r)))
          << "trial " << trial << " row " << r;
    }
    // A joint is held exactly when its limit acted.
    for (int r = 0; r < m; ++r) {
      const std::vector<int>& held = joint_rows.held();
      const bool is_held = std::find(held.begin(), held.end(), rows[r].index) != held.end();
      EXPECT_EQ(is_held, y[r] != 0.0);
    }
  }
}

// The midpoint's iterations solve with one matrix and rates that change little: the second
// solve starts from the first one's impulses. It must find the solution a solve from zero finds
// (unique: G positive definite), to the sweeps' tolerance.
TEST(JointRows, WarmStartedSolveEqualsTheColdOne) {
  std::mt19937 rng(5151);
  constexpr int n = 8;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const std::vector<int> limited = threeOf(rng, n);
    const ArticulatedBody tree = treeWith(rng, n, limited);
    const MatrixXd K = randomSpd(rng, n);
    tree_math::TreeCholesky llt;
    llt.compute(K);
    VectorXd q(n), nu0(n);
    std::vector<LimitRow> rows;
    pressIntoLimits(rng, limited, q, nu0, rows);
    // The next iteration's rates: a change of 1e-3 .. 1e-9 (the iteration's corrections).
    const double change = std::pow(10.0, -3.0 - 6.0 * std::abs(u(rng)));
    VectorXd nu1 = nu0;
    for (int k = 0; k < n; ++k) nu1[k] += change * u(rng);

    JointRows warm;
    warm.newMatrix();
    VectorXd nu_warm = nu0;
    warm.solve(tree, llt, q, kH, nu_warm);
    nu_warm = nu1;
    warm.solve(tree, llt, q, kH, nu_warm);  // the same matrix: from the last impulses
    JointRows cold;
    cold.newMatrix();
    VectorXd nu_cold = nu1;
    cold.solve(tree, llt, q, kH, nu_cold);

    VectorXd y_warm(n), y_cold(n);
    warm.impulses(y_warm);
    cold.impulses(y_cold);
    const double scale = 1.0 + nu1.cwiseAbs().maxCoeff();
    EXPECT_LE((nu_warm - nu_cold).cwiseAbs().maxCoeff(), 1e-12 * scale) << "trial " << trial;
    const MatrixXd A = K.inverse();
    EXPECT_LE((A * (y_warm - y_cold)).cwiseAbs().maxCoeff(), 1e-12 * scale) << "trial " << trial;
    EXPECT_EQ(warm.held(), cold.held()) << "trial " << trial;
    EXPECT_EQ(warm.limitActed(), cold.limitActed()) << "trial " << trial;
  }
}

// Friction and a lower limit on one joint resting exactly at its stop (q = lower: target 0),
// pushed into it: the rate ends at zero and the joint is held either way; only the sum of the
// two impulses is unique. The limit acts exactly when friction alone (|y| ≤ ½ h F) cannot hold
// the joint — also when the solve starts from a split where the limit took part (a harder push
// in the iteration before).
TEST(JointRows, FrictionAtAStopSplitsItsImpulseAsFromZero) {
  std::mt19937 rng(515);
  constexpr int n = 6, k = 3;
  const double F = 40.0, bound = 0.5 * kH * F;
  const ArticulatedBody tree = treeWith(rng, n, {k}, k, F);
  const MatrixXd K = randomSpd(rng, n);
  const MatrixXd A = K.inverse();
  tree_math::TreeCholesky llt;
  llt.compute(K);
  VectorXd q = VectorXd::Zero(n);
  q[k] = -0.5;  // at the lower limit exactly
  // The rate that an impulse of `push` times friction's bound stops.
  const auto rates = [&](double push) {
    VectorXd nu = VectorXd::Zero(n);
    nu[k] = -push * bound * A(k, k);
    for (int i = 0; i < n; ++i)
      if (i != k) nu[i] = 0.3 * A(i, k);
    return nu;
  };
  for (const double push : {0.3, 0.9, 1.5, 4.0}) {
    JointRows cold;
    cold.newMatrix();
    VectorXd nu_cold = rates(push);
    cold.solve(tree, llt, q, kH, nu_cold);
    JointRows warm;  // first a harder push: the limit takes part
    warm.newMatrix();
    VectorXd nu_warm = rates(5.0);
    warm.solve(tree, llt, q, kH, nu_warm);
    ASSERT_TRUE(warm.limitActed());
    nu_warm = rates(push);
    warm.solve(tree, llt, q, kH, nu_warm);

    VectorXd y_cold(n), y_warm(n);
    cold.impulses(y_cold);
    warm.impulses(y_warm);
    const double scale = 1.0 + rates(push).cwiseAbs().maxCoeff();
    for (const JointRows* rows : {&cold, &warm}) {
      const VectorXd& nu = rows == &cold ? nu_cold : nu_warm;
      EXPECT_LE(std::abs(nu[k]), 1e-14 * scale) << "push " << push;  // at rest at its stop
      EXPECT_EQ(rows->held(), std::vector<int>{k}) << "push " << push;
      EXPECT_EQ(rows->limitActed(), push > 1.0) << "push " << push;
    }
    EXPECT_NEAR(y_cold[k], push * bound, 1e-14 * push * bound) << "push " << push;
    EXPECT_NEAR(y_warm[k], y_cold[k], 1e-14 * push * bound) << "push " << push;
    EXPECT_LE((nu_warm - nu_cold).cwiseAbs().maxCoeff(), 1e-14 * scale) << "push " << push;
  }
}

}  // namespace joint_rows_test
}  // namespace dynamics
}  // namespace cga_rigid_sim
