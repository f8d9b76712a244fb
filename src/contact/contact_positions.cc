// The position correction (doc/contacts.md#solver, #trees): pseudo-velocities pv, pw (and a
// tree's pν) that remove a fraction of each overlap beyond the slop over the step, solved by
// Gauss–Seidel on the normals alone (no friction), island by island on the velocity solve's
// islands. They move the poses, not the momenta; a tree's correction is capped per step.
#include <algorithm>

#include "contact/contact_resting_tree.h"
#include "contact/contact_solver_internals.h"

namespace cga_rigid_sim {
namespace sim {
namespace {
// An overlap past the slop by more than this (m) has a one-tree island's correction solved
// exactly: a foot jammed between the floor and its own leg is millimetres deep, a resting one
// within a few micrometres of the slop, where a correction solved exactly a step cost several
// Newton steps for what the sweeps do as well (doc/decisions.md#a-resting-robots-island).
constexpr double kExactCorrectionExcess = 1e-4;
}  // namespace

namespace detail {
namespace {

// Each row's target pseudo-velocity: the fraction `correction` of its overlap beyond the slop
// over one step (none for a compliant contact, whose spring holds the overlap); returns the
// largest.
double setBiases(const SolverSettings& st, std::vector<ContactRow>& rows) {
  double max_bias = 0.0;
  for (ContactRow& c : rows) {
    c.bias = c.depth > st.slop && !c.compliant ? st.correction * (c.depth - st.slop) / st.h : 0.0;
    c.lambda_p = 0.0;
    max_bias = std::max(max_bias, c.bias);
  }
  return max_bias;
}

// One Gauss–Seidel sweep of island I's pseudo-impulses, with its trees' limit rows; returns the
// largest change of a contact point's pseudo-velocity, or, once a body's or a limited rate's
// change reaches `tolerance`, that change (the sweep has not converged: the trees' contact
// points are not measured), as sweepIsland does.
double sweepPositions(const SolverSettings& st, std::vector<SolverTree>& trees,
                      std::vector<ContactRow>& rows, SolverWork& work, const SolverWork::Island& I,
                      double tolerance) {
  forBodies(work, I, [&](int s) { work.vel_sweep[s] = work.vel[s]; });
  forTrees(work, trees, I, [](SolverTree& t) { t.pnu_sweep = t.pnu; });
  forRows(work, rows, I, [&](std::size_t k, ContactRow& c) {
    if (c.bias <= 0 && c.lambda_p == 0.0) return;
    const int a = work.a[k], b = work.b[k];
    double u = c.n.dot(relativeVelocity(work.vel, a, b, c));
    if (onTree(c)) u += c.n.dot(treeVelocity<&SolverTree::pnu>(trees, c));
    const double lp = std::max(0.0, c.lambda_p + (c.bias - u) * c.inv_k_nn);
    const double d = lp - c.lambda_p;
    c.lambda_p = lp;
    if (d != 0.0) applyTo<&SolverTree::pnu>(work.vel, work.response, trees, a, b, c, d * c.n);
  });
  double change = bodyChange(work, I);
  forTrees(work, trees, I, [&](SolverTree& t) {  // within the limits
    change = std::max(change, sweepPositionLimits(t, st.h));
  });
  if (I.trees > 0 && change < tolerance) {
    forTrees(work, trees, I, [](SolverTree& t) { t.pnu_sweep = t.pnu - t.pnu_sweep; });
    forRows(work, rows, I, [&](std::size_t, ContactRow& c) {
      if (onTree(c))
        change = std::max(change, treeVelocity<&SolverTree::pnu_sweep>(trees, c).norm());
    });
  }
  return change;
}

// A tree's correction moves no coordinate by more than max_tree_shift in one step: scaled
// down as a whole (it keeps its direction, so an internal contact still leaves the tree's
// centre of mass where it is, and stays within the limits, a convex set holding pν = 0).
void capTreeShifts(const SolverSettings& st, std::vector<SolverTree>& trees) {
  for (SolverTree& t : trees) {
    const double largest = st.h * t.pnu.cwiseAbs().maxCoeff();
    if (largest > st.max_tree_shift) t.pnu *= st.max_tree_shift / largest;
  }
}

}  // namespace
}  // namespace detail

void solvePositions(const SolverSettings& st, std::vector<SolverBody>& bodies,
                    std::vector<SolverTree>& trees, std::vector<ContactRow>& rows,
                    SolverWork& work) {
  for (SolverTree& t : trees) t.pnu.setZero(t.nu.size());
  const std::size_t n = bodies.size();
  for (SolverBody& b : bodies) {
    b.pv.setZero();
    b.pw.setZero();
  }
  if (detail::setBiases(st, rows) == 0.0) return;
  std::fill(work.vel.begin(), work.vel.end(), SolverWork::Twist());  // responses, islands kept
  for (const SolverWork::Island& I : work.islands) {
    double island_bias = 0.0;
    detail::forRows(work, rows, I, [&](std::size_t, ContactRow& c) {
      island_bias = std::max(island_bias, c.bias);
    });
    if (island_bias == 0.0) continue;
    // One tree alone with an overlap past the slop by more than kExactCorrectionExcess: solved
    // exactly (contact_resting_tree.h); smaller ones are swept, which is cheaper and enough.
    if (island_bias > st.correction * kExactCorrectionExcess / st.h &&
        correctTreePositions(st, trees, rows, work, I))
      continue;
    detail::finishTreeResponses(trees, rows, work, I);
    const double tolerance = 1e-3 * island_bias;  // 0.1 % of the island's largest correction
    for (int it = 0; it < st.position_iterations; ++it)
      if (detail::sweepPositions(st, trees, rows, work, I, tolerance) < tolerance) break;
  }
  for (std::size_t s = 0; s < n; ++s) {
    bodies[s].pv = work.vel[s].v;
    bodies[s].pw = work.vel[s].w;
  }
  detail::capTreeShifts(st, trees);
}

}  // namespace sim
}  // namespace cga_rigid_sim
