// Landings (contact_landing.h, doc/contacts.md#impacts): the landing time of a body over the
// plane, its landing, and the land sub-stage of the contact step (contact_step.h).
#include "contact/contact_landing.h"

#include <algorithm>
#include <cmath>

#include "cga_rigid_sim/body/derived.h"
#include "cga_rigid_sim/body/impulse.h"
#include "contact/contact_detection.h"
#include "contact/contact_step.h"

namespace cga_rigid_sim {
namespace sim {

// The first instant in (0, h] at which a gap to the plane closes, for a body that only has
// plane gaps: each contact point's height follows d(t) = gap + u t + ½ a t² (u its normal
// velocity, a gravity's normal component; exact for a sphere, whose lowest point does not
// depend on the rotation). 0 when none closes at more than the resting speed.
double landingTime(const Model& model, const Data& data, const ContactScratch& S, std::size_t first,
                   std::size_t last, double rest_speed) {
  const double h = model.config.dt;
  double t_land = 0.0;
  for (std::size_t k = first; k < last; ++k) {
    const Contact& c = S.found[k];
    const dynamics::BodyState& st = data.bodies[model.moving_of_body[c.body_a]].state;
    const Eigen::Vector3d x = dynamics::comPosition_W(st, model.lambda);
    const double u = c.normal_W.dot(dynamics::comVelocity_W(st, model.lambda) +
                                    dynamics::angularVelocity_W(st).cross(c.point_W - x));
    const double a = c.normal_W.dot(model.scene.gravity_W);
    const double gap = -c.depth;
    const double disc = u * u - 2.0 * a * gap;
    if (u >= 0 || disc < 0) continue;
    const double t = 2.0 * gap / (-u + std::sqrt(disc));  // the smaller root, stably
    if (t > h || -(u + a * t) <= rest_speed) continue;
    if (t_land == 0.0 || t < t_land) t_land = t;
  }
  return t_land;
}

// A landing (doc/contacts.md#impacts): moving body i is stepped by its own integrator to the
// instant t it touches the plane, its contacts there are solved with restitution (no kick: the
// integrator has carried the loads to t), and it is stepped through the rest of the step. Its
// contacts are appended to `out`; returns the kinetic energy the impulses took out.
double land(const Model& model, Data& data, ContactScratch& S, int i, double t,
            const SolverSettings& settings, std::vector<Contact>& out) {
  MovingBodyData& b = data.bodies[i];
  const dynamics::Inertia& I = model.moving[i].inertia;
  const double lambda = model.lambda, h = model.config.dt;
  b.integrator->reset();
  b.integrator->step(I, b.loads, lambda, t, b.state);
  b.integrator->reset();
  const double rest = std::max(h - t, 1e-9 * h);
  S.land_found.clear();
  const double reach_speed =
      dynamics::comVelocity_W(b.state, lambda).norm() + dynamics::angularVelocity_W(b.state).norm();
  detectPlaneContactsOf(model, data, *S.cache, model.moving[i].body, 1e-9 + rest * reach_speed,
                        S.land_found);
  double dissipated = 0.0;
  if (!S.land_found.empty()) {
    S.land_bodies.assign(1, solverBody(model, b.state, b.state.omega_B, i));
    S.land_slot_a.assign(S.land_found.size(), 0);
    S.land_slot_b.assign(S.land_found.size(), -1);
    SolverSettings st = settings;
    st.h = rest;
    st.kinetic_energy = true;
    prepareRows(S.land_found, S.land_bodies, S.land_trees, S.land_slot_a, S.land_slot_b,
                S.land_rows);
    for (ContactRow& r : S.land_rows) {
      r.lambda_n = 0.0;
      r.lambda_t.setZero();
    }
    const SolveStats stats = solveVelocities(st, S.land_bodies, S.land_trees, S.land_rows, S.work);
    dissipated = stats.kinetic_before - stats.kinetic_after;
    cga::Moment T;
    for (std::size_t k = 0; k < S.land_found.size(); ++k) {
      const ContactRow& r = S.land_rows[k];
      const Eigen::Vector3d P = r.lambda_n * r.n + r.lambda_t.x() * r.t1 + r.lambda_t.y() * r.t2;
      T += dynamics::impulseMoment_B(b.state, cga::Force(P, 0.0), S.land_found[k].point_W, r.couple,
                                     lambda);
      Contact c = S.land_found[k];
      c.normal_impulse = r.lambda_n;
      c.friction_impulse_W = r.lambda_t.x() * r.t1 + r.lambda_t.y() * r.t2;
      out.push_back(c);
    }
    b.state.omega_B += I.solve(T, lambda);
  }
  b.integrator->step(I, b.loads, lambda, h - t, b.state);
  b.integrator->reset();
  b.contact_step = MovingBodyData::ContactStep::kDone;
  return dissipated;
}

bool landBodies(const Model& model, Data& data, ContactScratch& S, const SolverSettings& st) {
  // Landings: a body whose contacts are all gaps to the ground plane that close within the
  // step faster than the resting speed is stepped to the instant it lands and bounces there.
  std::size_t kept = S.found.size();
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
        const double t = landingTime(model, data, S, k, e, st.rest_speed);
        if (t > 0)
          landing_dissipated += land(model, data, S, S.moving_of_slot[s], t, st, S.landed);
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
    return false;
  }
  return true;
}

}  // namespace sim
}  // namespace cga_rigid_sim
