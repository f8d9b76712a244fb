// The velocity sweeps of an island with a tree (doc/contacts.md#trees, SolverWork::TreeSweeps):
// they move the tree's ν in its factor's coordinates, ν = ν₀ + L⁻¹ z, each contact and each joint
// stop over its path to the base alone, and make ν once after the sweeps. Whatever the sweeps
// leave unconverged, the ν they hand back must be the one their impulses give:
// ν = ν₀ + M⁻¹ (Σ Jᵀ P + Σ e_k y), with M⁻¹ from Eigen's dense LLT of M, not from the factor; and
// the sparse factor's coordinates must give the sweeps of the dense one (mimic joints' path).
// The position correction's sweeps take the same coordinates for pν: they must give the pν of
// the dense sweeps they replaced (impulses through the columns M⁻¹ Jᵀ and M⁻¹ e_k).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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
// `sparse`: the factor on the tree's sparsity, else dense (as with mimic joints). `overlaps`:
// for the position correction, two more contacts between links of the tree, and each contact's
// depth random within the 0.1 mm past the slop that the correction sweeps (deeper ones a lone
// tree's island corrects exactly), one within the slop.
Problem makeProblem(std::mt19937& rng, bool sparse, bool overlaps = false) {
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
  if (overlaps) {
    const SolverSettings st;
    for (int k = 0; k < 2; ++k) {  // between links of the tree: side a keeps J_a − J_b
      const int b = std::uniform_int_distribution<int>(1, tree.bodyCount() - 1)(rng);
      Contact c = p.contacts[k];
      c.point_W = p.bodies[b].x + testing::randomVector(rng, 0.2);
      p.contacts.push_back(c);
      p.slot_a.push_back(b);
      p.slot_b.push_back(b - 1);
    }
    std::uniform_real_distribution<double> fraction(0.05, 0.95);
    for (Contact& c : p.contacts) c.depth = st.slop + fraction(rng) * 1e-4;
    p.contacts[3].depth = 0.5 * st.slop;
    for (int k = 1; k < 8; k += 2) std::swap(p.slot_a[k], p.slot_b[k]);  // the tree as side b
  }
  // Each contact's normal against its point's velocity, so that every one approaches (the
  // screws are random: "down" means nothing to them).
  std::vector<ContactRow> rows;
  prepareRows(p.contacts, p.bodies, p.trees, p.slot_a, p.slot_b, rows);
  for (std::size_t k = 0; k < rows.size(); ++k)
    p.contacts[k].normal_W = rows[k].ta >= 0
                                 ? Eigen::Vector3d(-(rows[k].ja * p.trees[0].nu).normalized())
                                 : Eigen::Vector3d((rows[k].jb * p.trees[0].nu).normalized());
  return p;
}

// The settings of the swept solve: Newton's resting solve off, 30 sweeps at most as for any
// tree's island.
SolverSettings sweptSettings() {
  SolverSettings st;
  st.resting_tree_speed = 0.0;
  return st;
}

// The swept velocity solve of p (its working arrays left in `work`).
std::vector<ContactRow> solve(Problem& p, SolverWork& work) {
  std::vector<ContactRow> rows;
  prepareRows(p.contacts, p.bodies, p.trees, p.slot_a, p.slot_b, rows);
  solveVelocities(sweptSettings(), p.bodies, p.trees, rows, work);
  return rows;
}

