// The contact solver's internals (contact_solver.h), shared by its files and by nothing else:
// the kernels a sweep runs per contact — the relative velocity at a contact point and an
// impulse's application, written out in scalars — and the parts of a solve, each in the file
// named for it:
//
//   contact_delassus.cc        the rows: basis, lever arms, Delassus blocks (prepareRows)
//   contact_tree_jacobians.cc  a tree side's Jacobian J, the first half of its response M⁻¹ Jᵀ
//   contact_face_blocks.cc     the face blocks (SolverWork::Group)
//   contact_islands.cc         the islands (SolverWork::Island)
//   contact_row_targets.cc     each row's target: touch, gap, impact, compliant spring
//   contact_velocity_sweep.cc  one Gauss–Seidel sweep of an island, friction included
//   contact_tree_limits.cc     the joints' limit rows, swept with the contacts
//   contact_velocity_solve.cc  solveVelocities: the islands' sweeps and their energy guard
//   contact_positions.cc       solvePositions: the position correction
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "contact/contact_solver.h"

namespace cga_rigid_sim {
namespace sim {
namespace detail {

using Twist = SolverWork::Twist;

inline bool onTree(const ContactRow& c) { return c.ta >= 0 || c.tb >= 0; }

// ---- Per contact (the sweeps' whole cost) ----

/// u = J ν of the contact's tree sides (ν, or ν before the impulses), J from
/// contact_tree_jacobians.cc.
template <Eigen::VectorXd SolverTree::*Nu>
Eigen::Vector3d treeVelocity(const std::vector<SolverTree>& trees, const ContactRow& c) {
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  if (c.ta >= 0) u.noalias() += c.ja * (trees[c.ta].*Nu);
  if (c.tb >= 0) u.noalias() -= c.jb * (trees[c.tb].*Nu);
  return u;
}

/// The relative velocity of a's point against b's (slots a, b of `vel`; the dummy for none),
/// written out in scalars: this and applyTo are the sweeps' whole cost, and the compiler
/// vectorises Eigen's 3-vectors here into partial stores that stall the next load.
__attribute__((always_inline)) inline Eigen::Vector3d relativeVelocity(
    const std::vector<Twist>& vel, int a, int b, const ContactRow& c) {
  const double* va = vel[a].v.data();
  const double* wa = vel[a].w.data();
  const double* vb = vel[b].v.data();
  const double* wb = vel[b].w.data();
  const double* ra = c.ra.data();
  const double* rb = c.rb.data();
  return {va[0] - vb[0] + (wa[1] * ra[2] - wa[2] * ra[1]) - (wb[1] * rb[2] - wb[2] * rb[1]),
          va[1] - vb[1] + (wa[2] * ra[0] - wa[0] * ra[2]) - (wb[2] * rb[0] - wb[0] * rb[2]),
          va[2] - vb[2] + (wa[0] * ra[1] - wa[1] * ra[0]) - (wb[0] * rb[1] - wb[1] * rb[0])};
}

/// v += m⁻¹ P, w += I⁻¹ M: an impulse P with moment M about the centre of mass.
__attribute__((always_inline)) inline void kickNet(Twist& t, const SolverWork::Response& resp,
                                                   const Eigen::Vector3d& P,
                                                   const Eigen::Vector3d& M) {
  const Eigen::Matrix3d& I = resp.inv_inertia;
  double* v = t.v.data();
  double* w = t.w.data();
  v[0] += resp.inv_mass * P.x();
  v[1] += resp.inv_mass * P.y();
  v[2] += resp.inv_mass * P.z();
  w[0] += I(0, 0) * M.x() + I(0, 1) * M.y() + I(0, 2) * M.z();
  w[1] += I(1, 0) * M.x() + I(1, 1) * M.y() + I(1, 2) * M.z();
  w[2] += I(2, 0) * M.x() + I(2, 1) * M.y() + I(2, 2) * M.z();
}

/// v += s m P, w += s I⁻¹ (r × P) for one side (s = ±1).
__attribute__((always_inline)) inline void kick(Twist& t, const SolverWork::Response& resp,
                                                const Eigen::Vector3d& r, double px, double py,
                                                double pz) {
  const Eigen::Vector3d P(px, py, pz);
  kickNet(t, resp, P, r.cross(P));
}

/// The impulse P (world axes) at a contact between bodies, +P on a and −P on b, added to `vel`.
/// (A row with a tree side is a face block of its own; its tree sides move the sweeps' z:
/// applySwept, and the position correction's normal alone.)
__attribute__((always_inline)) inline void applyTo(
    std::vector<Twist>& vel, const std::vector<SolverWork::Response>& response, int a, int b,
    const ContactRow& c, const Eigen::Vector3d& P) {
  kick(vel[a], response[a], c.ra, P.x(), P.y(), P.z());
  kick(vel[b], response[b], c.rb, -P.x(), -P.y(), -P.z());
}

/// Calls f(t, run, b) for each tree side of row k: its tree, the coordinates of its link's path
/// to the base in the sweeps' arrays, and whether it is side b.
template <class F>
__attribute__((always_inline)) inline void forTreeSides(const SolverWork::TreeSweeps& T,
                                                        const ContactRow& c, std::size_t k, F&& f) {
  for (int side = 0; side < 2; ++side) {
    const int t = side ? c.tb : c.ta;
    if (t >= 0) f(t, side ? T.side_b[k] : T.side_a[k], side == 1);
  }
}

/// Row k's tree sides' point velocity in the sweeps' coordinates (SolverWork::TreeSweeps):
/// J ν₀ + Yᵀ z (`Z` = z), or Yᵀ Δz alone (kFromStart false; `Z` holding the change Δz). Over the
/// coordinates from the sides' links to the base only, in scalars as relativeVelocity is.
template <bool kFromStart, std::vector<Eigen::VectorXd> SolverWork::TreeSweeps::*Z>
__attribute__((always_inline)) inline Eigen::Vector3d sweptTreeVelocity(
    const SolverWork::TreeSweeps& T, const ContactRow& c, std::size_t k) {
  double u0 = 0.0, u1 = 0.0, u2 = 0.0;
  if (kFromStart) u0 = T.u0[k].x(), u1 = T.u0[k].y(), u2 = T.u0[k].z();
  const int* coordinate = T.coordinate.data();
  const Eigen::Vector3d* y = T.y.data();
  forTreeSides(T, c, k, [&](int t, const SolverWork::TreeSweeps::Run& run, bool b) {
    const double* z = (T.*Z)[t].data();
    double v0 = 0.0, v1 = 0.0, v2 = 0.0;
    for (int i = run.first; i < run.first + run.size; ++i) {
      const double zi = z[coordinate[i]];
      v0 += y[i].x() * zi;
      v1 += y[i].y() * zi;
      v2 += y[i].z() * zi;
    }
    if (b) v0 = -v0, v1 = -v1, v2 = -v2;
    u0 += v0, u1 += v1, u2 += v2;
  });
  return {u0, u1, u2};
}

/// The impulse P on row k's tree sides in the sweeps' coordinates: z += Y P on side a, −Y P on b.
__attribute__((always_inline)) inline void applyToSweptTrees(SolverWork::TreeSweeps& T,
                                                             const ContactRow& c, std::size_t k,
                                                             const Eigen::Vector3d& P) {
  const int* coordinate = T.coordinate.data();
  const Eigen::Vector3d* y = T.y.data();
  forTreeSides(T, c, k, [&](int t, const SolverWork::TreeSweeps::Run& run, bool b) {
    double* z = T.z[t].data();
    const double p0 = b ? -P.x() : P.x(), p1 = b ? -P.y() : P.y(), p2 = b ? -P.z() : P.z();
    for (int i = run.first; i < run.first + run.size; ++i)
      z[coordinate[i]] += y[i].x() * p0 + y[i].y() * p1 + y[i].z() * p2;
  });
}

/// The impulse P at row k, +P on a and −P on b, in the velocity sweeps: the bodies' velocities
/// as applyTo, a tree side's z.
__attribute__((always_inline)) inline void applySwept(SolverWork& work, const ContactRow& c,
                                                      std::size_t k, const Eigen::Vector3d& P) {
  const int a = work.a[k], b = work.b[k];
  kick(work.vel[a], work.response[a], c.ra, P.x(), P.y(), P.z());
  kick(work.vel[b], work.response[b], c.rb, -P.x(), -P.y(), -P.z());
  if (onTree(c)) applyToSweptTrees(work.tree_sweeps, c, k, P);
}

// ---- Per island ----

/// Calls f(k, row) for the island's rows, in their order.
template <class F>
void forRows(const SolverWork& work, std::vector<ContactRow>& rows, const SolverWork::Island& I,
             F&& f) {
  for (int q = I.first_group; q < I.first_group + I.groups; ++q) {
    const SolverWork::Group& g = work.groups[work.island_group[q]];
    for (int k = g.first; k < g.first + g.size; ++k) f(static_cast<std::size_t>(k), rows[k]);
  }
}

/// Calls f(slot) for the island's bodies.
template <class F>
void forBodies(const SolverWork& work, const SolverWork::Island& I, F&& f) {
  for (int q = I.first_body; q < I.first_body + I.bodies; ++q) f(work.island_body[q]);
}

/// Calls f(tree) for the island's trees.
template <class F>
void forTrees(const SolverWork& work, std::vector<SolverTree>& trees, const SolverWork::Island& I,
              F&& f) {
  for (int q = I.first_tree; q < I.first_tree + I.trees; ++q) f(trees[work.island_tree[q]]);
}

/// The largest change of a contact point's (pseudo-)velocity since vel_sweep, over the
/// island's bodies.
inline double bodyChange(const SolverWork& work, const SolverWork::Island& I) {
  double change = 0.0;
  for (int q = I.first_body; q < I.first_body + I.bodies; ++q) {
    const int s = work.island_body[q];
    change =
        std::max(change, (work.vel[s].v - work.vel_sweep[s].v).norm() +
                             work.response[s].reach * (work.vel[s].w - work.vel_sweep[s].w).norm());
  }
  return change;
}

// ---- The parts of a solve ----

/// Tree sides (contact_tree_jacobians.cc): a side on a link of a tree takes the Jacobian of
/// the contact point (c.ta/c.tb and c.ja/c.jb set, its body slot cleared); two links of one
/// tree share ν, so side a keeps J_a − J_b.
void takeTreeSides(const std::vector<SolverBody>& bodies, const std::vector<SolverTree>& trees,
                   const Eigen::Vector3d& point_W, ContactRow& c);
/// Adds the tree sides' J M⁻¹ Jᵀ to the Delassus block Kc (basis n, t1, t2; its upper triangle
/// is kept) and to c.k_n, keeps them in c.ka, c.kb and the first half of their responses,
/// Y = L⁻ᵀ Jᵀ, in c.wa, c.wb: the sweeps work on Y (contact_tree_jacobians.cc).
void addTreeSides(const std::vector<SolverTree>& trees, ContactRow& c, Eigen::Matrix3d& Kc);

/// The face blocks of the rows (contact_face_blocks.cc).
void makeGroups(std::vector<ContactRow>& rows, SolverWork& work);
/// The islands of the face blocks (contact_islands.cc).
void makeIslands(const std::vector<ContactRow>& rows, int n_trees, SolverWork& work);

/// Row k's target from the velocities before any contact impulse; `bounce`: impacts take
/// their restitution (contact_row_targets.cc).
void setTarget(const SolverSettings& st, const SolverWork& work,
               const std::vector<SolverTree>& trees, bool bounce, std::size_t k, ContactRow& c);

/// One Gauss–Seidel sweep of island I's contacts and its trees' limit rows; returns the
/// largest change of a contact point's velocity, or of a limited rate (contact_velocity_sweep.cc).
/// Once a body's or a rate's change reaches `tolerance` the trees' contact points are not
/// measured: the sweep is then known not to have converged, and what is returned is that
/// change (≥ tolerance), not the largest.
double sweepIsland(const SolverSettings& st, std::vector<SolverTree>& trees,
                   std::vector<ContactRow>& rows, SolverWork& work, const SolverWork::Island& I,
                   bool patch, double tolerance);

/// The sweeps' coordinates of island I's trees (SolverWork::TreeSweeps): z = 0, and the runs of
/// its rows' tree sides (from c.wa, c.wb, the first half of their responses) and of its trees'
/// limit rows (contact_velocity_solve.cc, contact_tree_limits.cc); the velocity sweeps' and the
/// position correction's.
void loadTreeSweeps(const std::vector<SolverTree>& trees, const std::vector<ContactRow>& rows,
                    SolverWork& work, const SolverWork::Island& I);
void loadSweptLimits(const SolverTree& t, int tree, SolverWork::TreeSweeps& T);
/// … and back: ν ← ν₀ + L⁻¹ z for island I's trees, after the sweeps.
void finishTreeSweeps(std::vector<SolverTree>& trees, SolverWork& work,
                      const SolverWork::Island& I);
/// L⁻¹ z of tree t (index in T), the change the sweeps made (the position correction: pν), held
/// in T's scratch until its next use.
Eigen::Ref<const Eigen::VectorXd> sweptChange(const SolverTree& tree, SolverWork::TreeSweeps& T,
                                              int t);

/// One pass over tree t's (index `tree`) limit rows on z, in the velocity sweeps (ν = ν₀ + L⁻¹ z)
/// or in the position correction's (pν = L⁻¹ z, on top of ν); returns the largest change of a
/// rate (contact_tree_limits.cc).
double sweepVelocityLimits(SolverTree& t, int tree, SolverWork::TreeSweeps& T, double h);
double sweepPositionLimits(SolverTree& t, int tree, SolverWork::TreeSweeps& T, double h);

}  // namespace detail
}  // namespace sim
}  // namespace cga_rigid_sim
