// The contacts stage (doc/contacts.md): detection at the step's start, then for every body that
// touches something a kick by its loads and the contact impulses, solved together; the
// integration then drifts those bodies torque-free (stage_integrate.cc). Bodies that touch
// nothing are left alone: they keep their exact or symplectic path.
#include <algorithm>
#include <limits>
#include <tuple>

#include "cga_rigid_sim/dynamics/derived.h"
#include "cga_rigid_sim/sim/stages.h"
#include "contact_landing.h"
#include "contact_momentum.h"
#include "contact_scratch.h"
#include "contact_trees.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// Gaps below this count as touching (the solver's residual lifts a resting body by ~1e-11 m).
constexpr double kTouching = 1e-9;

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

namespace {

// Whether a tree's kick is usable: its mass matrix factored and its kicked ν finite.
bool kickFinite(const SolverTree& k) {
  return k.llt.info() == Eigen::Success && k.nu.allFinite() && k.llt.matrixLLT().allFinite();
}

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

// The contacts of the awake bodies: detected, solved, applied.
void solveAwake(const Model& model, Data& data, ContactScratch& S) {
  S.found.clear();
  data.contact_sweeps = 0;
  detectContacts(model, data, *S.cache, S.found, &S.sleep.asleep);
  while (wakeTouched(model, data, S.sleep, S.found)) {  // their own contacts too
    S.found.clear();
    detectContacts(model, data, *S.cache, S.found, &S.sleep.asleep);
  }
  if (S.found.empty()) {
    data.contacts.clear();
    return;
  }
  const double h = model.config.dt, lambda = model.lambda;

  // Slots for every moving body in a contact (and its tree), and their kicked velocities.
  // Trees are kicked as a whole; their links' slots read the kicked velocities. A tree whose
  // kick is not finite (its mass matrix cannot be factored at this pose) takes no part: its
  // contacts are dropped and the slots made again without them; the tree stage then undoes
  // its step (stage_trees.cc, doc/articulated.md#faults).
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
    if (!dropped) break;
    if (S.found.empty()) {
      data.contacts.clear();
      return;
    }
  }
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

