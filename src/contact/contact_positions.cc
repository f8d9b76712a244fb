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

// The position correction's sweeps in the factor's coordinates (SolverWork::TreeSweeps,
// loadTreeSweeps): pν = L⁻¹ z, z = 0 at pν = 0. They push along the normals alone, so a row's
// tree side needs only Y n, a scalar per coordinate of its run (side b's negated), where the
// velocity sweeps read Y's three columns.
void loadNormals(std::vector<ContactRow>& rows, SolverWork& work, const SolverWork::Island& I) {
  if (I.trees == 0) return;
  SolverWork::TreeSweeps& T = work.tree_sweeps;
  T.yn.resize(T.y.size());
  forRows(work, rows, I, [&](std::size_t k, ContactRow& c) {
    forTreeSides(T, c, k, [&](int, const SolverWork::TreeSweeps::Run& run, bool b) {
      const Eigen::Vector3d n = b ? Eigen::Vector3d(-c.n) : c.n;
      for (int i = run.first; i < run.first + run.size; ++i) T.yn[i] = T.y[i].dot(n);
    });
  });
}

// Whether the runs loaded are island I's rows' as they are: each tree side's first entry of Y
// against the row's own (a guard against a marker left by a velocity solve this correction did
// not follow; a run made at another pose or for another row does not match to the bit).
bool runsMatch(const std::vector<SolverTree>& trees, std::vector<ContactRow>& rows,
               const SolverWork& work, const SolverWork::Island& I) {
  const SolverWork::TreeSweeps& T = work.tree_sweeps;
  if (T.side_a.size() < rows.size() || T.side_b.size() < rows.size()) return false;
  bool match = true;
  for (int q = I.first_tree; q < I.first_tree + I.trees; ++q) {  // a run per stop
    const int t = work.island_tree[q];
    match = match && t < static_cast<int>(T.stop.size()) && t < static_cast<int>(T.z.size()) &&
            T.stop[t].size() == trees[t].limits.size();
  }
  forRows(work, rows, I, [&](std::size_t k, ContactRow& c) {
    forTreeSides(T, c, k, [&](int, const SolverWork::TreeSweeps::Run& run, bool b) {
      const TreeFactor::Columns& Y = b ? c.wb : c.wa;
      match = match && run.size > 0 && run.first + run.size <= static_cast<int>(T.y.size()) &&
              T.coordinate[run.first] < Y.rows() &&
              T.y[run.first] == Y.row(T.coordinate[run.first]).transpose();
    });
  });
  return match;
}

// The sweeps' coordinates for island I's position correction: z = 0 on its trees, with the runs
// its velocity sweeps left if they were the last made (`swept`: the island whose runs are still
// loaded from this step's velocity solve, the same rows and factor), else made again; and Y n.
void loadPositionSweeps(const std::vector<SolverTree>& trees, std::vector<ContactRow>& rows,
                        SolverWork& work, const SolverWork::Island& I,
                        const SolverWork::Island*& swept) {
  if (I.trees == 0) return;
  SolverWork::TreeSweeps& T = work.tree_sweeps;
  if (swept == &I && runsMatch(trees, rows, work, I)) {
    for (int q = I.first_tree; q < I.first_tree + I.trees; ++q) {
      const int t = work.island_tree[q];
      T.z[t].setZero(trees[t].nu.size());
    }
  } else {
    loadTreeSweeps(trees, rows, work, I);
    swept = nullptr;
  }
  loadNormals(rows, work, I);
}

// n·(J pν) of row k's tree sides: (Y n)ᵀ z over their runs.
__attribute__((always_inline)) inline double sweptNormalVelocity(const SolverWork::TreeSweeps& T,
                                                                 const ContactRow& c,
                                                                 std::size_t k) {
  double u = 0.0;
  forTreeSides(T, c, k, [&](int t, const SolverWork::TreeSweeps::Run& run, bool) {
    const double* z = T.z[t].data();
    for (int i = run.first; i < run.first + run.size; ++i) u += T.yn[i] * z[T.coordinate[i]];
  });
  return u;
}

// The pseudo-impulse d n on row k's tree sides: z += d (Y n).
__attribute__((always_inline)) inline void applyNormalToSweptTrees(SolverWork::TreeSweeps& T,
                                                                   const ContactRow& c,
                                                                   std::size_t k, double d) {
  forTreeSides(T, c, k, [&](int t, const SolverWork::TreeSweeps::Run& run, bool) {
    double* z = T.z[t].data();
    for (int i = run.first; i < run.first + run.size; ++i) z[T.coordinate[i]] += d * T.yn[i];
  });
}

