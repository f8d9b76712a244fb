// The contact step's kick (contact_step.h): every moving body in a contact gets a solver slot
// (a tree link the slot of its tree too), and the loads' kick: a free body's in world-axes
// momentum, a tree's through its mass matrix (contact_trees.cc). Then the speculative contacts
// whose gap stays open over the step are dropped.
#include <algorithm>

#include "cga_rigid_sim/body/derived.h"
#include "contact/contact_momentum.h"
#include "contact/contact_step.h"
#include "contact/contact_trees.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

int slotOf(const Model& model, ContactScratch& S, int j) {
  if (j < 0) return -1;
  const int i = model.moving_of_body[j];
  if (i < 0) return -1;
  if (S.slot_of_moving[i] < 0) {
    S.slot_of_moving[i] = static_cast<int>(S.moving_of_slot.size());
    S.moving_of_slot.push_back(i);
    const int t = model.tree_of_moving[i];
    if (t >= 0 && S.solver_tree_of_tree[t] < 0) {
      S.solver_tree_of_tree[t] = static_cast<int>(S.tree_of_solver_tree.size());
      S.tree_of_solver_tree.push_back(t);
    }
  }
  return S.slot_of_moving[i];
}

// The loads' kick over h, added to the world-axes momentum: h g (and h f_W / m, h τ_W of the
// applied loads) — the same ΔΩ_B = h (I∧n)⁻¹ (T_applied + T_gravity), in world axes.
void kickMomentum(const Model& model, const MovingBodyData& b, const dynamics::Inertia& I,
                  MovingBodyData::ContactMomentum& m) {
  const double h = model.config.dt, lambda = model.lambda;
  if (b.loads.hasGravity()) addCompensated(m.v_hi, m.v_lo, h * b.loads.gravity());
  if (!b.loads.hasApplied()) return;
  const cga::Moment T = b.loads.appliedMoment_B(b.state.M_WB, lambda);
  const Eigen::Quaterniond& R = b.state.M_WB.rotation();
  addCompensated(m.v_hi, m.v_lo, (h / I.mass()) * (R * T.force(lambda)));
  addCompensated(m.L_hi, m.L_lo, h * (R * T.torque()));
}

// Whether a tree's kick is usable: its mass matrix factored and its kicked ν finite.
bool kickFinite(const SolverTree& k) { return k.factor.ok() && k.nu.allFinite(); }

// Removes the contacts that touch a link (or the floating root) of tree t.
void dropContactsOf(const Model& model, int t, std::vector<Contact>& found) {
  const auto inTree = [&](int j) {
    const int i = j < 0 ? -1 : model.moving_of_body[j];
    return i >= 0 && model.tree_of_moving[i] == t;
  };
  found.erase(
      std::remove_if(found.begin(), found.end(),
                     [&](const Contact& c) { return inTree(c.body_a) || inTree(c.body_b); }),
      found.end());
}

// Slots for every moving body in a contact (and its tree), and the trees' kicks. A tree whose
// kick is not finite (its mass matrix cannot be factored at this pose) takes no part: its
// contacts are dropped and the slots made again without them; the tree stage then undoes its
// step (stage_trees.cc, doc/articulated.md#faults). False when no contact is left.
bool makeSlots(const Model& model, Data& data, ContactScratch& S) {
  for (;;) {
    S.slot_of_moving.assign(data.bodies.size(), -1);
    S.moving_of_slot.clear();
    S.solver_tree_of_tree.assign(model.trees.size(), -1);
    S.tree_of_solver_tree.clear();
    S.slot_a.resize(S.found.size());
    S.slot_b.resize(S.found.size());
    for (std::size_t k = 0; k < S.found.size(); ++k) {
      S.slot_a[k] = slotOf(model, S, S.found[k].body_a);
      S.slot_b[k] = slotOf(model, S, S.found[k].body_b);
    }
    S.trees.resize(S.tree_of_solver_tree.size());
    S.tree_kicked.resize(S.tree_of_solver_tree.size());
    bool dropped = false;
    for (std::size_t u = 0; u < S.trees.size(); ++u) {
      kickTree(model, data, S.tree_of_solver_tree[u], S.trees[u], S.tree_kicked[u]);
      if (kickFinite(S.trees[u])) continue;
      dropContactsOf(model, S.tree_of_solver_tree[u], S.found);
      dropped = true;
    }
    if (!dropped) return true;
    if (S.found.empty()) {
      data.contacts.clear();
      return false;
    }
  }
}

}  // namespace

