// The variational midpoint's starting guess (tree_midpoint.h): the next step's midpoint velocity
// ν̄ extrapolated over a run of steps of the same h, so that the iteration of the next step
// starts close to its root. Internal: included by tree_integrator_midpoint.cc, whose step
// inlines it.
#pragma once

#include <algorithm>
#include <cmath>

#include "tree/tree_midpoint.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace {

// The next step's ν̄ extrapolated from the sequence of ν̄ (a smooth sequence: ν̄ differs from
// ν(t + h/2) by a smooth O(h²)) over the run of steps with the same h: by the polynomial of
// degree d through the last d + 1 values, in Newton's backward form ν̄_{k+1} ≈ Σ_{j=0..d} ∇^j ν̄_k
// (∇ the backward difference), whose error is ∇^{d+1} ν̄_{k+1}, O(h^{d+1}). The degree is the
// one whose prediction of this step's ν̄ would have been the closest (|∇^{d+1} ν̄_k|∞, smallest
// over d = 1 … kMaxDegree): high while the motion is smooth on the scale of h (doc/decisions.md,
// "the midpoint's starting guess"), low when h is coarse against the motion, where high-degree
// extrapolation amplifies instead of cancelling. Only the start of the iteration depends on it: the
// step converges to the same root (to round-off) from either. The differences are updated in place,
// ∇^j ν̄_k = ∇^{j−1} ν̄_k − ∇^{j−1} ν̄_{k−1}: kDifferences subtractions per coordinate.
inline void Midpoint::predictNext(int nv) {
  const int m = history_filled_ = std::min(history_filled_ + 1, kDifferences);
  differences_.resize(static_cast<std::size_t>(nv) * kDifferences);
  double err[kDifferences] = {};  // err[j] = |∇^j ν̄_k|∞, j < m
  if (m == kDifferences)
    updateDifferences<kDifferences>(nv, err);  // a long run: the loops unrolled
  else
    updateDifferences<0>(nv, err, m);
  if (m < 3) {  // from ν(t + h) and ν̄: ν̄_{k+1} ≈ 2ν(t + h) − ν̄_k
    guess_ = 2.0 * nu_end_ - nu_bar_;
    return;
  }
  int degree = 1;
  for (int d = 2; d + 1 < m && d <= kMaxDegree; ++d)
    if (err[d + 1] < err[degree + 1]) degree = d;
  guess_.resize(nv);
  for (int i = 0; i < nv; ++i) {
    const double* d = differences_.data() + static_cast<std::ptrdiff_t>(i) * kDifferences;
    double x = d[0];
    for (int j = 1; j <= degree; ++j) x += d[j];
    guess_[i] = x;
  }
}

// ∇^j ν̄ for j < m (M: m as a constant, or 0 for the run-time `m`), their norms into err.
template <int M>
inline void Midpoint::updateDifferences(int nv, double* err, int m) {
  if (M != 0) m = M;
  for (int i = 0; i < nv; ++i) {
    double* d = differences_.data() + static_cast<std::ptrdiff_t>(i) * kDifferences;
    double old = d[0];  // ∇^{j−1} ν̄_{k−1}
    d[0] = nu_bar_[i];
#pragma GCC unroll 16
    for (int j = 1; j < m; ++j) {
      const double next_old = d[j];
      d[j] = d[j - 1] - old;
      old = next_old;
      err[j] = std::max(err[j], std::abs(d[j]));
    }
  }
}

}  // namespace
}  // namespace dynamics
}  // namespace cga_rigid_sim
