// The contact step's rows and solve (contact_step.h): the solver's rows of the contacts left,
// warm-started from last step's impulses of the same contacts; then the velocity and position
// solves, whose impulses the trees take, with what their guards check their step against.
#include <algorithm>
#include <tuple>

#include "contact/contact_step.h"
#include "contact/contact_trees.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

auto pairKey(const Contact& c) { return std::make_tuple(c.body_a, c.shape_a, c.body_b, c.shape_b); }

// Last step's impulse of the same contact, if it existed: same pair of shapes and the same
// vertex, or (no vertex known) a point within 2 mm.
const Contact* previousOf(const Data& data, const ContactScratch& S, const Contact& c) {
  const auto key = pairKey(c);
  auto it = std::lower_bound(
      S.previous.begin(), S.previous.end(), key,
      [&data](std::size_t k, const auto& v) { return pairKey(data.contacts[k]) < v; });
  for (; it != S.previous.end() && pairKey(data.contacts[*it]) == key; ++it) {
    const Contact& p = data.contacts[*it];
    if (c.feature >= 0 ? p.feature == c.feature : (p.point_W - c.point_W).squaredNorm() < 4e-6)
      return &p;
  }
  return nullptr;
}

// What the contact step's guard checks a tree against (contact_tree_end.cc): a floating
// tree's momentum changes by the impulses of its contacts with anything else (its contacts
// with itself cancel), and a tree's energy by the work of contacts with other moving bodies.
void noteTreeReferences(const Model& model, Data& data, const ContactScratch& S) {
  const double lambda = model.lambda;
  for (TreeData& td : data.trees) td.contact_transfer = 0.0;
  for (std::size_t k = 0; k < S.found.size(); ++k) {
    const int ta = S.slot_a[k] >= 0 ? S.bodies[S.slot_a[k]].tree : -1;
    const int tb = S.slot_b[k] >= 0 ? S.bodies[S.slot_b[k]].tree : -1;
    if (ta == tb) continue;
    const ContactRow& r = S.rows[k];
    const Eigen::Vector3d P = r.lambda_n * r.n + r.lambda_t.x() * r.t1 + r.lambda_t.y() * r.t2;
    const cga::Moment J(S.found[k].point_W.cross(P), lambda * P);
    const bool other_moves = S.slot_a[k] >= 0 && S.slot_b[k] >= 0;
    for (const auto& [u, sign] : {std::pair{ta, 1.0}, std::pair{tb, -1.0}}) {
      if (u < 0) continue;
      const SolverTree& st = S.trees[u];
      TreeData& td = data.trees[S.tree_of_solver_tree[u]];
      td.contact_momentum_expected += J * sign;
      td.contact_momentum_scale += P.norm();
      if (!other_moves) continue;
      const auto& jac = sign > 0 ? r.ja : r.jb;
      td.contact_transfer += sign * P.dot(0.5 * (jac * st.nu_start + jac * st.nu));
    }
  }
}

}  // namespace

SolverSettings contactSettings(const Model& model) {
  SolverSettings settings;
  const double h = model.config.dt;
  settings.h = h;
  settings.kick = model.scene.gravity_W.norm() * h;
  settings.gravity_kick_W = model.scene.gravity_W * h;
  settings.rest_speed = 2.0 * settings.kick;
  settings.bounce_speed = 3.0 * model.scene.gravity_W.norm() * h;
  settings.model = model.config.contact_model;
  return settings;
}

void makeRows(const Model& /*model*/, Data& data, ContactScratch& S) {
  const std::size_t kept = S.found.size();
  // A tree whose contacts all stay open keeps its whole step: its kick is dropped and its tree
  // stage steps it under its loads.
  S.tree_used.assign(S.trees.size(), 0);
  for (std::size_t k = 0; k < kept; ++k)
    for (const int slot : {S.slot_a[k], S.slot_b[k]})
      if (slot >= 0 && S.bodies[slot].tree >= 0) S.tree_used[S.bodies[slot].tree] = 1;
  prepareRows(S.found, S.bodies, S.trees, S.slot_a, S.slot_b, S.rows);

  // Warm start from last step's impulses of the same contacts.
  S.previous.resize(data.contacts.size());
  for (std::size_t k = 0; k < S.previous.size(); ++k) S.previous[k] = k;
  const auto byPair = [&data](std::size_t x, std::size_t y) {
    return pairKey(data.contacts[x]) < pairKey(data.contacts[y]) ||
           (pairKey(data.contacts[x]) == pairKey(data.contacts[y]) && x < y);
  };
  if (!std::is_sorted(S.previous.begin(), S.previous.end(), byPair))  // detection's order mostly is
    std::sort(S.previous.begin(), S.previous.end(), byPair);
  for (std::size_t k = 0; k < kept; ++k) {
    ContactRow& r = S.rows[k];
    r.lambda_n = 0.0;
    r.lambda_t.setZero();
    r.pyramid_share = std::numeric_limits<double>::quiet_NaN();
    if (const Contact* p = previousOf(data, S, S.found[k])) {
      r.lambda_n = p->normal_impulse;
      r.lambda_t = {r.t1.dot(p->friction_impulse_W), r.t2.dot(p->friction_impulse_W)};
      r.pyramid_share = p->pyramid_share;
    }
  }
}

void solveRows(const Model& model, Data& data, ContactScratch& S, const SolverSettings& st) {
  data.contact_sweeps = solveVelocities(st, S.bodies, S.trees, S.rows, S.work).iterations;
  solvePositions(st, S.bodies, S.trees, S.rows, S.work);
  for (std::size_t u = 0; u < S.trees.size(); ++u) {
    const int t = S.tree_of_solver_tree[u];
    if (!S.tree_used[u]) continue;
    takeTreeImpulses(model, data, t, S.trees[u], S.tree_kicked[u]);
  }
  noteTreeReferences(model, data, S);
}

}  // namespace sim
}  // namespace cga_rigid_sim
