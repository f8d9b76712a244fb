// JointRows (joint_rows.h).
#include "tree/joint_rows.h"

#include <algorithm>
#include <cmath>

namespace cga_rigid_sim {
namespace dynamics {

namespace {
// Gauss–Seidel sweeps stop when no impulse changes a rate by more than this (m/s or rad/s,
// relative to 1 + |ν̄|∞) — round-off of the rates — or after kMaxSweeps.
constexpr double kSweepTolerance = 1e-14;
constexpr int kMaxSweeps = 100;
}  // namespace

void JointRows::solve(const ArticulatedBody& tree, const tree_math::TreeCholesky& llt,
                      const Eigen::VectorXd& q, double h, Eigen::VectorXd& nu_bar) {
  rows_.clear();
  held_.clear();
  if (&tree != tree_) {  // the joints with friction or limits, once per tree
    tree_ = &tree;
    watched_.clear();
    // Per independent coordinate (a joint's own without mimic joints; with them, the limits
    // and friction of the joints that follow it mapped onto their leader's).
    for (const JointCoordinate& c : tree.coordinates())
      if (c.friction > 0 || c.hasLimits())
        watched_.push_back({c.joint, tree.reducedIndex(c.joint), c.lower, c.upper, c.friction});
  }
  for (const Watched& j : watched_) {
    const int k = j.joint, i = j.index;
    if (j.friction > 0) rows_.push_back({i, Kind::kFriction, 0.0, 0.5 * h * j.friction});
    const double end = q[k] + h * nu_bar[i];
    if (end <= j.lower || q[k] <= j.lower)
      rows_.push_back({i, Kind::kLower, (j.lower - q[k]) / h, 0.0});
    if (end >= j.upper || q[k] >= j.upper)
      rows_.push_back({i, Kind::kUpper, (j.upper - q[k]) / h, 0.0});
  }
  if (rows_.empty()) return;
  const std::size_t n = static_cast<std::size_t>(nu_bar.size());
  if (columns_.size() < n) {  // never shrunk: no reallocation
    columns_.resize(n);
    column_matrix_.resize(n, 0);
  }
  for (const Row& row : rows_) {  // the columns this matrix has not made yet
    const int k = row.index;
    if (column_matrix_[k] == matrix_) continue;
    columns_[k].setZero(nu_bar.size());
    columns_[k][k] = 1.0;
    llt.solveInPlace(columns_[k]);
    column_matrix_[k] = matrix_;
  }
  // The sweeps on the rows' own system: w = ν̄[index] moves by G y, an O(m) update where ν̄'s
  // would be O(n); ν̄ takes the impulses once at the end. (The same iteration as sweeping ν̄
  // itself: only the rounding differs.)
  const int m = static_cast<int>(rows_.size());
  if (G_.rows() < m) {  // never shrunk: no reallocation once the most rows have been seen
    G_.resize(m, m);
    w_.resize(m);
  }
  const Eigen::Index stride = G_.rows();
  double* G = G_.data();
  double* w = w_.data();
  for (int s = 0; s < m; ++s) {
    const double* column = columns_[rows_[s].index].data();
    double* G_s = G + s * stride;
    for (int r = 0; r < m; ++r) G_s[r] = column[rows_[r].index];
    w[s] = nu_bar[rows_[s].index];
  }
  const double scale = 1.0 + nu_bar.cwiseAbs().maxCoeff();
  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    double largest = 0.0;
    for (int r = 0; r < m; ++r) {
      Row& row = rows_[r];
      const double* G_r = G + r * stride;
      const double v = w[r], a = G_r[r];
      double y = row.y;
      switch (row.kind) {
        case Kind::kLower:
          y = std::max(0.0, y + (row.target - v) / a);
          break;
        case Kind::kUpper:
          y = std::min(0.0, y + (row.target - v) / a);
          break;
        case Kind::kFriction:
          y = std::clamp(y - v / a, -row.bound, row.bound);
          break;
      }
      const double dy = y - row.y;
      if (dy != 0.0)
        for (int i = 0; i < m; ++i) w[i] += G_r[i] * dy;
      largest = std::max(largest, std::abs(dy * a));
      row.y = y;
    }
    if (largest <= kSweepTolerance * scale) break;
  }
  for (const Row& row : rows_)
    if (row.y != 0.0) nu_bar += columns_[row.index] * row.y;
  for (const Row& row : rows_) {
    const bool held = row.kind == Kind::kFriction ? std::abs(row.y) < row.bound : row.y != 0.0;
    if (held && std::find(held_.begin(), held_.end(), row.index) == held_.end())
      held_.push_back(row.index);
  }
}

void JointRows::clampPositions(const ArticulatedBody& tree, Eigen::VectorXd& q) const {
  for (const JointCoordinate& c : tree.coordinates())
    if (c.hasLimits()) q[c.joint] = std::clamp(q[c.joint], c.lower, c.upper);
  applyMimicPositions(tree, q);
}

template <class Factor>
void stopRates(const Factor& llt, const std::vector<int>& held, Eigen::VectorXd& nu,
               StopScratch& s) {
  const int m = static_cast<int>(held.size()), n = static_cast<int>(nu.size());
  if (m == 0) return;
  // Sized for every coordinate held at once, the first time: m changes as joints reach and
  // leave their stops, and the leading blocks of these serve every m without allocating.
  if (s.AE.rows() != n) {
    s.AE.resize(n, n);
    s.G.resize(n, n);
    s.e.resize(n);
    s.v.resize(n);
    s.dnu.resize(n);
  }
  for (int c = 0; c < m; ++c) {
    s.e.setZero();
    s.e[held[c]] = 1.0;
    llt.solveInPlace(s.e);
    s.AE.col(c) = s.e;
    s.v[c] = -nu[held[c]];
  }
  auto AE = s.AE.leftCols(m);
  auto G = s.G.topLeftCorner(m, m);
  for (int r = 0; r < m; ++r) G.row(r) = AE.row(held[r]);
  Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> G_llt(G);  // in place: G holds its factor after
  auto z = s.v.head(m);
  G_llt.solveInPlace(z);
  s.dnu.noalias() = AE * z;
  nu += s.dnu;
  for (int c = 0; c < m; ++c) nu[held[c]] = 0.0;  // exactly, not to round-off
}

template void stopRates(const tree_math::Cholesky&, const std::vector<int>&, Eigen::VectorXd&,
                        StopScratch&);
template void stopRates(const tree_math::TreeCholesky&, const std::vector<int>&, Eigen::VectorXd&,
                        StopScratch&);

bool JointRows::stopHeld(const ArticulatedBody&, const tree_math::TreeCholesky& llt,
                         Eigen::VectorXd& nu) const {
  if (held_.empty()) return false;
  stopRates(llt, held_, nu, stop_);
  return true;
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
