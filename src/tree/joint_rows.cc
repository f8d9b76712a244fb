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
    last_rows_.clear();
    // Per independent coordinate (a joint's own without mimic joints; with them, the limits
    // and friction of the joints that follow it mapped onto their leader's).
    for (const JointCoordinate& c : tree.coordinates())
      if (c.friction > 0 || c.hasLimits())
        watched_.push_back({c.joint, tree.reducedIndex(c.joint), c.lower, c.upper, c.friction});
  }
  // (Local pointers: rows_.push_back could alias the members, so the compiler would reload
  // them for every joint.)
  const Watched* watched = watched_.data();
  const int watched_count = static_cast<int>(watched_.size());
  const double *q_data = q.data(), *nu_data = nu_bar.data();
  for (int p = 0; p < watched_count; ++p) {
    const Watched& j = watched[p];
    const int k = j.joint, i = j.index, key = 3 * p;
    const double q_k = q_data[k], end = q_k + h * nu_data[i];
    if (j.friction > 0) rows_.push_back({i, Kind::kFriction, 0.0, 0.5 * h * j.friction, key});
    if (end <= j.lower || q_k <= j.lower)
      rows_.push_back({i, Kind::kLower, (j.lower - q_k) / h, 0.0, key + 1});
    if (end >= j.upper || q_k >= j.upper)
      rows_.push_back({i, Kind::kUpper, (j.upper - q_k) / h, 0.0, key + 2});
  }
  const bool warm = last_matrix_ == matrix_ && warmStart();
  if (rows_.empty()) {
    last_rows_.clear();
    last_matrix_ = matrix_;
    return;
  }
  const std::size_t n = static_cast<std::size_t>(nu_bar.size());
  if (columns_.size() < n) {  // never shrunk: no reallocation
    columns_.resize(n);
    column_matrix_.resize(n, 0);
  }
  for (const Row& row : rows_) {  // the columns this matrix has not made yet
    const int k = row.index;
    if (column_matrix_[k] == matrix_) continue;
    columns_[k].resize(nu_bar.size());
    llt.solveUnit(k, columns_[k]);
    column_matrix_[k] = matrix_;
  }
  // The sweeps run on the rows' own system: w = ν̄[index] moves by G y, an O(m) update where
  // ν̄'s would be O(n); ν̄ takes the impulses once at the end. (The same iteration as sweeping
  // ν̄ itself: only the rounding differs.)
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
  // A warm start: the iterations of one step solve LCPs with this matrix and nearly the same
  // rates, and the last solve's impulses are close to this one's.
  if (warm)
    for (int s = 0; s < m; ++s)
      if (rows_[s].y != 0.0)
        for (int r = 0; r < m; ++r) w[r] += G[r + s * stride] * rows_[s].y;
  sweep(1.0 + nu_bar.cwiseAbs().maxCoeff());
  canonicalSplit();
  for (const Row& row : rows_)
    if (row.y != 0.0) nu_bar += columns_[row.index] * row.y;
  for (const Row& row : rows_) {
    const bool held = row.kind == Kind::kFriction ? std::abs(row.y) < row.bound : row.y != 0.0;
    if (held && std::find(held_.begin(), held_.end(), row.index) == held_.end())
      held_.push_back(row.index);
  }
  last_rows_ = rows_;  // (into the capacity of the rows before: no allocation once sized)
  last_matrix_ = matrix_;
}

bool JointRows::warmStart() {
  // Both lists ascend in key (watched_'s order, then friction, lower, upper).
  bool any = false;
  std::size_t p = 0;
  for (Row& row : rows_) {
    while (p < last_rows_.size() && last_rows_[p].key < row.key) ++p;
    if (p == last_rows_.size()) break;
    if (last_rows_[p].key != row.key) continue;
    row.y = last_rows_[p].y;  // feasible: the same h (bound) and the same kind (sign)
    any = any || row.y != 0.0;
  }
  return any;
}

int JointRows::sweep(double scale) {
  const int m = static_cast<int>(rows_.size());
  const Eigen::Index stride = G_.rows();
  const double* G = G_.data();
  double* w = w_.data();
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
    if (largest <= kSweepTolerance * scale) return sweep + 1;
  }
  return kMaxSweeps;
}

void JointRows::canonicalSplit() {
  // The rows of one coordinate are adjacent (friction, lower, upper). Their columns are the
  // same, so G is singular there and the sweeps find one of many splits of their sum: the
  // rate w is unique, and a limit row with y ≠ 0 pins it at its target. The split is free
  // among the rows that allow that rate with any impulse of their sign: friction when the rate
  // is 0 (a joint at rest exactly at its stop: q clamped to the limit, target 0), and a limit
  // whose target is that rate (lower = upper). Their sum goes to friction first (within its
  // bound), the rest to the limit of its sign: a limit acts only where friction alone could
  // not hold the joint.
  for (std::size_t first = 0, end = 0; first < rows_.size(); first = end) {
    end = first + 1;
    while (end < rows_.size() && rows_[end].index == rows_[first].index) ++end;
    if (end - first < 2) continue;
    const Row* pin = nullptr;
    for (std::size_t r = first; r < end; ++r)
      if (rows_[r].kind != Kind::kFriction && rows_[r].y != 0.0) pin = &rows_[r];
    if (!pin) continue;  // no limit acts: friction's impulse alone is unique
    const double rate = pin->target;
    Row *friction = nullptr, *lower = nullptr, *upper = nullptr;
    int free_rows = 0;
    double sum = 0.0;
    for (std::size_t r = first; r < end; ++r) {
      Row& row = rows_[r];
      const bool free = row.kind == Kind::kFriction ? rate == 0.0 : row.target == rate;
      if (!free) continue;
      ++free_rows;
      sum += row.y;
      (row.kind == Kind::kFriction ? friction : row.kind == Kind::kLower ? lower : upper) = &row;
    }
    if (free_rows < 2) continue;
    double rest = sum;
    if (friction) {
      friction->y = std::clamp(sum, -friction->bound, friction->bound);
      rest = sum - friction->y;
    }
    if (lower) lower->y = upper ? std::max(rest, 0.0) : rest;
    if (upper) upper->y = lower ? std::min(rest, 0.0) : rest;
  }
}

void JointRows::clampPositions(const ArticulatedBody& tree, Eigen::VectorXd& q) const {
  for (const JointCoordinate& c : tree.coordinates())
    if (c.hasLimits()) q[c.joint] = std::clamp(q[c.joint], c.lower, c.upper);
  applyMimicPositions(tree, q);
}

namespace {
// e ← A⁻¹ e_k (e of A's size): along k's path on a tree's factor (the same bits).
void unitColumn(const tree_math::TreeCholesky& llt, int k, Eigen::VectorXd& e) {
  llt.solveUnit(k, e);
}
void unitColumn(const tree_math::Cholesky& llt, int k, Eigen::VectorXd& e) {
  e.setZero();
  e[k] = 1.0;
  llt.solveInPlace(e);
}
}  // namespace

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
    unitColumn(llt, held[c], s.e);
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