// One Gauss–Seidel sweep of island I's pseudo-impulses, with its trees' limit rows; returns the
// largest change of a contact point's pseudo-velocity, or, once a body's or a limited rate's
// change reaches `tolerance`, that change (the sweep has not converged: the trees' contact
// points are not measured), as sweepIsland does.
double sweepPositions(const SolverSettings& st, std::vector<SolverTree>& trees,
                      std::vector<ContactRow>& rows, SolverWork& work, const SolverWork::Island& I,
                      double tolerance) {
  SolverWork::TreeSweeps& T = work.tree_sweeps;
  forBodies(work, I, [&](int s) { work.vel_sweep[s] = work.vel[s]; });
  for (int q = I.first_tree; q < I.first_tree + I.trees; ++q)
    T.z_sweep[work.island_tree[q]] = T.z[work.island_tree[q]];
  forRows(work, rows, I, [&](std::size_t k, ContactRow& c) {
    if (c.bias <= 0 && c.lambda_p == 0.0) return;
    const int a = work.a[k], b = work.b[k];
    // A tree against the ground, a static body or itself has no body side (both slots the dummy).
    const bool trees_only = onTree(c) && a == b;
    double u = trees_only ? 0.0 : c.n.dot(relativeVelocity(work.vel, a, b, c));
    if (onTree(c)) u += sweptNormalVelocity(T, c, k);
    const double lp = std::max(0.0, c.lambda_p + (c.bias - u) * c.inv_k_nn);
    const double d = lp - c.lambda_p;
    c.lambda_p = lp;
    if (d == 0.0) return;
    if (!trees_only) applyTo(work.vel, work.response, a, b, c, d * c.n);
    if (onTree(c)) applyNormalToSweptTrees(T, c, k, d);
  });
  double change = bodyChange(work, I);
  for (int q = I.first_tree; q < I.first_tree + I.trees; ++q) {  // within the limits
    const int t = work.island_tree[q];
    change = std::max(change, sweepPositionLimits(trees[t], t, T, st.h));
  }
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

// pν = L⁻¹ z for island I's trees, after the sweeps.
void finishPositionSweeps(std::vector<SolverTree>& trees, SolverWork& work,
                          const SolverWork::Island& I) {
  for (int q = I.first_tree; q < I.first_tree + I.trees; ++q) {
    const int t = work.island_tree[q];
    trees[t].pnu = sweptChange(trees[t], work.tree_sweeps, t);
  }
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
  // The island whose runs the velocity solve's sweeps left, taken once: a later step's velocity
  // solve may leave none (Newton's solves make no runs).
  const SolverWork::Island* swept =
      work.tree_sweeps.swept_rows == &rows ? work.tree_sweeps.swept_island : nullptr;
  work.tree_sweeps.swept_island = nullptr;
  const std::size_t n = bodies.size();
  for (SolverBody& b : bodies) {
    b.pv.setZero();
    b.pw.setZero();
  }
  // Nothing to correct where every overlap is within the slop, or passes it by no more than
  // the onset (a resting contact settles a few nanometres past it: correcting that each step
  // moves nothing that matters). An island with one overlap past the onset is corrected whole,
  // each overlap beyond the slop by its part.
  const double onset_bias = st.correction * st.correction_onset / st.h;
  if (detail::setBiases(st, rows) <= onset_bias) return;
  std::fill(work.vel.begin(), work.vel.end(), SolverWork::Twist());  // responses, islands kept
  for (const SolverWork::Island& I : work.islands) {
    double island_bias = 0.0;
    detail::forRows(work, rows, I, [&](std::size_t, ContactRow& c) {
      island_bias = std::max(island_bias, c.bias);
    });
    if (island_bias <= onset_bias) continue;
    // One tree alone with an overlap past the slop by more than kExactCorrectionExcess: solved
    // exactly (contact_resting_tree.h); smaller ones are swept, which is cheaper and enough.
    if (island_bias > st.correction * kExactCorrectionExcess / st.h &&
        correctTreePositions(st, trees, rows, work, I))
      continue;
    detail::loadPositionSweeps(trees, rows, work, I, swept);
    const double tolerance = 1e-3 * island_bias;  // 0.1 % of the island's largest correction
    for (int it = 0; it < st.position_iterations; ++it)
      if (detail::sweepPositions(st, trees, rows, work, I, tolerance) < tolerance) break;
    detail::finishPositionSweeps(trees, work, I);
  }
  for (std::size_t s = 0; s < n; ++s) {
    bodies[s].pv = work.vel[s].v;
    bodies[s].pw = work.vel[s].w;
  }
  detail::capTreeShifts(st, trees);
}

}  // namespace sim
}  // namespace cga_rigid_sim
