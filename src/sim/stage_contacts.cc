// The contacts stage (doc/contacts.md): detection at the step's start, then for every body that
// touches something a kick by its loads and the contact impulses, solved together; the
// integration then drifts those bodies torque-free (stage_integrate.cc). Bodies that touch
// nothing are left alone: they keep their exact or symplectic path.
#include <algorithm>
#include <tuple>

#include "cga_rigid_sim/dynamics/derived.h"
#include "cga_rigid_sim/dynamics/impulse.h"
#include "cga_rigid_sim/sim/stages.h"
#include "contact_scratch.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

auto pairKey(const Contact& c) { return std::make_tuple(c.body_a, c.shape_a, c.body_b, c.shape_b); }

// Last step's impulse of the same contact, if it existed: same pair of shapes and the same
// vertex, or (no vertex known) a point within 2 mm.
const Contact* previousOf(const Data& data, const ContactScratch& S, const Contact& c) {
  const auto key = pairKey(c);
  auto it = std::lower_bound(S.previous.begin(), S.previous.end(), key,
                             [&data](std::size_t k, const auto& v) {
                               return pairKey(data.contacts[k]) < v;
                             });
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
  }
  return S.slot_of_moving[i];
}

// Ω_B after the loads' kick over h: ΔΩ_B = h (I∧n)⁻¹ (T_applied + T_gravity).
cga::Bivelocity kicked(const Model& model, const MovingBodyData& b, int i) {
  const dynamics::Inertia& I = model.moving[i].inertia;
  const double lambda = model.lambda, h = model.config.dt;
  cga::Moment T = b.loads.gravityMoment_B(I.mass(), b.state.M_WB, lambda);
  if (b.loads.hasApplied()) T += b.loads.appliedMoment_B(b.state.M_WB, lambda);
  return b.state.omega_B + h * I.solve(T, lambda);
}

SolverBody solverBody(const Model& model, const dynamics::BodyState& s, const cga::Bivelocity& omega_B,
                      int i) {
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

}  // namespace

