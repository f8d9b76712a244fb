// One Gauss–Seidel sweep of an island (doc/contacts.md#solver): per face block its normal
// impulses together, per single contact its normal impulse; then each contact's friction (the
// Coulomb disc) and patch couples; then the island's trees' limit rows. Each step of a sweep is
// a projection that never adds energy.
#include <algorithm>
#include <cmath>

#include "contact/contact_patch.h"
#include "contact/contact_solver_internals.h"

namespace cga_rigid_sim {
namespace sim {
namespace detail {
namespace {

// Friction: the impulse that stops the sliding at relative velocity u, projected onto the
// cone's disc; updates λ_t and returns its change. `relax` > 1 over-relaxes the step (then
// projects onto the disc again): λ_t + relax (λ_t' − λ_t). It has the same fixed points (where
// the step is zero, so is the relaxed one; on the rim a relaxed step that projects back onto
// λ_t would need a step pointing out of the disc, which a projected λ_t' cannot have).
__attribute__((always_inline)) inline Eigen::Vector2d frictionStep(ContactRow& c,
                                                                   const Eigen::Vector3d& u,
                                                                   double relax = 1.0) {
  const Eigen::Vector2d u_t = Eigen::Vector2d(c.t1.dot(u), c.t2.dot(u)) - c.target_t;
  const double tmax = c.mu * c.lambda_n;
  Eigen::Vector2d lt = c.lambda_t - c.k_tt_inv * u_t;  // sticks, if the cone allows
  if (lt.squaredNorm() > tmax * tmax) {                // slides
    lt = c.lambda_t - u_t * c.inv_k_t;
    const double t = lt.norm();
    if (t > tmax) lt *= t > 0 ? tmax / t : 0.0;
  }
  if (relax != 1.0) {
    lt = c.lambda_t + relax * (lt - c.lambda_t);
    const double t2 = lt.squaredNorm();
    if (t2 > tmax * tmax) lt *= tmax > 0 ? tmax / std::sqrt(t2) : 0.0;
  }
  const Eigen::Vector2d dt = lt - c.lambda_t;
  c.lambda_t = lt;
  return dt;
}

// The over-relaxation of the friction at a face's corners (successive over-relaxation): each
// corner's friction step tilts the box and changes its neighbours' slip, and plain Gauss–Seidel
// (1) converges slowly on the columns of a landed pile. Single contacts keep the exact step: a
// rolling ball's one contact converges in one sweep, and a relaxed step would only make it
// oscillate. Why 1.5: doc/decisions.md.
constexpr double kFaceFrictionRelaxation = 1.5;

// The friction (and patch couples) of a block's corners, corner by corner.
void sweepFriction(const SolverWork::Group& g, SolverWork& work, std::vector<ContactRow>& rows,
                   const ContactModel& model, bool patch) {
  const int a = work.a[g.first], b = work.b[g.first];
  for (int i = 0; i < g.size; ++i) {
    ContactRow& c = rows[g.first + i];
    const Eigen::Vector2d dt =
        frictionStep(c, relativeVelocity(work.vel, a, b, c), kFaceFrictionRelaxation);
    if (dt.x() != 0.0 || dt.y() != 0.0)
      applyTo(work.vel, work.response, a, b, c, dt.x() * c.t1 + dt.y() * c.t2);
    if (patch) patchStep(model, c, work.vel[a], work.vel[b], work.response[a], work.response[b]);
  }
}

// One sweep over a block of a face's corners: their normal impulses together (the block's
// pseudo-inverse brings every normal velocity to its target at once), or one by one when that
// would make one negative; then each corner's friction. Kept out of the sweep's loop, which
// inlines the single contacts' update instead (doc/decisions.md).
__attribute__((noinline)) void sweepGroup(const SolverWork::Group& g, SolverWork& work,
                                          std::vector<ContactRow>& rows, const ContactModel& model,
                                          bool patch) {
  const int a = work.a[g.first], b = work.b[g.first];
  if (rows[g.first].compliant) {  // the springs' impulses are fixed: friction alone
    for (int i = 0; i < g.size; ++i) {
      ContactRow& c = rows[g.first + i];
      const double dn = c.lambda_fixed - c.lambda_n;
      c.lambda_n = c.lambda_fixed;
      if (dn != 0.0) applyTo(work.vel, work.response, a, b, c, dn * c.n);
    }
    sweepFriction(g, work, rows, model, patch);
    return;
  }
  Eigen::Vector4d r = Eigen::Vector4d::Zero();
  for (int i = 0; i < g.size; ++i) {
    const ContactRow& c = rows[g.first + i];
    r(i) = c.target - c.n.dot(relativeVelocity(work.vel, a, b, c));
  }
  const Eigen::Vector4d d = g.pinv * r;
  bool feasible = true;
  for (int i = 0; i < g.size; ++i) feasible = feasible && rows[g.first + i].lambda_n + d(i) >= 0;
  if (feasible) {  // all at once: one kick per side with the block's net impulse and moment
    Eigen::Vector3d P = Eigen::Vector3d::Zero(), Ma = P, Mb = P;
    for (int i = 0; i < g.size; ++i) {
      ContactRow& c = rows[g.first + i];
      c.lambda_n += d(i);
      const Eigen::Vector3d Pi = d(i) * c.n;
      P += Pi;
      Ma += c.ra.cross(Pi);
      Mb += c.rb.cross(Pi);
    }
    kickNet(work.vel[a], work.response[a], P, Ma);
    kickNet(work.vel[b], work.response[b], -P, -Mb);
  }
  for (int i = 0; i < g.size && !feasible; ++i) {
    ContactRow& c = rows[g.first + i];
    // Gauss–Seidel within the block.
    const double u_n = c.n.dot(relativeVelocity(work.vel, a, b, c));
    const double dn = std::max(0.0, c.lambda_n + (c.target - u_n) * c.inv_k_nn) - c.lambda_n;
    c.lambda_n += dn;
    if (dn != 0.0) applyTo(work.vel, work.response, a, b, c, dn * c.n);
  }
  sweepFriction(g, work, rows, model, patch);
}

// One sweep over a single contact: its normal impulse, then its friction at the velocity after
// it, applied together; then its patch couples. Inlined into the sweep's loop: a call per
// contact and sweep would cost a fair part of the update itself.
__attribute__((always_inline)) inline void sweepContact(const SolverSettings& st, SolverWork& work,
                                                        std::vector<ContactRow>& rows,
                                                        std::size_t k, bool patch) {
  ContactRow& c = rows[k];
  const int a = work.a[k], b = work.b[k];
  // A tree against the ground or a static body (or against itself) has no body side: both
  // slots are the dummy, whose velocity is zero and which takes no kick.
  const bool trees_only = onTree(c) && a == b;
  // Normal: the impulse that brings u_n to its target, kept ≥ 0.
  Eigen::Vector3d u = trees_only ? Eigen::Vector3d::Zero() : relativeVelocity(work.vel, a, b, c);
  if (onTree(c)) u += sweptTreeVelocity<true, &SolverWork::TreeSweeps::z>(work.tree_sweeps, c, k);
  const double ln = c.compliant ? c.lambda_fixed
                                : std::max(0.0, c.lambda_n + (c.target - c.n.dot(u)) * c.inv_k_nn);
  const double dn = ln - c.lambda_n;
  c.lambda_n = ln;
  u += dn * c.k_n;  // the velocity after it, without applying it yet
  const Eigen::Vector2d dt = frictionStep(c, u);
  // Both at once: one application per contact and sweep.
  if (dn != 0.0 || dt.x() != 0.0 || dt.y() != 0.0) {
    const Eigen::Vector3d P = dn * c.n + dt.x() * c.t1 + dt.y() * c.t2;
    if (trees_only)
      applyToSweptTrees(work.tree_sweeps, c, k, P);
    else
      applySwept(work, c, k, P);
  }
  if (patch && !onTree(c))
    patchStep(st.model, c, work.vel[a], work.vel[b], work.response[a], work.response[b]);
}

}  // namespace

double sweepIsland(const SolverSettings& st, std::vector<SolverTree>& trees,
                   std::vector<ContactRow>& rows, SolverWork& work, const SolverWork::Island& I,
                   bool patch, double tolerance) {
  SolverWork::TreeSweeps& T = work.tree_sweeps;
  if (I.trees > 0) T.swept_island = &I, T.swept_rows = &rows;  // (loadTreeSweeps made the runs)
  forBodies(work, I, [&](int s) { work.vel_sweep[s] = work.vel[s]; });
  for (int q = I.first_tree; q < I.first_tree + I.trees; ++q)
    T.z_sweep[work.island_tree[q]] = T.z[work.island_tree[q]];
  for (int q = I.first_group; q < I.first_group + I.groups; ++q) {
    const SolverWork::Group& g = work.groups[work.island_group[q]];
    if (g.size > 1)
      sweepGroup(g, work, rows, st.model, patch);
    else
      sweepContact(st, work, rows, g.first, patch);
  }
  // The joints' limits, solved with the contacts (a rate's change counts as a point's at 1 m).
  double limit_change = 0.0;
  for (int q = I.first_tree; q < I.first_tree + I.trees; ++q) {
    const int t = work.island_tree[q];
    limit_change = std::max(limit_change, sweepVelocityLimits(trees[t], t, T, st.h));
  }
  double change = std::max(bodyChange(work, I), limit_change);
  // A tree's change as its contact points see it, unless the sweep is already known not to
  // have converged (a tree's stops take many sweeps: this is most of them).
  if (I.trees > 0 && change < tolerance) {
    for (int q = I.first_tree; q < I.first_tree + I.trees; ++q) {
      const int t = work.island_tree[q];
      T.z_sweep[t] = T.z[t] - T.z_sweep[t];
    }
    forRows(work, rows, I, [&](std::size_t k, ContactRow& c) {
      if (onTree(c))
        change = std::max(
            change, sweptTreeVelocity<false, &SolverWork::TreeSweeps::z_sweep>(T, c, k).norm());
    });
  }
  return change;
}

}  // namespace detail
}  // namespace sim
}  // namespace cga_rigid_sim