std::vector<ContactRow> solve(Problem& p) {
  SolverWork work;
  return solve(p, work);
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

// u = J ν at a row of the one tree: side a's Jacobian, or minus side b's.
Eigen::Matrix<double, 3, Eigen::Dynamic> J(const ContactRow& c) {
  return c.ta >= 0 ? Eigen::Matrix<double, 3, Eigen::Dynamic>(c.ja)
                   : Eigen::Matrix<double, 3, Eigen::Dynamic>(-c.jb);
}

// The sweeps' 30 sweeps leave these islands' contacts approaching past their targets by 2e-3
// to 0.7 m/s (rates of ~1 m/s, stops within 0.1 mm, random screws). With Newton's solves on
// (the default settings) the normals and stops are solved again with the sweeps' friction held,
// in rounds while keeping that friction within μ λ_n cuts it (polishTreeNormals). Asserted on
// every problem the sweeps leave sinking: the answer is the one its impulses give (through
// Eigen's LLT, as above: 1e-12), its friction within the cone, its kinetic energy not above the
// energy before the impulses (1e-9: the products' round-off), and no contact approaching
// faster than the sweeps left the fastest (the sweeps' answer stands where it would). And in
// all but a few the normals hold: every contact within 1e-4 m/s of its target, twenty times
// below the least the sweeps left (measured: 18 of 19 problems within 2.1e-5 m/s; in the other
// the held friction is still being cut after the eight rounds and the sweeps' answer stands).
// The test fails without the solve (every problem then stays as swept).
TEST(TreeSweeps, NormalsSolvedAgainWhereTheSweepsLeaveAContactSinking) {
  std::mt19937 rng(23);
  int sinking = 0, held = 0;
  for (int trial = 0; trial < 20; ++trial) {
    Problem p = makeProblem(rng, true);
    Problem swept = p;
    SolverWork work;
    std::vector<ContactRow> rows;
    prepareRows(swept.contacts, swept.bodies, swept.trees, swept.slot_a, swept.slot_b, rows);
    solveVelocities(sweptSettings(), swept.bodies, swept.trees, rows, work);
    double sink = 0.0;
    for (const ContactRow& c : rows)
      sink = std::max(sink, c.target - c.n.dot(J(c) * swept.trees[0].nu));
    const SolverSettings st;
    if (sink <= st.tree_sink_speed) continue;
    ++sinking;
    const Eigen::VectorXd nu0 = p.trees[0].nu;
    rows.clear();
    prepareRows(p.contacts, p.bodies, p.trees, p.slot_a, p.slot_b, rows);
    solveVelocities(st, p.bodies, p.trees, rows, work);
    const SolverTree& t = p.trees[0];
    Eigen::VectorXd f = Eigen::VectorXd::Zero(nu0.size());
    double approach = 0.0;
    for (const ContactRow& c : rows) {
      approach = std::max(approach, c.target - c.n.dot(J(c) * t.nu));
      EXPECT_LE(c.lambda_t.norm(), c.mu * c.lambda_n * (1 + 1e-12)) << "trial " << trial;
      f += c.ja.transpose() * (c.lambda_n * c.n + c.lambda_t.x() * c.t1 + c.lambda_t.y() * c.t2);
    }
    for (const SolverTree::LimitRow& r : t.limits) f[r.index] += r.y_lower + r.y_upper;
    const Eigen::VectorXd expected = t.M.llt().solve(f);
    const Eigen::VectorXd moved = t.nu - nu0;
    EXPECT_LE((moved - expected).cwiseAbs().maxCoeff(), 1e-12 * moved.cwiseAbs().maxCoeff())
        << "trial " << trial;
    EXPECT_LE(t.nu.dot(t.M * t.nu), nu0.dot(t.M * nu0) * (1 + 1e-9)) << "trial " << trial;
    EXPECT_LE(approach, sink) << "trial " << trial;
    held += approach <= 1e-4;
  }
  EXPECT_GE(sinking, 15);  // the sweeps do leave contacts sinking here (measured: 19 of 20)
  EXPECT_GE(held, sinking - 2);
}

// Newton's resting solve warm-started from its own answer to the same problem
// (doc/contacts.md#resting-trees): the last step's impulses, each contact's split onto its
// four friction edges as the solve left it (ContactRow::pyramid_share, pyramidEdges), start the
// first round at that answer, so the solve factors its Hessian once, never updates it (the
// first Newton step's active rows are the answer's) and ends at the same answer. The problems:
// the trees above at a hundredth of their rates (some contacts stick), four contacts on each of
// two links, a foot's corners (redundant rows), touching (no position correction). The answer
// is the same to the solve's tolerance: rows within 1e-8 m/s of their targets, ν of ~1e-2 m/s;
// 1e-6 of ν's scale bounds the difference (measured 4.9e-7). Started cold instead, every
// problem takes updates (the test fails). This checks the start, not the split: on these
// problems any split of the same impulses starts at the same active rows (the split's own test
// is tree_resting_test's PyramidEdgesGiveBackTheEdgesTheyWereMadeFrom).
TEST(TreeSweeps, RestingSolveWarmStartedFromItsAnswerStartsAtIt) {
  std::mt19937 rng(41);
  SolverSettings st;
  st.resting_tree_speed = 1e9;  // Newton's solve at any speed
  int solved = 0;
  double worst = 0.0;
  for (int trial = 0; trial < 20; ++trial) {
    Problem p = makeProblem(rng, true);
    p.trees[0].nu *= 0.01;
    const int feet[2] = {1 + trial % (kJoints - 1), kJoints - trial % (kJoints - 1)};
    for (int k = 0; k < 8; ++k) {
      p.slot_a[k] = feet[k / 4];
      p.contacts[k].point_W = p.bodies[feet[k / 4]].x + testing::randomVector(rng, 0.1);
      p.contacts[k].depth = 0.0;
    }
    {
      std::vector<ContactRow> r;
      prepareRows(p.contacts, p.bodies, p.trees, p.slot_a, p.slot_b, r);
      // One normal per foot, against its first point's velocity: the four approach together.
      for (int k = 0; k < 8; ++k)
        p.contacts[k].normal_W = -(r[4 * (k / 4)].ja * p.trees[0].nu).normalized();
    }
    SolverTree& t = p.trees[0];
    const Eigen::VectorXd nu0 = t.nu;
    SolverWork work;
    std::vector<ContactRow> first;
    prepareRows(p.contacts, p.bodies, p.trees, p.slot_a, p.slot_b, first);
    solveVelocities(st, p.bodies, p.trees, first, work);
    // A refused solve (the sweeps' answer) leaves the shares unknown.
    if (!std::all_of(first.begin(), first.end(),
                     [](const ContactRow& c) { return std::isfinite(c.pyramid_share); }))
      continue;
    ++solved;
    const Eigen::VectorXd answer = t.nu;
    std::vector<ContactRow> rows;
    prepareRows(p.contacts, p.bodies, p.trees, p.slot_a, p.slot_b, rows);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      rows[k].lambda_n = first[k].lambda_n;
      rows[k].lambda_t = first[k].lambda_t;
      rows[k].pyramid_share = first[k].pyramid_share;
    }
    for (SolverTree::LimitRow& r : t.limits) {
      r.y_lower_last = r.y_lower;
      r.y_upper_last = r.y_upper;
    }
    t.nu = nu0;
    const TreeNewton& N = work.resting_tree.newton;
    const long f = N.factorisations, u = N.rank_updates;
    solveVelocities(st, p.bodies, p.trees, rows, work);
    EXPECT_EQ(N.factorisations - f, 1) << "trial " << trial;
    EXPECT_EQ(N.rank_updates - u, 0) << "trial " << trial;
    worst = std::max(worst, (t.nu - answer).cwiseAbs().maxCoeff() / answer.cwiseAbs().maxCoeff());
  }
  EXPECT_GE(solved, 15);  // (measured: 20 of 20)
  EXPECT_LE(worst, 1e-6);
}