void solveContacts(const Model& model, Data& data) {
  if (!data.contact_scratch) data.contact_scratch = std::make_shared<ContactScratch>();
  ContactScratch& S = *data.contact_scratch;
  S.found.clear();
  detectContacts(model, data, *S.cache, S.found);
  if (S.found.empty()) {
    data.contacts.clear();
    return;
  }
  const double h = model.config.dt, lambda = model.lambda;

  // Slots for every moving body in a contact, and their kicked velocities.
  S.slot_of_moving.assign(data.bodies.size(), -1);
  S.moving_of_slot.clear();
  S.slot_a.resize(S.found.size());
  S.slot_b.resize(S.found.size());
  for (std::size_t k = 0; k < S.found.size(); ++k) {
    S.slot_a[k] = slotOf(model, S, S.found[k].body_a);
    S.slot_b[k] = slotOf(model, S, S.found[k].body_b);
  }
  S.kicked_B.resize(S.moving_of_slot.size());
  S.bodies.resize(S.moving_of_slot.size());
  for (std::size_t s = 0; s < S.moving_of_slot.size(); ++s) {
    const int i = S.moving_of_slot[s];
    S.kicked_B[s] = kicked(model, data.bodies[i], i);
    S.bodies[s] = solverBody(model, data.bodies[i].state, S.kicked_B[s], i);
  }

  // A speculative contact whose gap stays open over the step is dropped: a body near the
  // ground but not reaching it keeps its own path.
  std::size_t kept = 0;
  for (std::size_t k = 0; k < S.found.size(); ++k) {
    const Contact& c = S.found[k];
    if (c.depth <= 0) {
      const int a = S.slot_a[k], b = S.slot_b[k];
      Eigen::Vector3d u = S.bodies[a].v + S.bodies[a].w.cross(c.point_W - S.bodies[a].x);
      if (b >= 0) u -= S.bodies[b].v + S.bodies[b].w.cross(c.point_W - S.bodies[b].x);
      if (c.normal_W.dot(u) * h >= c.depth) continue;
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
  settings.rest_speed = 2.0 * model.scene.gravity_W.norm() * h;
  prepareRows(S.found, S.bodies, S.slot_a, S.slot_b, settings, S.rows);

  // Warm start from last step's impulses of the same contacts.
  S.previous.resize(data.contacts.size());
  for (std::size_t k = 0; k < S.previous.size(); ++k) S.previous[k] = k;
  std::sort(S.previous.begin(), S.previous.end(), [&data](std::size_t x, std::size_t y) {
    return pairKey(data.contacts[x]) < pairKey(data.contacts[y]) ||
           (pairKey(data.contacts[x]) == pairKey(data.contacts[y]) && x < y);
  });
  for (std::size_t k = 0; k < kept; ++k) {
    ContactRow& r = S.rows[k];
    r.lambda_n = 0.0;
    r.lambda_t.setZero();
    if (const Contact* p = previousOf(data, S, S.found[k])) {
      r.lambda_n = p->normal_impulse;
      r.lambda_t = {r.t1.dot(p->friction_impulse_W), r.t2.dot(p->friction_impulse_W)};
    }
  }

  const SolveStats stats = solveVelocities(settings, S.bodies, S.rows);
  solvePositions(settings, S.bodies, S.rows);

  // The impulses act on the states as CGA impulses: ΔΩ_B = (I∧n)⁻¹ T_imp (the lecture's rule,
  // doc/conventions.md (E17)), after the loads' kick.
  std::vector<cga::Moment>& T = S.impulse_B;
  T.assign(S.bodies.size(), cga::Moment());
  for (std::size_t k = 0; k < kept; ++k) {
    const ContactRow& r = S.rows[k];
    const Eigen::Vector3d P = r.lambda_n * r.n + r.lambda_t.x() * r.t1 + r.lambda_t.y() * r.t2;
    const Eigen::Vector3d& p = S.found[k].point_W;
    for (int side = 0; side < 2; ++side) {
      const int s = side ? r.b : r.a;
      if (s < 0) continue;
      const dynamics::BodyState& st = data.bodies[S.moving_of_slot[s]].state;
      T[s] += dynamics::impulseMoment_B(st, cga::Force(side ? Eigen::Vector3d(-P) : P, 0.0), p,
                                        Eigen::Vector3d::Zero(), lambda);
    }
  }
  double potential_change = 0.0;
  const Eigen::Vector3d& g = model.scene.gravity_W;
  for (std::size_t s = 0; s < S.bodies.size(); ++s) {
    const int i = S.moving_of_slot[s];
    MovingBodyData& b = data.bodies[i];
    const dynamics::Inertia& I = model.moving[i].inertia;
    b.state.omega_B = S.kicked_B[s] + I.solve(T[s], lambda);
    // The position correction moves the pose only: x += h p_v, R ← exp(h p_w) R.
    const SolverBody& sb = S.bodies[s];
    if (!sb.pv.isZero(0.0) || !sb.pw.isZero(0.0)) {
      const Eigen::Vector3d dx = h * sb.pv, dr = h * sb.pw;
      const double angle = dr.norm();
      Eigen::Quaterniond R = b.state.M_WB.rotation();
      if (angle > 0) R = Eigen::Quaterniond(Eigen::AngleAxisd(angle, dr / angle)) * R;
      b.state.M_WB = cga::Motor::fromPose(R.normalized(), sb.x + dx, lambda);
      potential_change -= I.mass() * g.dot(dx);
    }
    b.contact_step = true;
    b.integrator->reset();
  }
  data.dissipated_energy += stats.kinetic_before - stats.kinetic_after - potential_change;

  // The contacts of this step, with their impulses, for reports and the next warm start.
  data.contacts.assign(S.found.begin(), S.found.end());
  for (std::size_t k = 0; k < kept; ++k) {
    const ContactRow& r = S.rows[k];
    data.contacts[k].normal_impulse = r.lambda_n;
    data.contacts[k].friction_impulse_W = r.lambda_t.x() * r.t1 + r.lambda_t.y() * r.t2;
  }
}

}  // namespace sim
}  // namespace cga_rigid_sim
