// The velocity solve (doc/contacts.md#solver, #energy): island by island, targets from the
// velocities before any contact impulse, a warm start (or a resting island's direct solve),
// Gauss–Seidel sweeps until the island's own tolerance, and the energy guard: a solve whose
// restitution raised the island's kinetic energy is redone with e = 0.
#include <algorithm>

#include "contact/contact_patch.h"
#include "contact/contact_resting.h"
#include "contact/contact_resting_tree.h"
#include "contact/contact_solver_internals.h"

namespace cga_rigid_sim {
namespace sim {
namespace detail {
namespace {

// The working arrays for `bodies` and `rows`: responses, lever arms, the rows' slots (the
// dummy for none); the velocities are taken from the bodies by the caller.
void loadWork(const std::vector<SolverBody>& bodies, const std::vector<ContactRow>& rows,
              SolverWork& work) {
  const int n = static_cast<int>(bodies.size());
  work.response.resize(n + 1);
  work.vel.resize(n + 1);
  work.vel_sweep.resize(n + 1);
  work.vel_start.resize(n + 1);
  for (int s = 0; s < n; ++s) {
    work.response[s].inv_mass = bodies[s].inv_mass;
    work.response[s].inv_inertia = bodies[s].inv_inertia;
    work.response[s].reach = 0.0;
  }
  work.response[n] = SolverWork::Response();
  work.vel[n] = Twist();
  work.a.resize(rows.size());
  work.b.resize(rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const ContactRow& c = rows[k];
    work.a[k] = c.a >= 0 ? c.a : n;
    work.b[k] = c.b >= 0 ? c.b : n;
    if (c.a >= 0) work.response[c.a].reach = std::max(work.response[c.a].reach, c.ra.norm());
    if (c.b >= 0) work.response[c.b].reach = std::max(work.response[c.b].reach, c.rb.norm());
  }
}

// A tree side's run: the coordinates from its leaves to the base (every one with a dense factor),
// Y's rows on them, and J ν₀ over them (J is zero off them), added to u.
SolverWork::TreeSweeps::Run loadSide(const SolverTree& t,
                                     const Eigen::Matrix<double, 3, Eigen::Dynamic>& J,
                                     const TreeFactor::Columns& Y, int leaf, int leaf2,
                                     SolverWork::TreeSweeps& T, Eigen::Vector3d& u) {
  SolverWork::TreeSweeps::Run run;
  run.first = static_cast<int>(T.coordinate.size());
  auto take = [&](int i) {
    T.coordinate.push_back(i);
    T.y.push_back(Y.row(i).transpose());
    u += J.col(i) * t.nu[i];
  };
  if (!t.factor.sparse()) {
    for (int i = 0; i < static_cast<int>(t.nu.size()); ++i) take(i);
  } else {  // the union of the two paths, as TreeFactor::halfSolve walks it
    for (int a = leaf, b = leaf2; a >= 0 || b >= 0;) {
      const int i = std::max(a, b);
      take(i);
      if (a == i) a = t.coordinate_parent[a];
      if (b == i) b = t.coordinate_parent[b];
    }
  }
  run.size = static_cast<int>(T.coordinate.size()) - run.first;
  return run;
}

}  // namespace

void loadTreeSweeps(const std::vector<SolverTree>& trees, const std::vector<ContactRow>& rows,
                    SolverWork& work, const SolverWork::Island& I) {
  if (I.trees == 0) return;
  SolverWork::TreeSweeps& T = work.tree_sweeps;
  T.coordinate.clear();  // (an island's runs serve its solve only)
  T.y.clear();
  T.stop_coordinate.clear();
  T.s.clear();
  T.side_a.resize(rows.size());
  T.side_b.resize(rows.size());
  T.u0.resize(rows.size());
  T.z.resize(trees.size());
  T.z_sweep.resize(trees.size());
  T.stop.resize(trees.size());
  T.stop_a.resize(trees.size());
  T.stop_norm.resize(trees.size());
  T.scratch.resize(trees.size());
  T.change.resize(trees.size());
  for (int q = I.first_tree; q < I.first_tree + I.trees; ++q) {
    const int t = work.island_tree[q];
    T.z[t].setZero(trees[t].nu.size());
    T.z_sweep[t].setZero(trees[t].nu.size());
    loadSweptLimits(trees[t], t, T);
  }
  for (int q = I.first_group; q < I.first_group + I.groups; ++q) {
    const SolverWork::Group& g = work.groups[work.island_group[q]];
    for (int k = g.first; k < g.first + g.size; ++k) {
      const ContactRow& c = rows[k];
      if (!onTree(c)) continue;
      Eigen::Vector3d u = Eigen::Vector3d::Zero(), ub = Eigen::Vector3d::Zero();
      T.side_a[k] = T.side_b[k] = SolverWork::TreeSweeps::Run();
      if (c.ta >= 0) T.side_a[k] = loadSide(trees[c.ta], c.ja, c.wa, c.leaf_a, c.leaf_a2, T, u);
      if (c.tb >= 0) T.side_b[k] = loadSide(trees[c.tb], c.jb, c.wb, c.leaf_b, -1, T, ub);
      T.u0[k] = u - ub;
    }
  }
}

Eigen::Ref<const Eigen::VectorXd> sweptChange(const SolverTree& tree, SolverWork::TreeSweeps& T,
                                              int t) {
  Eigen::VectorXd& change = T.change[t];
  change = T.z[t];                  // (copies into storage of the same size: no allocation)
  tree.factor.finishSolve(change);  // L⁻¹ z
  return change;
}

void finishTreeSweeps(std::vector<SolverTree>& trees, SolverWork& work,
                      const SolverWork::Island& I) {
  for (int q = I.first_tree; q < I.first_tree + I.trees; ++q) {
    const int t = work.island_tree[q];
    trees[t].nu += sweptChange(trees[t], work.tree_sweeps, t);
  }
}

namespace {

// The kinetic energy of an island's bodies and trees, before the contact impulses (vel_start,
// ν_start) or at the velocities now in `work` (vel, ν).
double islandKinetic(const std::vector<SolverBody>& bodies, const std::vector<SolverTree>& trees,
                     const SolverWork& work, const SolverWork::Island& I, bool before) {
  const std::vector<SolverWork::Twist>& vel = before ? work.vel_start : work.vel;
  double T = 0.0;
  for (int q = I.first_body; q < I.first_body + I.bodies; ++q) {
    const int s = work.island_body[q];
    const SolverWork::Twist& t = vel[s];
    T += 0.5 * (bodies[s].mass * t.v.squaredNorm() + t.w.dot(bodies[s].inertia * t.w));
  }
  for (int q = I.first_tree; q < I.first_tree + I.trees; ++q) {
    const SolverTree& t = trees[work.island_tree[q]];
    const Eigen::VectorXd& nu = before ? t.nu_start : t.nu;
    T += 0.5 * nu.dot(t.M.selfadjointView<Eigen::Lower>() * nu);
  }
  return T;
}

// The island's tolerance on a sweep's change (SolverSettings::tolerance and its terms), from
// its fastest contact point's speed before the impulses.
double islandTolerance(const SolverSettings& st, std::vector<SolverTree>& trees,
                       std::vector<ContactRow>& rows, const SolverWork& work,
                       const SolverWork::Island& I) {
  double speed = 0.0;
  forBodies(work, I, [&](int s) {
    speed = std::max(speed, work.vel[s].v.norm() + work.response[s].reach * work.vel[s].w.norm());
  });
  if (I.trees > 0)
    forRows(work, rows, I, [&](std::size_t, ContactRow& c) {
      if (onTree(c)) speed = std::max(speed, treeVelocity<&SolverTree::nu>(trees, c).norm());
    });
  return st.tolerance + st.tolerance_of_kick * st.kick +
         st.tolerance_of_speed * std::max(0.0, speed - 2.0 * st.kick);
}

// Back to the velocities before the contacts, every impulse of the island cleared.
void restartCold(std::vector<SolverTree>& trees, std::vector<ContactRow>& rows, SolverWork& work,
                 const SolverWork::Island& I) {
  forBodies(work, I, [&](int s) { work.vel[s] = work.vel_start[s]; });
  forTrees(work, trees, I, [](SolverTree& t) {
    t.nu = t.nu_start;
    for (SolverTree::LimitRow& r : t.limits) r.y_lower = r.y_upper = 0.0;
  });
  forRows(work, rows, I, [](std::size_t, ContactRow& c) {
    c.lambda_n = 0.0;
    c.lambda_t.setZero();
    c.lambda_spin = 0.0;
    c.lambda_roll.setZero();
    c.couple.setZero();
  });
}

// The warm start's impulses, each inside its cone (a compliant contact: its spring's).
void clampWarmStart(std::vector<ContactRow>& rows, const SolverWork& work,
                    const SolverWork::Island& I) {
  forRows(work, rows, I, [&](std::size_t, ContactRow& c) {
    c.lambda_n = c.compliant ? c.lambda_fixed : std::max(0.0, c.lambda_n);
    const double tmax = c.mu * c.lambda_n, t = c.lambda_t.norm();
    if (t > tmax) c.lambda_t *= t > 0 ? tmax / t : 0.0;
  });
}

// … applied (a tree's in the sweeps' coordinates, loadTreeSweeps).
void warmStart(std::vector<ContactRow>& rows, SolverWork& work, const SolverWork::Island& I) {
  clampWarmStart(rows, work, I);
  forRows(work, rows, I, [&](std::size_t k, ContactRow& c) {
    applySwept(work, c, k, c.lambda_n * c.n + c.lambda_t.x() * c.t1 + c.lambda_t.y() * c.t2);
  });
}

// The energy guard: restitution in several simultaneous impacts can add energy; e = 0 cannot
// (doc/contacts.md#energy). Whether the island's solve may stand.
bool energyGuardHolds(const std::vector<SolverBody>& bodies, const std::vector<SolverTree>& trees,
                      std::vector<ContactRow>& rows, const SolverWork& work,
                      const SolverWork::Island& I) {
  bool any_bounce = false;
  forRows(work, rows, I,
          [&](std::size_t, ContactRow& c) { any_bounce = any_bounce || c.impact > 0; });
  return !any_bounce || islandKinetic(bodies, trees, work, I, false) <=
                            islandKinetic(bodies, trees, work, I, true) * (1 + 1e-12) + 1e-300;
}

// The velocity solve of one island: sweeps until its own change is below its tolerance, with
// restitution, and once more without it when the energy guard fails; returns its sweeps.
int solveIsland(const SolverSettings& st, const std::vector<SolverBody>& bodies,
                std::vector<SolverTree>& trees, std::vector<ContactRow>& rows, SolverWork& work,
                const SolverWork::Island& I) {
  const double tolerance = islandTolerance(st, trees, rows, work, I);
  const int max_iterations = I.trees > 0 ? st.max_tree_iterations : st.max_iterations;
  const bool patch = patchResistance(st.model);
  int sweeps = 0;
  for (int attempt = 0; attempt < 2; ++attempt) {
    const bool bounce = attempt == 0;
    if (!bounce) restartCold(trees, rows, work, I);  // start again from before the contacts
    forRows(work, rows, I,
            [&](std::size_t k, ContactRow& c) { setTarget(st, work, trees, bounce, k, c); });
    // A resting tree's island by Newton's method, from the warm start's impulses: exact, no
    // sweeps (and no responses M⁻¹ Jᵀ: it works on M itself). On failure it leaves ν as it was.
    if (bounce && I.trees > 0) {
      clampWarmStart(rows, work, I);
      const int steps = solveRestingTree(st, trees, rows, work, I);
      if (steps > 0) return steps;
    }
    loadTreeSweeps(trees, rows, work, I);
    // A resting island of faces solved directly; the sweeps then only confirm it.
    if (!bounce || st.model.compliant() || !solveResting(bodies, rows, work, I))
      warmStart(rows, work, I);
    int it = 0;
    for (; it < max_iterations; ++it) {
      if (sweepIsland(st, trees, rows, work, I, patch, tolerance) < tolerance) {
        ++it;
        break;
      }
    }
    finishTreeSweeps(trees, work, I);
    sweeps += it;
    // A tree's island the sweeps left sinking: its normals and stops solved again.
    if (bounce && it == max_iterations) polishTreeNormals(st, trees, rows, work, I);
    if (energyGuardHolds(bodies, trees, rows, work, I)) break;
  }
  return sweeps;
}

}  // namespace
}  // namespace detail

double kineticEnergy(const std::vector<SolverBody>& bodies, const std::vector<SolverTree>& trees) {
  double T = 0.0;
  for (const SolverBody& b : bodies)
    T += 0.5 * (b.mass * b.v.squaredNorm() + b.w.dot(b.inertia * b.w));
  for (const SolverTree& t : trees) T += 0.5 * t.nu.dot(t.M.selfadjointView<Eigen::Lower>() * t.nu);
  return T;
}

SolveStats solveVelocities(const SolverSettings& st, std::vector<SolverBody>& bodies,
                           std::vector<SolverTree>& trees, std::vector<ContactRow>& rows,
                           SolverWork& work) {
  SolveStats stats;
  work.tree_sweeps.swept_island = nullptr;  // no runs of this solve's islands yet
  detail::loadWork(bodies, rows, work);
  detail::makeGroups(rows, work);
  detail::makeIslands(rows, static_cast<int>(trees.size()), work);
  const std::size_t n = bodies.size();
  // The velocities before any contact impulse: the warm start is applied after the targets
  // are read from them.
  for (std::size_t s = 0; s < n; ++s) work.vel_start[s] = {bodies[s].v, bodies[s].w};
  work.vel_start[n] = SolverWork::Twist();
  std::copy(work.vel_start.begin(), work.vel_start.end(), work.vel.begin());
  for (SolverTree& t : trees) t.nu_start = t.nu;
  if (st.kinetic_energy) stats.kinetic_before = kineticEnergy(bodies, trees);
  for (const SolverWork::Island& I : work.islands)
    stats.iterations =
        std::max(stats.iterations, detail::solveIsland(st, bodies, trees, rows, work, I));
  for (std::size_t s = 0; s < n; ++s) {
    bodies[s].v = work.vel[s].v;
    bodies[s].w = work.vel[s].w;
  }
  if (st.kinetic_energy) stats.kinetic_after = kineticEnergy(bodies, trees);
  return stats;
}

}  // namespace sim
}  // namespace cga_rigid_sim
