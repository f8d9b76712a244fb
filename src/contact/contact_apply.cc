// The contact step's apply (contact_step.h): each free body in a contact takes the sum of its
// impulses as a CGA impulse, its position correction (paid from its kinetic energy where it
// lifts the body) and, where all its contacts share one normal, the shift that makes its sliding
// trapezoidal; its energy is booked; the integrate stage then drifts it (contact_drift.cc).
// Tree links take their impulses through their tree (contact_trees.cc, stage_trees.cc).
#include <algorithm>
#include <cmath>
#include <limits>

#include "cga_rigid_sim/body/derived.h"
#include "contact/contact_momentum.h"
#include "contact/contact_step.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// Per slot: the sum of its contact impulses and of their moments about its centre (with the
// patch couples), world axes.
void sumImpulses(ContactScratch& S) {
  S.impulse_W.assign(S.bodies.size(), Eigen::Vector3d::Zero());
  S.impulse_moment_W.assign(S.bodies.size(), Eigen::Vector3d::Zero());
  for (std::size_t k = 0; k < S.found.size(); ++k) {
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
}

// The common normal of each slot's contacts (NaN: they differ, or one is an impact or a gap
// that closes): only then is its sliding made trapezoidal.
void findCommonNormals(ContactScratch& S) {
  std::vector<Eigen::Vector3d>& common = S.common_normal;
  common.assign(S.bodies.size(), Eigen::Vector3d::Zero());
  for (std::size_t k = 0; k < S.found.size(); ++k) {
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
}

// The position correction moves the pose: x += h p_v, R ← exp(h p_w) R. It must not add
// energy: lifting the body by Δx against gravity costs ΔU = −m g·Δx, which is taken from its
// kinetic energy (at most half of it; the rest of the overlap waits for later steps). Returns
// the centre of mass after it.
Eigen::Vector3d correctPosition(const Model& model, const SolverBody& sb,
                                const dynamics::Inertia& I, const Eigen::Vector3d& x_start,
                                MovingBodyData& b, MovingBodyData::ContactMomentum& m) {
  const double h = model.config.dt, lambda = model.lambda;
  const Eigen::Vector3d& g = model.scene.gravity_W;
  Eigen::Vector3d x = x_start;
  if (sb.pv.isZero(0.0) && sb.pw.isZero(0.0)) return x;
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
  // Ω_B turns with the body (as a CGA impulse would leave it), so the correction's turn keeps
  // the kinetic energy; the carried momentum starts again from the turned state.
  if (angle > 0) m = stateMomentum(I, b.state, lambda);
  return x;
}

// Slot s's free body takes its impulses, its sliding shift and its position correction, and is
// left for the drift; returns the energy its contact step dissipated (doc/contacts.md#energy):
// what it had at the step's start plus the work of its applied loads (trapezoidal in Ω) minus
// what it has after the step (the torque-free drift keeps the kinetic energy; the centre of
// mass moves by h v + shift).
double applyToBody(const Model& model, Data& data, ContactScratch& S, std::size_t s) {
  const double h = model.config.dt, lambda = model.lambda;
  const Eigen::Vector3d& g = model.scene.gravity_W;
  const std::vector<Eigen::Vector3d>& common = S.common_normal;
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
  const Eigen::Vector3d x = correctPosition(model, S.bodies[s], I, x_start, b, m);
  const Eigen::Vector3d x_end = x + h * velocity_W(m) + b.contact_shift_W;
  double work = 0.0;
  if (b.loads.hasApplied()) {
    const cga::Moment T_applied = b.loads.appliedMoment_B(b.state.M_WB, lambda);
    const cga::Bivelocity mid = 0.5 * (omega_start + b.state.omega_B);
    work = h * (T_applied.rot.dot(mid.rot) + T_applied.trans.dot(mid.trans));
  }
  const double dissipated = I.kineticEnergy(omega_start, lambda) -
                            I.kineticEnergy(b.state.omega_B, lambda) +
                            I.mass() * g.dot(x_end - x_start) + work;
  b.contact_step = MovingBodyData::ContactStep::kDrift;
  b.contact_momentum = m;
  b.contact_momentum.valid = false;
  b.contact_momentum.pending = true;
  b.integrator->reset();
  return dissipated;
}

}  // namespace

void applyToBodies(const Model& model, Data& data, ContactScratch& S) {
  // The impulses act on the bodies as CGA impulses, ΔΩ_B = (I∧n)⁻¹ T_imp (the lecture's rule,
  // doc/conventions.md (E17)), after the loads' kick: in world axes, T_imp adds its force to
  // the momentum and its moment about the centre to the angular momentum (contact_momentum.h).
  sumImpulses(S);
  findCommonNormals(S);
  double dissipated = 0.0;
  for (std::size_t s = 0; s < S.bodies.size(); ++s) {
    if (S.landing[s]) continue;           // stepped through already
    if (S.bodies[s].tree >= 0) continue;  // its tree books its step (contact_tree_end.cc)
    dissipated += applyToBody(model, data, S, s);
  }
  data.dissipated_energy += dissipated;
}

}  // namespace sim
}  // namespace cga_rigid_sim