  // A speculative contact whose gap stays open over the step is dropped: a body near the
  // ground but not reaching it keeps its own path. Touching contacts stay (a stack's).
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
    return;
  }

  SolverSettings settings;
  settings.h = h;
  settings.kick = model.scene.gravity_W.norm() * h;
  settings.gravity_kick_W = model.scene.gravity_W * h;
  settings.rest_speed = 2.0 * settings.kick;
  settings.bounce_speed = 3.0 * model.scene.gravity_W.norm() * h;
  settings.model = model.config.contact_model;

  // Landings: a body whose contacts are all gaps to the ground plane that close within the
  // step faster than the resting speed is stepped to the instant it lands and bounces there.
  S.landing.assign(S.bodies.size(), 1);
  for (std::size_t s = 0; s < S.bodies.size(); ++s)
    if (S.bodies[s].tree >= 0) S.landing[s] = 0;  // a tree's links land as the tree moves
  for (std::size_t k = 0; k < kept; ++k) {
    const Contact& c = S.found[k];
    if (c.body_b != kGroundPlane || c.depth > 0) S.landing[S.slot_a[k]] = 0;
    if (S.slot_b[k] >= 0) S.landing[S.slot_b[k]] = 0;
  }
  S.landed.clear();
  double landing_dissipated = 0.0;
  {
    std::size_t k = 0;
    while (k < kept) {  // a body's plane contacts are consecutive (detection order)
      std::size_t e = k + 1;
      while (e < kept && S.slot_a[e] == S.slot_a[k]) ++e;
      const int s = S.slot_a[k];
      if (S.landing[s]) {
        const double t = landingTime(model, data, S, k, e, settings.rest_speed);
        if (t > 0)
          landing_dissipated += land(model, data, S, S.moving_of_slot[s], t, settings, S.landed);
        else
          S.landing[s] = 0;
      }
      k = e;
    }
    std::size_t out = 0;
    for (std::size_t q = 0; q < kept; ++q) {
      if (S.landing[S.slot_a[q]]) continue;
      S.found[out] = S.found[q];
      S.slot_a[out] = S.slot_a[q];
      S.slot_b[out] = S.slot_b[q];
      ++out;
    }
    kept = out;
    S.found.resize(kept);
    S.slot_a.resize(kept);
    S.slot_b.resize(kept);
  }
  data.dissipated_energy += landing_dissipated;
  if (kept == 0) {
    data.contacts.assign(S.landed.begin(), S.landed.end());
    return;
  }
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
    if (const Contact* p = previousOf(data, S, S.found[k])) {
      r.lambda_n = p->normal_impulse;
      r.lambda_t = {r.t1.dot(p->friction_impulse_W), r.t2.dot(p->friction_impulse_W)};
    }
  }

  data.contact_sweeps = solveVelocities(settings, S.bodies, S.trees, S.rows, S.work).iterations;
  solvePositions(settings, S.bodies, S.trees, S.rows, S.work);
  for (std::size_t u = 0; u < S.trees.size(); ++u) {
    const int t = S.tree_of_solver_tree[u];
    if (S.tree_used[u]) takeTreeImpulses(S.trees[u], data.trees[t], model.trees[t].body);
  }
  // What the tree stage checks a tree's contact step against (stage_trees.cc): a floating
  // tree's momentum changes by the impulses of its contacts with anything else (its contacts
  // with itself cancel), and a tree's energy by the work of contacts with other moving bodies.
  for (TreeData& td : data.trees) td.contact_transfer = 0.0;
  for (std::size_t k = 0; k < kept; ++k) {
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

  // The impulses act on the bodies as CGA impulses, ΔΩ_B = (I∧n)⁻¹ T_imp (the lecture's rule,
  // doc/conventions.md (E17)), after the loads' kick: in world axes, T_imp adds its force to
  // the momentum and its moment about the centre to the angular momentum (contact_momentum.h).
  S.impulse_W.assign(S.bodies.size(), Eigen::Vector3d::Zero());
  S.impulse_moment_W.assign(S.bodies.size(), Eigen::Vector3d::Zero());
  for (std::size_t k = 0; k < kept; ++k) {
    const ContactRow& r = S.rows[k];
    const Eigen::Vector3d P = r.lambda_n * r.n + r.lambda_t.x() * r.t1 + r.lambda_t.y() * r.t2;
    const Eigen::Vector3d& p = S.found[k].point_W;
    if (r.a >= 0) {
      S.impulse_W[r.a] += P;
      S.impulse_moment_W[r.a] += (p - S.bodies[r.a].x).cross(P) + r.couple;
    }
    if (r.b >= 0) {
      S.impulse_W[r.b] -= P;
      S.impulse_moment_W[r.b] -= (p - S.bodies[r.b].x).cross(P) + r.couple;
    }
  }
  // The common normal of each slot's contacts (NaN: they differ, or one is an impact or a gap
  // that closes): only then is its sliding made trapezoidal.
  std::vector<Eigen::Vector3d>& common = S.common_normal;
  common.assign(S.bodies.size(), Eigen::Vector3d::Zero());
  for (std::size_t k = 0; k < kept; ++k) {
    const ContactRow& r = S.rows[k];
    const bool sustained = r.impact == 0.0 && r.depth >= -kTouching;
    for (int side = 0; side < 2; ++side) {
      const int s = side ? r.b : r.a;
      if (s < 0) continue;
      Eigen::Vector3d& n = common[s];
      if (!sustained)
        n.setConstant(std::numeric_limits<double>::quiet_NaN());
      else if (n.isZero(0.0))
        n = r.n;
      else if (n.allFinite() && (n - r.n).norm() > 1e-9 && (n + r.n).norm() > 1e-9)
        n.setConstant(std::numeric_limits<double>::quiet_NaN());
    }
  }
  // The energy book (doc/contacts.md#energy): per body, what it had at the step's start plus
  // the work of its applied loads (trapezoidal in Ω) minus what it has after the step (the
  // torque-free drift keeps the kinetic energy; the centre of mass moves by h v + shift).
  double dissipated = 0.0;
  const Eigen::Vector3d& g = model.scene.gravity_W;
  for (std::size_t s = 0; s < S.bodies.size(); ++s) {
    if (S.landing[s]) continue;           // stepped through already
    if (S.bodies[s].tree >= 0) continue;  // its tree books its step (stage_trees.cc)
    const int i = S.moving_of_slot[s];
    MovingBodyData& b = data.bodies[i];
    const dynamics::Inertia& I = model.moving[i].inertia;
    const cga::Bivelocity omega_start = b.state.omega_B;
    const Eigen::Vector3d& v_start = S.v_start[s];
    const Eigen::Vector3d x_start = dynamics::comPosition_W(b.state, lambda);
    MovingBodyData::ContactMomentum& m = S.momentum[s];
    addCompensated(m.v_hi, m.v_lo, S.impulse_W[s] / I.mass());
    addCompensated(m.L_hi, m.L_lo, S.impulse_moment_W[s]);
    b.state.omega_B = bodyVelocity(I, b.state.M_WB.rotation(), m, lambda);
    const Eigen::Vector3d v_end = velocity_W(m);
    b.contact_shift_W.setZero();
    if (common[s].allFinite() && !common[s].isZero(0.0)) {
      const Eigen::Vector3d dv = v_start - v_end;
      b.contact_shift_W = 0.5 * h * (dv - common[s].dot(dv) * common[s]);
    }
    // The position correction moves the pose: x += h p_v, R ← exp(h p_w) R. It must not add
    // energy: lifting the body by Δx against gravity costs ΔU = −m g·Δx, which is taken from
    // its kinetic energy (at most half of it; the rest of the overlap waits for later steps).
    const SolverBody& sb = S.bodies[s];
    Eigen::Vector3d x = x_start;
    if (!sb.pv.isZero(0.0) || !sb.pw.isZero(0.0)) {
      double f = 1.0;
      const double dU = -I.mass() * g.dot(h * sb.pv);
      if (dU > 0) {
        const double T_end = I.kineticEnergy(b.state.omega_B, lambda);
        f = std::min(1.0, 0.5 * T_end / dU);
        if (T_end > 0) {
          const double k = std::sqrt(1.0 - f * dU / T_end);
          b.state.omega_B = k * b.state.omega_B;
          m.v_hi *= k, m.v_lo *= k, m.L_hi *= k, m.L_lo *= k;
        }
      }
      const Eigen::Vector3d dr = f * h * sb.pw;
      const double angle = dr.norm();
      Eigen::Quaterniond R = b.state.M_WB.rotation();
      if (angle > 0) R = Eigen::Quaterniond(Eigen::AngleAxisd(angle, dr / angle)) * R;
      x += f * h * sb.pv;
      b.state.M_WB = cga::Motor::fromPose(R.normalized(), x, lambda);
      // Ω_B turns with the body (as a CGA impulse would leave it), so the correction's turn
      // keeps the kinetic energy; the carried momentum starts again from the turned state.
      if (angle > 0) m = stateMomentum(I, b.state, lambda);
    }
    const Eigen::Vector3d x_end = x + h * velocity_W(m) + b.contact_shift_W;
    double work = 0.0;
    if (b.loads.hasApplied()) {
      const cga::Moment T_applied = b.loads.appliedMoment_B(b.state.M_WB, lambda);
      const cga::Bivelocity mid = 0.5 * (omega_start + b.state.omega_B);
      work = h * (T_applied.rot.dot(mid.rot) + T_applied.trans.dot(mid.trans));
    }
    dissipated += I.kineticEnergy(omega_start, lambda) - I.kineticEnergy(b.state.omega_B, lambda) +
                  I.mass() * g.dot(x_end - x_start) + work;
    b.contact_step = MovingBodyData::ContactStep::kDrift;
    b.contact_momentum = m;
    b.contact_momentum.valid = false;
    b.contact_momentum.pending = true;
    b.integrator->reset();
  }
  data.dissipated_energy += dissipated;

  // The contacts of this step, with their impulses, for reports and the next warm start.
  data.contacts.assign(S.found.begin(), S.found.end());
  for (std::size_t k = 0; k < kept; ++k) {
    const ContactRow& r = S.rows[k];
    data.contacts[k].normal_impulse = r.lambda_n;
    data.contacts[k].friction_impulse_W = r.lambda_t.x() * r.t1 + r.lambda_t.y() * r.t2;
  }
  data.contacts.insert(data.contacts.end(), S.landed.begin(), S.landed.end());
}

}  // namespace

void solveContacts(const Model& model, Data& data) {
  if (!data.contact_scratch) data.contact_scratch = std::make_shared<ContactScratch>();
  ContactScratch& S = *data.contact_scratch;
  wakeChanged(model, data, S.sleep);
  solveAwake(model, data, S);
  fallAsleep(model, data, S.sleep);
}

}  // namespace sim
}  // namespace cga_rigid_sim
