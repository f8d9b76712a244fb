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
namespace {

// The column M⁻¹ e_k of a limit row, made the first time the row acts in a step.
void makeColumn(const SolverTree& t, SolverTree::LimitRow& r) {
  r.column.setZero(t.nu.size());
  r.column[r.index] = 1.0;
  t.factor.solveInPlace(r.column);
  r.a = r.column[r.index];
}

// One Gauss–Seidel pass over tree t's limit rows: the rates `nu` (ν, or pν with `base` = the
// rates it adds to: ν for the position correction) kept so that q + h (base_k + nu_k) stays
// within [lower, upper], by the accumulated impulses *y_lower ≥ 0 and *y_upper ≤ 0 on the
// joint. Returns the largest change of a rate.
template <Eigen::VectorXd SolverTree::*Nu, double SolverTree::LimitRow::*Lower,
          double SolverTree::LimitRow::*Upper>
double sweepLimits(SolverTree& t, double h, const Eigen::VectorXd* base) {
  double change = 0.0;
  Eigen::VectorXd& nu = t.*Nu;
  for (SolverTree::LimitRow& r : t.limits) {
    const double b = base ? (*base)[r.index] : 0.0;
    const double lo = (r.lower - r.q) / h - b, hi = (r.upper - r.q) / h - b;
    double v = nu[r.index];
    if (r.*Lower == 0.0 && r.*Upper == 0.0 && v >= lo && v <= hi) continue;  // free
    if (r.a == 0.0) makeColumn(t, r);
    if (!(r.a > 0.0)) continue;
    const double yl = std::max(0.0, r.*Lower + (lo - v) / r.a);
    double dy = yl - r.*Lower;
    r.*Lower = yl;
    v += dy * r.a;
    const double yu = std::min(0.0, r.*Upper + (hi - v) / r.a);
    dy += yu - r.*Upper;
    r.*Upper = yu;
    if (dy == 0.0) continue;
    nu.noalias() += dy * r.column;
    change = std::max(change, std::abs(dy * r.a));
  }
  return change;
}

}  // namespace

double sweepVelocityLimits(SolverTree& t, double h) {
  return sweepLimits<&SolverTree::nu, &SolverTree::LimitRow::y_lower,
                     &SolverTree::LimitRow::y_upper>(t, h, nullptr);
}

double sweepPositionLimits(SolverTree& t, double h) {
  return sweepLimits<&SolverTree::pnu, &SolverTree::LimitRow::p_lower,
                     &SolverTree::LimitRow::p_upper>(t, h, &t.nu);
}

}  // namespace detail
}  // namespace sim
}  // namespace cga_rigid_sim