// The position correction as its sweeps were before they took the factor's coordinates: the
// same Gauss–Seidel on the same rows in the same order, with the same stopping test, a row's
// pseudo-impulse applied to pν through the dense column M⁻¹ Jᵀ n and a stop's through M⁻¹ e_k,
// here from Eigen's LLT of M. `rows` and the tree as solveVelocities left them (one island, its
// rows in their order); the rows' impulses in lambda_p, the stops' in p_lower, p_upper. (The
// correction's cap, max_tree_shift, is far from these pν.)
Eigen::VectorXd densePositionSweeps(const SolverSettings& st, SolverTree& t,
                                    std::vector<ContactRow>& rows) {
  const Eigen::LLT<Eigen::MatrixXd> llt(t.M);
  const int n = static_cast<int>(t.nu.size());
  std::vector<Eigen::VectorXd> column;  // M⁻¹ Jᵀ n per row
  double max_bias = 0.0;
  for (ContactRow& c : rows) {
    c.bias = c.depth > st.slop ? st.correction * (c.depth - st.slop) / st.h : 0.0;
    c.lambda_p = 0.0;
    max_bias = std::max(max_bias, c.bias);
    column.push_back(llt.solve(J(c).transpose() * c.n));
  }
  std::vector<Eigen::VectorXd> stop_column;  // M⁻¹ e_k per stop
  for (SolverTree::LimitRow& r : t.limits) {
    r.p_lower = r.p_upper = 0.0;
    stop_column.push_back(llt.solve(Eigen::VectorXd::Unit(n, r.index)));
  }
  const double tolerance = 1e-3 * max_bias;
  Eigen::VectorXd pnu = Eigen::VectorXd::Zero(n);
  for (int it = 0; it < st.position_iterations; ++it) {
    const Eigen::VectorXd before = pnu;
    for (std::size_t k = 0; k < rows.size(); ++k) {
      ContactRow& c = rows[k];
      if (c.bias <= 0 && c.lambda_p == 0.0) continue;
      const double u = c.n.dot(J(c) * pnu);
      const double lp = std::max(0.0, c.lambda_p + (c.bias - u) * c.inv_k_nn);
      pnu += (lp - c.lambda_p) * column[k];
      c.lambda_p = lp;
    }
    double change = 0.0;
    for (std::size_t j = 0; j < t.limits.size(); ++j) {
      SolverTree::LimitRow& r = t.limits[j];
      const double b = t.nu[r.index];
      const double lo = (r.lower - r.q) / st.h - b, hi = (r.upper - r.q) / st.h - b;
      double v = pnu[r.index];
      if (r.p_lower == 0.0 && r.p_upper == 0.0 && v >= lo && v <= hi) continue;
      const double a = stop_column[j][r.index];
      const double yl = std::max(0.0, r.p_lower + (lo - v) / a);
      double dy = yl - r.p_lower;
      r.p_lower = yl;
      v += dy * a;
      const double yu = std::min(0.0, r.p_upper + (hi - v) / a);
      dy += yu - r.p_upper;
      r.p_upper = yu;
      pnu += dy * stop_column[j];
      change = std::max(change, std::abs(dy * a));
    }
    if (change < tolerance)
      for (const ContactRow& c : rows) change = std::max(change, (J(c) * (pnu - before)).norm());
    if (change < tolerance) break;
  }
  return pnu;
}

