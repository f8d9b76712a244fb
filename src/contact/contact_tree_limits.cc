// A tree's joint limits as rows of the contact solve (doc/contacts.md#trees, SolverTree::
// LimitRow): over the step a joint may reach its limits, not pass them, by impulses on the
// joint itself; the contacts and the stops share the load through M(q). The same rows keep the
// position correction within the limits.
#include <algorithm>
#include <cmath>

#include "contact/contact_solver_internals.h"

namespace cga_rigid_sim {
namespace sim {
namespace detail {
void loadSweptLimits(const SolverTree& t, int tree, SolverWork::TreeSweeps& T) {
  const int n = static_cast<int>(t.nu.size()), m = static_cast<int>(t.limits.size());
  std::vector<SolverWork::TreeSweeps::Run>& stop = T.stop[tree];
  std::vector<double>& stop_a = T.stop_a[tree];
  std::vector<double>& stop_norm = T.stop_norm[tree];
  stop.resize(m);
  stop_a.resize(m);
  stop_norm.resize(m);
  TreeFactor::Columns& columns = T.scratch[tree];
  columns.setZero(n, 3);
  T.swept_island = nullptr;  // the runs are being made anew
  const bool sparse = t.factor.sparse();
  // Whether coordinate k is on the path from `leaf` to the base (a parent's index is smaller than
  // its child's).
  auto onPath = [&](int k, int leaf) {
    if (k < 0) return false;
    while (leaf > k) leaf = t.coordinate_parent[leaf];
    return leaf == k;
  };
  // Up to three stops a half solve, one a column: it walks the union of the paths from two
  // leaves to the base, and solves every column whose stop is on that union (a joint above
  // another's, as down a limb's chain, rides along; with a dense factor, any three).
  for (int j = 0; j < m;) {
    int leaf_a = -1, leaf_b = -1, taken = 0;
    for (; j + taken < m && taken < 3; ++taken) {
      const int k = t.limits[j + taken].index;
      if (!sparse || onPath(k, leaf_a) || onPath(k, leaf_b)) {
        // on the union already
      } else if (onPath(leaf_a, k)) {
        leaf_a = k;
      } else if (onPath(leaf_b, k)) {
        leaf_b = k;
      } else if (leaf_a < 0) {
        leaf_a = k;
      } else if (leaf_b < 0) {
        leaf_b = k;
      } else {
        break;
      }
      columns(k, taken) = 1.0;
    }
    t.factor.halfSolve(columns, leaf_a, leaf_b);
    for (int c = 0; c < taken; ++c, ++j) {  // s = L⁻ᵀ e_k
      const int k = t.limits[j].index;
      SolverWork::TreeSweeps::Run& run = stop[j];
      run.first = static_cast<int>(T.stop_coordinate.size());
      double a = 0.0;
      // s is zero off k's path to the base (with a dense factor: nowhere).
      for (int i = sparse ? k : n - 1; i >= 0; i = sparse ? t.coordinate_parent[i] : i - 1) {
        const double s = columns(i, c);
        T.stop_coordinate.push_back(i);
        T.s.push_back(s);
        a += s * s;
        columns(i, c) = 0.0;
      }
      run.size = static_cast<int>(T.stop_coordinate.size()) - run.first;
      stop_a[j] = a;
      stop_norm[j] = std::sqrt(a);
    }
  }
}

namespace {

// One Gauss–Seidel pass over tree t's limit rows in the sweeps' coordinates (SolverWork::
// TreeSweeps): the rate ν_k = ν₀_k + sᵀ z is kept so that q + h ν_k stays within [lower, upper]
// by the accumulated impulses *y_lower ≥ 0 and *y_upper ≤ 0 on the joint; an impulse dy adds
// dy s to z. kPosition: the position correction's pass, its rate pν_k = sᵀ z on top of ν_k (its
// bounds less ν_k, as the correction's dense pass had them). Returns the largest change of a rate.
//
// A stop without impulse whose rate cannot have reached its bounds is passed over without
// computing sᵀ z: |sᵀ z| ≤ |s| |z| (Cauchy–Schwarz), and |z| is kept as an upper bound through the
// pass (it grows by at most |dy| |s| an impulse). The bound allows for the rounding of
// ν₀_k + sᵀ z (at most ~1e-15 of its terms), so a stop passed over is one the sum would have found
// free: the same answer to the bit.
template <double SolverTree::LimitRow::*Lower, double SolverTree::LimitRow::*Upper, bool kPosition>
double sweepSweptLimits(SolverTree& t, int tree, SolverWork::TreeSweeps& T, double h) {
  double change = 0.0;
  double* z = T.z[tree].data();
  double z_norm = T.z[tree].norm() * (1.0 + 1e-12);
  const int* coordinate = T.stop_coordinate.data();
  const double* s = T.s.data();
  for (std::size_t j = 0; j < t.limits.size(); ++j) {
    SolverTree::LimitRow& r = t.limits[j];
    double lo = (r.lower - r.q) / h, hi = (r.upper - r.q) / h;
    double v0 = t.nu[r.index];
    if (kPosition) lo -= v0, hi -= v0, v0 = 0.0;
    const double s_norm = T.stop_norm[tree][j];
    const bool loaded = r.*Lower != 0.0 || r.*Upper != 0.0;
    if (!loaded) {
      const double reach = s_norm * z_norm * (1.0 + 1e-12) + 1e-14 * std::abs(v0);
      if (v0 - reach > lo && v0 + reach < hi) continue;  // free, and known to be
    }
    const SolverWork::TreeSweeps::Run& run = T.stop[tree][j];
    double v = v0;
    for (int i = run.first; i < run.first + run.size; ++i) v += s[i] * z[coordinate[i]];
    if (!loaded && v >= lo && v <= hi) continue;  // free
    const double a = T.stop_a[tree][j];
    if (!(a > 0.0)) continue;
    const double yl = std::max(0.0, r.*Lower + (lo - v) / a);
    double dy = yl - r.*Lower;
    r.*Lower = yl;
    v += dy * a;
    const double yu = std::min(0.0, r.*Upper + (hi - v) / a);
    dy += yu - r.*Upper;
    r.*Upper = yu;
    if (dy == 0.0) continue;
    for (int i = run.first; i < run.first + run.size; ++i) z[coordinate[i]] += dy * s[i];
    z_norm += std::abs(dy) * s_norm * (1.0 + 1e-12);
    change = std::max(change, std::abs(dy * a));
  }
  return change;
}

}  // namespace

double sweepVelocityLimits(SolverTree& t, int tree, SolverWork::TreeSweeps& T, double h) {
  return sweepSweptLimits<&SolverTree::LimitRow::y_lower, &SolverTree::LimitRow::y_upper, false>(
      t, tree, T, h);
}

double sweepPositionLimits(SolverTree& t, int tree, SolverWork::TreeSweeps& T, double h) {
  return sweepSweptLimits<&SolverTree::LimitRow::p_lower, &SolverTree::LimitRow::p_upper, true>(
      t, tree, T, h);
}

}  // namespace detail
}  // namespace sim
}  // namespace cga_rigid_sim
