// Newton's method on a tree's contact cost (contact_tree_newton.h, doc/contacts.md#resting-trees).
#include "contact/contact_tree_newton.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cga_rigid_sim {
namespace sim {
namespace {

// Trees with at most this many coordinates build the Hessian row by row over each row's
// nonzeros (their indices found once per solve); larger ones by one dense rank update.
constexpr int kSparseMax = 256;
// A downdate that leaves a pivot's square below this fraction of what it was keeps fewer than
// 16 − 9 = 7 of its digits: the factor is made whole instead. A contact row weighs ~1/ε = 1e6
// times the rest of its pivot (contact_resting_tree.cc), so removing one leaves ~1e-6.
constexpr double kMinPivotRatio = 1e-9;

}  // namespace

void TreeNewton::resize(int m, int s, int n) {
  if (g.rows() < m || g.cols() != n) g.resize(std::max<Eigen::Index>(m, 2 * g.rows()), n);
  if (r.size() < m) {
    r.resize(g.rows());
    D.resize(g.rows());
    beta.resize(g.rows());
  }
  if (static_cast<int>(single.size()) < s) single.resize(s);
  if (z_.size() < m + s) {
    z_.resize(g.rows() + static_cast<Eigen::Index>(single.size()));
    gd_.resize(z_.size());
    re_.resize(z_.size());
    weighted_.resize(z_.size());
    active_.resize(z_.size());
    crossing_.reserve(z_.size());
    changed_.reserve(z_.size());
  }
  if (S_.rows() != n || S_.cols() < m) S_.resize(n, g.rows());
  if (H_.rows() != n) {
    H_.resize(n, n);
    grad_.resize(n);
    delta_.resize(n);
    work_.resize(n);
    dnu_.resize(n);
    start_.resize(n);
    mdnu_.resize(n);
    x_.setZero(n);
    dg_.resize(n);
  }
  rows = m;
  n_single = s;
  nv = n;
}

bool TreeNewton::factorHessian() {
  const int n = nv;
  inv_diag_.resize(n);
  nz_.resize(static_cast<std::size_t>(n) * n);
  nz_count_.resize(n);
  for (int k = n - 1; k >= 0; --k) {
    const double d = H_(k, k);
    if (!(d > 0.0 && std::isfinite(d))) return false;
    const double l = std::sqrt(d), inv = 1.0 / l;
    H_(k, k) = l;
    inv_diag_[k] = inv;
    // Row k of L left of the diagonal: its nonzeros, scaled.
    int* nz = nz_.data() + static_cast<std::size_t>(k) * n;
    int count = 0;
    for (int j = 0; j < k; ++j) {
      double& x = H_(k, j);
      if (x == 0.0) continue;
      x *= inv;
      nz[count++] = j;
    }
    nz_count_[k] = count;
    // H_ij −= L_ki L_kj over those pairs (i ≥ j: the lower triangle).
    for (int a = 0; a < count; ++a) {
      const int i = nz[a];
      const double li = H_(k, i);
      for (int b = 0; b <= a; ++b) H_(i, nz[b]) -= li * H_(k, nz[b]);
    }
  }
  return true;
}

void TreeNewton::solveHessian(Eigen::VectorXd& x) const {
  const int n = nv;
  for (int i = n - 1; i >= 0; --i) {  // Lᵀ y = x, from the last coordinate in
    const double y = x[i] * inv_diag_[i];
    x[i] = y;
    const int* nz = nz_.data() + static_cast<std::size_t>(i) * n;
    for (int a = 0; a < nz_count_[i]; ++a) x[nz[a]] -= H_(i, nz[a]) * y;
  }
  for (int i = 0; i < n; ++i) {  // L z = y, from the first out
    double z = x[i];
    const int* nz = nz_.data() + static_cast<std::size_t>(i) * n;
    for (int a = 0; a < nz_count_[i]; ++a) z -= H_(i, nz[a]) * x[nz[a]];
    x[i] = z * inv_diag_[i];
  }
}

bool TreeNewton::rankOne(int top, double sign) {
  // H ± x xᵀ = L'ᵀ L' row by row from the last coordinate in (the rows of L are Cholesky's
  // columns in the reversed order): row k and x are turned (a hyperbolic turn for −) so that
  // x loses its k-th entry, which moves x onto row k's columns j < k only — a point's
  // Jacobian's path to the base, L's own structure, when x is a contact row's: the classical
  // Cholesky update and downdate (Gill, Golub, Murray and Saunders, "Methods for modifying
  // matrix factorizations", 1974).
  const int n = nv;
  bool ok = true;
  for (int k = top; k >= 0; --k) {
    const double xk = x_[k];
    if (xk == 0.0) continue;
    x_[k] = 0.0;
    if (!ok) continue;  // x_ is still cleared, for the next call
    const double l = H_(k, k), l2 = l * l;
    const double r2 = l2 + sign * xk * xk;
    if (!(r2 > kMinPivotRatio * l2)) {
      ok = false;
      continue;
    }
    const double r = std::sqrt(r2), c = r / l, s = xk / l, inv_c = l / r;
    H_(k, k) = r;
    inv_diag_[k] = 1.0 / r;
    int* nz = nz_.data() + static_cast<std::size_t>(k) * n;
    int count = 0;
    for (int j = 0; j < k; ++j) {
      double& lkj = H_(k, j);
      const double xj = x_[j];
      if (lkj == 0.0 && xj == 0.0) continue;
      lkj = (lkj + sign * s * xj) * inv_c;
      x_[j] = c * xj - s * lkj;
      if (lkj != 0.0) nz[count++] = j;
    }
    nz_count_[k] = count;
  }
  return ok;
}

bool TreeNewton::updateFactor() {
  const int m = rows;
  for (const int i : changed_) {
    const double sign = active_[i] ? 1.0 : -1.0;
    int top = -1;
    if (i < m) {
      const double w = std::sqrt(D[i]);
      if (nv <= kSparseMax) {
        for (int a = row_nz_begin_[i]; a < row_nz_begin_[i + 1]; ++a) {
          const int c = row_nz_[a];
          x_[c] = w * g(i, c);
          top = std::max(top, c);
        }
      } else {
        for (int c = 0; c < nv; ++c) {
          if (g(i, c) == 0.0) continue;
          x_[c] = w * g(i, c);
          top = c;
        }
      }
    } else {
      const Single& q = single[i - m];
      x_[q.index] = std::sqrt(q.D);
      top = q.index;
    }
    ++rank_updates;
    if (!rankOne(top, sign)) return false;
  }
  return true;
}

void TreeNewton::splitRows(double dMd, double dMx) {
  const int m = rows + n_single;
  fixed_slope_ = dMx;
  fixed_curvature_ = dMd;
  crossing_.clear();
  for (int i = 0; i < m; ++i) {
    const double zi = z_[i], gi = gd_[i];
    if (zi >= 0 ? gi >= 0 : gi <= 0) {  // the same side of its kink for every α ≥ 0
      if (zi < 0) {
        const double Di = i < rows ? D[i] : single[i - rows].D;
        fixed_slope_ += Di * gi * zi;
        fixed_curvature_ += Di * gi * gi;
      }
    } else {
      crossing_.push_back(i);
    }
  }
}

double TreeNewton::slope(double alpha, double* curvature) const {
  double f = fixed_slope_ + alpha * fixed_curvature_, c = fixed_curvature_;
  for (const int i : crossing_) {
    const double zi = z_[i] + alpha * gd_[i];
    if (zi < 0) {
      const double Di = i < rows ? D[i] : single[i - rows].D;
      f += Di * gd_[i] * zi;
      c += Di * gd_[i] * gd_[i];
    }
  }
  *curvature = c;
  return f;
}

bool TreeNewton::factorActive(const Eigen::MatrixXd& M) {
  const int m = rows, s = n_single, n = nv;
  const auto G = g.topLeftCorner(m, n);
  H_.triangularView<Eigen::Lower>() = M.triangularView<Eigen::Lower>();
  if (n <= kSparseMax) {
    // D_i g_iᵀ g_i over the coordinates a row moves: a point's Jacobian has nonzeros only on
    // the joints between its link and the base (a foot: the base's six and its leg's).
    for (int i = 0; i < m; ++i) {
      if (!active_[i]) continue;
      const int* nz = row_nz_.data() + row_nz_begin_[i];
      const int k = row_nz_begin_[i + 1] - row_nz_begin_[i];
      // Row by row of H_'s lower triangle (nz is ascending).
      double* dg = dg_.data();
      for (int a = 0; a < k; ++a) dg[a] = D[i] * G(i, nz[a]);
      for (int b = 0; b < k; ++b) {
        const double gb = G(i, nz[b]);
        double* row = H_.data() + static_cast<std::ptrdiff_t>(nz[b]) * n;
        for (int a = 0; a <= b; ++a) row[nz[a]] += dg[a] * gb;
      }
    }
  } else {
    int na = 0;
    for (int i = 0; i < m; ++i)
      if (active_[i]) S_.col(na++).noalias() = std::sqrt(D[i]) * G.row(i).transpose();
    if (na > 0) H_.selfadjointView<Eigen::Lower>().rankUpdate(S_.leftCols(na));
  }
  for (int j = 0; j < s; ++j)
    if (active_[m + j]) H_(single[j].index, single[j].index) += single[j].D;
  factored_ = factorHessian();
  ++factorisations;
  return factored_;
}

void TreeNewton::addRowsGradient() {
  const int m = rows, s = n_single;
  for (int i = 0; i < m; ++i) weighted_[i] = active_[i] ? D[i] * z_[i] : 0.0;
  grad_.noalias() += g.topLeftCorner(m, nv).transpose() * weighted_.head(m);
  for (int j = 0; j < s; ++j)
    if (active_[m + j]) grad_[single[j].index] += single[j].D * z_[m + j] * single[j].sign;
}

void TreeNewton::residuals(const Eigen::VectorXd& nu) {
  const int m = rows, s = n_single;
  z_.head(m).noalias() = g.topLeftCorner(m, nv) * nu;
  z_.head(m) -= re_.head(m);
  for (int j = 0; j < s; ++j) z_[m + j] = single[j].sign * nu[single[j].index] - re_[m + j];
}

double TreeNewton::cost(const Eigen::MatrixXd& M, const Eigen::VectorXd& nu_f,
                        const Eigen::VectorXd& nu) {
  residuals(nu);
  dnu_ = nu - nu_f;
  work_.noalias() = M.selfadjointView<Eigen::Lower>() * dnu_;
  double c = dnu_.dot(work_);
  for (int i = 0; i < rows + n_single; ++i)
    if (z_[i] < 0) c += (i < rows ? D[i] : single[i - rows].D) * z_[i] * z_[i];
  return 0.5 * c;
}

int TreeNewton::predict(const Eigen::MatrixXd& M, const Eigen::VectorXd& nu_f,
                        Eigen::VectorXd& nu) {
  const int m = rows, s = n_single;
  bool any = false;
  for (int i = 0; i < m; ++i) any = (active_[i] = beta[i] > 0) || any;
  for (int j = 0; j < s; ++j) any = (active_[m + j] = single[j].beta > 0) || any;
  if (!any) return 0;
  // The gradient of the quadratic those rows make, at ν (cost() leaves z_ there and
  // M (ν − ν_f) in work_), and its minimiser.
  const double before = cost(M, nu_f, nu);
  grad_ = work_;
  addRowsGradient();
  if (!factorActive(M)) return -1;
  delta_ = -grad_;
  solveHessian(delta_);
  delta_ += nu;
  if (cost(M, nu_f, delta_) < before) nu = delta_;
  return 1;
}

int TreeNewton::minimise(const Eigen::MatrixXd& M, const Eigen::VectorXd& nu_f, Eigen::VectorXd& nu,
                         double tolerance, int max_steps, bool from_impulses) {
  const int m = rows, s = n_single, n = nv;
  const auto G = g.topLeftCorner(m, n);
  int step = 0;
  if (from_impulses) {
    const int predicted = predict(M, nu_f, nu);
    if (predicted < 0) return -1;
    step += predicted;
  }
  bool carried = false;  // z_, dnu_ and mdnu_ carried along the last step instead of computed
  while (step < max_steps) {
    ++step;
    // The residuals z_i = g_i ν − r_i, the gradient and, over the active rows (z_i < 0), the
    // Hessian M + Σ D_i g_iᵀ g_i.
    if (!carried) {
      residuals(nu);
      dnu_ = nu - nu_f;
      mdnu_.noalias() = M.selfadjointView<Eigen::Lower>() * dnu_;
    }
    grad_ = mdnu_;
    // The active rows; the Hessian depends on them alone (and on M): when they are those of
    // the factor kept from the last step (of this solve), it is reused.
    changed_.clear();
    for (int i = 0; i < m + s; ++i) {
      const char a = z_[i] < 0;
      if (a != active_[i]) changed_.push_back(i);
      active_[i] = a;
    }
    addRowsGradient();
    // A few rows in or out: the factor updated row by row (spoilt by a downdate: made whole).
    if (!factored_ || !changed_.empty()) {
      const bool update = factored_ && static_cast<int>(changed_.size()) <= max_rank_updates;
      if (!(update && updateFactor()) && !factorActive(M)) return -1;
    }
    delta_ = -grad_;
    solveHessian(delta_);
    // The exact line search: φ(α) is piecewise quadratic, φ' piecewise linear and
    // nondecreasing; its root by Newton steps kept inside a bracket.
    gd_.head(m).noalias() = G * delta_;
    for (int j = 0; j < s; ++j) gd_[m + j] = single[j].sign * delta_[single[j].index];
    double full = 0;  // the full step's largest change of a row's velocity
    for (int i = 0; i < m + s; ++i) full = std::max(full, std::abs(gd_[i]));
    if (full <= tolerance) {  // converged to round-off: no line search needed
      nu += delta_;
      break;
    }
    work_.noalias() = M.selfadjointView<Eigen::Lower>() * delta_;
    const double dMd = delta_.dot(work_), dMx = dnu_.dot(work_);
    double c = 0;
    splitRows(dMd, dMx);
    const double f0 = slope(0.0, &c);
    if (!(f0 < 0)) break;  // no descent left: the minimiser, to round-off
    double lo = 0, hi = -1, alpha = 1;
    for (int it = 0; it < 60; ++it) {
      const double f = slope(alpha, &c);
      if (std::abs(f) <= 1e-14 * std::abs(f0)) break;
      (f < 0 ? lo : hi) = alpha;
      double next = alpha - f / c;
      if (hi >= 0 && !(next > lo && next < hi)) next = 0.5 * (lo + hi);
      if (next == alpha) break;
      alpha = next;
    }
    nu.noalias() += alpha * delta_;
    // A full step that leaves the active rows as they were has reached the minimiser of the
    // quadratic they make, which is the cost's (to round-off; with an updated factor to the
    // updates' round-off, which the rounds' impulses then check).
    bool same = std::abs(alpha - 1.0) < 1e-9;
    double moved = 0;
    for (int i = 0; i < m + s; ++i) {
      moved = std::max(moved, std::abs(alpha * gd_[i]));
      same = same && ((z_[i] + alpha * gd_[i] < 0) == (active_[i] != 0));
    }
    if (same || moved <= tolerance) break;
    // The next step's residuals and M (ν − ν_f) from this one's products along δ.
    z_.head(m + s) += alpha * gd_.head(m + s);
    dnu_.noalias() += alpha * delta_;
    mdnu_.noalias() += alpha * work_;
    carried = true;
  }
  return step;
}

int TreeNewton::solve(const Eigen::MatrixXd& M, const Eigen::VectorXd& nu_f, Eigen::VectorXd& nu,
                      double tolerance, int max_steps, int max_rounds) {
  const int m = rows, s = n_single;
  const auto G = g.topLeftCorner(m, nv);
  int steps = 0;
  factored_ = false;  // a new M and new rows
  // Each row's nonzero coordinates, for the Hessian's rebuilds in this solve.
  row_nz_begin_.resize(m + 1);
  row_nz_.clear();
  for (int i = 0; i < m && nv <= kSparseMax; ++i) {
    row_nz_begin_[i] = static_cast<int>(row_nz_.size());
    for (int c = 0; c < nv; ++c)
      if (G(i, c) != 0.0) row_nz_.push_back(c);
  }
  row_nz_begin_[m] = static_cast<int>(row_nz_.size());
  double last_missed = std::numeric_limits<double>::infinity();
  for (int round = 0; round < max_rounds; ++round) {
    // The targets shifted by the impulses so far: r_i + β_i / D_i.
    for (int i = 0; i < m; ++i) re_[i] = r[i] + beta[i] / D[i];
    for (int j = 0; j < s; ++j) re_[m + j] = single[j].r + single[j].beta / single[j].D;
    // The first round starts from the minimiser of the quadratic of the rows the warm start
    // loads (the last step's active set); when that start walks into more kinks than a round
    // may take, the round runs again from ν as given.
    const bool first = round == 0;
    if (first) start_ = nu;
    int taken = minimise(M, nu_f, nu, 1e-3 * tolerance, max_steps, first);
    if (first && taken == max_steps) {
      steps += taken;
      nu = start_;
      factored_ = false;
      taken = minimise(M, nu_f, nu, 1e-3 * tolerance, max_steps, false);
    }
    // A round that did not reach its minimiser gives impulses D_i times its error: refused.
    if (taken < 0 || taken == max_steps) return -1;
    steps += taken;
    // The new impulses β_i = max(0, β_i + D_i (r_i − g_i ν)); their change over D_i is how far
    // the round's minimiser missed the rows' targets.
    z_.head(m).noalias() = G * nu;
    double missed = 0;
    for (int i = 0; i < m; ++i) {
      const double b = D[i] * std::max(0.0, re_[i] - z_[i]);
      missed = std::max(missed, std::abs(b - beta[i]) / D[i]);
      beta[i] = b;
    }
    for (int j = 0; j < s; ++j) {
      Single& q = single[j];
      const double b = q.D * std::max(0.0, re_[m + j] - q.sign * nu[q.index]);
      missed = std::max(missed, std::abs(b - q.beta) / q.D);
      q.beta = b;
    }
    // Done, or no longer converging: rows that cannot all hold (a stop already passed and a
    // contact that keeps the joint there) let their impulses grow by the same amount each
    // round, however many rounds run.
    if (missed <= tolerance || missed > 0.5 * last_missed) break;
    last_missed = missed;
  }
  return steps;
}

}  // namespace sim
}  // namespace cga_rigid_sim