// The swept pν against the dense sweeps' on the same rows after the same velocity solve: the
// same projections in the same order, their impulses through the factor's coordinates instead
// of Eigen's M⁻¹ columns, so the same pν up to a few cond(M) ε relative, which the projections
// do not amplify (a row or stop would have to sit within round-off of switching): measured
// ≤ 1.4e-14 of |pν| over these 20 problems, asserted 1e-12; the rows' and stops' impulses
// ≤ 1.1e-14 of the largest row impulse, asserted 1e-12. 90 rows push and 38 stops act over the
// 20 problems (asserted: some of each). Side b's normal taken unnegated leaves pν 0.7 off.
TEST_P(TreeSweepsTest, PositionCorrectionIsTheDenseSweeps) {
  std::mt19937 rng(GetParam() ? 21 : 23);
  int pushing = 0, stopped = 0;
  for (int trial = 0; trial < 10; ++trial) {
    Problem p = makeProblem(rng, GetParam(), true);
    const SolverSettings st = sweptSettings();
    SolverWork work;
    std::vector<ContactRow> rows = solve(p, work);
    SolverTree dense_tree = p.trees[0];
    std::vector<ContactRow> dense_rows = rows;
    const Eigen::VectorXd expected = densePositionSweeps(st, dense_tree, dense_rows);
    solvePositions(st, p.bodies, p.trees, rows, work);
    const Eigen::VectorXd& pnu = p.trees[0].pnu;
    const double scale = expected.cwiseAbs().maxCoeff();
    ASSERT_GT(scale, 0.0);
    EXPECT_LE((pnu - expected).cwiseAbs().maxCoeff(), 1e-12 * scale) << "trial " << trial;
    double impulse = 0.0, impulse_error = 0.0;
    for (std::size_t k = 0; k < rows.size(); ++k) {
      impulse = std::max(impulse, std::abs(dense_rows[k].lambda_p));
      impulse_error = std::max(impulse_error, std::abs(rows[k].lambda_p - dense_rows[k].lambda_p));
      pushing += rows[k].lambda_p > 0;
    }
    EXPECT_LE(impulse_error, 1e-12 * impulse) << "trial " << trial;
    for (std::size_t j = 0; j < dense_tree.limits.size(); ++j) {
      const SolverTree::LimitRow &r = p.trees[0].limits[j], &d = dense_tree.limits[j];
      EXPECT_LE(std::abs(r.p_lower - d.p_lower) + std::abs(r.p_upper - d.p_upper),
                1e-12 * std::max(impulse, std::abs(d.p_lower) + std::abs(d.p_upper)))
          << "trial " << trial << " stop " << j;
      stopped += d.p_lower != 0.0 || d.p_upper != 0.0;
    }
  }
  EXPECT_GT(pushing, 0);
  EXPECT_GT(stopped, 0);
}

INSTANTIATE_TEST_SUITE_P(SparseAndDense, TreeSweepsTest, ::testing::Bool());

}  // namespace tree_sweeps_test
}  // namespace sim
}  // namespace cga_rigid_sim