SolverBody solverBody(const Model& model, const dynamics::BodyState& s,
                      const cga::Bivelocity& omega_B, int i) {
  const dynamics::Inertia& I = model.moving[i].inertia;
  const Eigen::Matrix3d R = s.M_WB.rotation().toRotationMatrix();
  SolverBody out;
  out.x = s.M_WB.translation(model.lambda);
  out.v = R * omega_B.linear(model.lambda);
  out.w = R * omega_B.angular();
  out.mass = I.mass();
  out.inv_mass = 1.0 / I.mass();
  out.inertia = R * I.principalMoments().asDiagonal() * R.transpose();
  out.inv_inertia = R * I.principalMoments().cwiseInverse().asDiagonal() * R.transpose();
  return out;
}

bool kickContactBodies(const Model& model, Data& data, ContactScratch& S) {
  if (!makeSlots(model, data, S)) return false;
  const double lambda = model.lambda;
  S.kicked_B.resize(S.moving_of_slot.size());
  S.momentum.resize(S.moving_of_slot.size());
  S.v_start.resize(S.moving_of_slot.size());
  S.bodies.resize(S.moving_of_slot.size());
  for (std::size_t s = 0; s < S.moving_of_slot.size(); ++s) {
    const int i = S.moving_of_slot[s];
    const int t = model.tree_of_moving[i];
    if (t < 0) {
      const MovingBodyData& b = data.bodies[i];
      const dynamics::Inertia& I = model.moving[i].inertia;
      MovingBodyData::ContactMomentum& m = S.momentum[s];
      m = startMomentum(I, b, lambda);
      S.v_start[s] = velocity_W(m);
      kickMomentum(model, b, I, m);
      S.kicked_B[s] = bodyVelocity(I, b.state.M_WB.rotation(), m, lambda);
      S.bodies[s] = solverBody(model, b.state, S.kicked_B[s], i);
      S.bodies[s].v = velocity_W(m);
      continue;
    }
    // A link: its velocity moves with its tree's ν, so it has no mass of its own here.
    const int u = S.solver_tree_of_tree[t], b = model.tree_body_of_moving[i];
    S.kicked_B[s] = S.tree_kicked[u].omega[b];
    SolverBody& sb = S.bodies[s];
    sb = SolverBody();
    sb.tree = u;
    sb.tree_body = b;
    const dynamics::BodyState& st = data.bodies[i].state;
    const Eigen::Matrix3d R = st.M_WB.rotation().toRotationMatrix();
    sb.x = st.M_WB.translation(lambda);
    sb.v = R * S.kicked_B[s].linear(lambda);
    sb.w = R * S.kicked_B[s].angular();
  }
  return true;
}

bool keepClosingContacts(const Model& model, Data& data, ContactScratch& S) {
  // A speculative contact whose gap stays open over the step is dropped: a body near the
  // ground but not reaching it keeps its own path. Touching contacts stay (a stack's).
  const double h = model.config.dt, lambda = model.lambda;
  std::size_t kept = 0;
  for (std::size_t k = 0; k < S.found.size(); ++k) {
    const Contact& c = S.found[k];
    if (c.depth < -kTouching) {
      // Closing over the step at the mean of the velocities before and after the kick (exact
      // under a constant acceleration): the kicked velocity alone would close gaps that a free
      // flight does not reach this step, and a bounce there would start above the surface.
      const int a = S.slot_a[k], b = S.slot_b[k];
      const auto pointVelocity = [&](int slot, const cga::Bivelocity& omega_B) {
        const dynamics::BodyState& st = data.bodies[S.moving_of_slot[slot]].state;
        const Eigen::Quaterniond& R = st.M_WB.rotation();
        return Eigen::Vector3d(
            R * (omega_B.linear(lambda) +
                 omega_B.angular().cross(R.conjugate() * (c.point_W - S.bodies[slot].x))));
      };
      Eigen::Vector3d u = pointVelocity(a, data.bodies[S.moving_of_slot[a]].state.omega_B) +
                          pointVelocity(a, S.kicked_B[a]);
      if (b >= 0)
        u -= pointVelocity(b, data.bodies[S.moving_of_slot[b]].state.omega_B) +
             pointVelocity(b, S.kicked_B[b]);
      if (0.5 * c.normal_W.dot(u) * h >= c.depth) continue;
    }
    S.found[kept] = S.found[k];
    S.slot_a[kept] = S.slot_a[k];
    S.slot_b[kept] = S.slot_b[k];
    ++kept;
  }
  S.found.resize(kept);
  S.slot_a.resize(kept);
  S.slot_b.resize(kept);
  if (kept == 0) {
    data.contacts.clear();
    return false;
  }
  return true;
}

}  // namespace sim
}  // namespace cga_rigid_sim
