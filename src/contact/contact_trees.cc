// Articulated trees in the contact step (contact_trees.h, doc/contacts.md#trees): a tree's
// energy and input power, its kick into the solver's view of it, and its impulses taken back.
#include "contact/contact_trees.h"

#include <algorithm>

namespace cga_rigid_sim {
namespace sim {
namespace {

// The world twist (ω; v_o) of a link's screw s = (w, u) (e23, e31, e12; e1n, e2n, e3n) in the
// link's frame, the link at M_W (x ↦ R x + a): the screw moved to the world, (R w, R u +
// (a/λ) × R w) (adjointMatrix's blocks, doc/articulated.md (A1)), with v_o = λ times its second
// half the velocity of the point at the world origin.
Eigen::Matrix<double, 6, 1> twistOf(const cga::Motor& M_W, const cga::Bivelocity& s,
                                    double lambda) {
  const Eigen::Matrix3d R = M_W.rotation().toRotationMatrix();
  const Eigen::Vector3d Rw = R * s.rot;
  Eigen::Matrix<double, 6, 1> c;
  c << Rw, lambda * (R * s.trans) + M_W.translation(lambda).cross(Rw);
  return c;
}

// The loads' generalized acceleration ν̇ = M⁻¹ (τ + Q) of tree t, into the kick scratch (with
// the links' external moments f), at rest in the same pose, with no velocity terms (they
// belong to the drift): from M's factor when it is given (Q by the RNEA's inward pass, O(n),
// and the factor's sparse solve), else by ABA (mimic joints, servos).
void accelerationAtRest(const Model& model, Data& data, int t, const TreeFactor* factor) {
  const dynamics::ArticulatedBody& tree = model.trees[t].body;
  const TreeData& td = data.trees[t];
  TreeStageScratch::Kick& S = data.tree_scratch.kick;
  S.still = S.kin;
  for (auto& w : S.still.omega) w = cga::Bivelocity();
  dynamics::externalMoments(tree, S.still, td.loads, S.f);
  if (factor) {
    dynamics::forcesAtRest(tree, S.still, td.loads.effort, S.f, S.nu_dot,
                           data.tree_scratch.algorithms);
    factor->solveInPlace(S.nu_dot);
    return;
  }
  S.state = td.state;
  S.state.omega_0 = cga::Bivelocity();
  S.state.v.setZero();
  dynamics::forwardDynamics(tree, S.state, S.still, td.loads.effort, S.f, S.nu_dot,
                            data.tree_scratch.algorithms);
}

// Servos in a contact step's kick, linearly implicit (doc/articulated.md#servos): their torque
// s = s₀ − (h Kd + h² Kp) ν̇ at the kick's end, s₀ = Kp (r − q − h ν) + Kd (ṙ − ν), with
// (M + h Kd + h² Kp) ν̇ = M ν̇₀ + s₀ (ν̇₀: the loads' acceleration without servos; on the
// independent coordinates with mimic joints). The clamped efforts replace td.loads.effort, and
// the kick then takes them as given efforts (accelerationAtRest again): stable at any gains,
// exact for a clamped joint, booked as the actuators' work like every effort.
void kickServos(const Model& model, Data& data, int t, const Eigen::MatrixXd& M) {
  const dynamics::ArticulatedBody& tree = model.trees[t].body;
  TreeData& td = data.trees[t];
  const dynamics::JointServos& sv = td.loads.servos;
  const double h = model.config.dt;
  TreeStageScratch::Kick& S = data.tree_scratch.kick;
  const int n = tree.jointCount();
  S.servo_rhs.noalias() = M * S.nu_dot;
  S.servo_A = M;
  S.servo_s0.resize(n);
  for (int k = 0; k < n; ++k) {
    const int i = tree.velocityIndex(k);
    const double v = td.state.v[k];
    S.servo_s0[k] = sv.torque(k, td.state.q[k] + h * v, v);
    S.servo_rhs[i] += S.servo_s0[k];
    S.servo_A(i, i) += h * sv.kd[k] + h * h * sv.kp[k];
  }
  if (tree.hasMimic()) {
    dynamics::reduceMatrix(tree, S.servo_A, S.servo_A_r, data.tree_scratch.algorithms);
    dynamics::reduceForce(tree, S.servo_rhs, S.servo_rhs_r);
    S.servo_llt.compute(S.servo_A_r);
    S.servo_llt.solveInPlace(S.servo_rhs_r);
    dynamics::expandVelocity(tree, S.servo_rhs_r, S.servo_rhs);
  } else {
    S.servo_llt.compute(S.servo_A);
    S.servo_llt.solveInPlace(S.servo_rhs);  // ν̇
  }
  for (int k = 0; k < n; ++k) {
    const int i = tree.velocityIndex(k);
    const double s = S.servo_s0[k] - (h * sv.kd[k] + h * h * sv.kp[k]) * S.servo_rhs[i];
    const double limit = tree.joints()[k].effort_limit;
    td.loads.effort[k] = std::clamp(td.loads.effort[k] + s, -limit, limit);
  }
}

// The world momentum floating tree t's step must end with, but for the contacts' external
// impulses (the contacts stage adds them): the momentum now plus the loads' impulse h W over
// the step; and its scale.
void noteExpectedMomentum(const Model& model, Data& data, int t) {
  const dynamics::ArticulatedBody& tree = model.trees[t].body;
  TreeData& td = data.trees[t];
  const double h = model.config.dt, lambda = model.lambda;
  const TreeStageScratch::Kick& S = data.tree_scratch.kick;
  cga::Moment W;
  double scale = 0.0;
  for (int b = 0; b < tree.bodyCount(); ++b) {
    W += S.kin.M_W[b].apply(S.f[b], lambda);
    scale += tree.inertiaOf(b).mass() * S.kin.omega[b].linear(lambda).norm();
  }
  td.contact_momentum_expected = dynamics::worldMomentum(tree, S.kin) + W * h;
  td.contact_momentum_scale = scale + h * W.force(lambda).norm();
}

// The scale of the energy guard's tolerance (contact_tree_end.cc): symplectic Euler's error over
// one step, ½ h² (ν̇ᵀ M ν̇ ∓ νᵀ (∂Q/∂q) ν), bounded by the kick's and the rates' terms.
void noteEnergySlack(const Model& model, Data& data, int t, const SolverTree& out) {
  const dynamics::ArticulatedBody& tree = model.trees[t].body;
  TreeData& td = data.trees[t];
  const double h = model.config.dt;
  TreeStageScratch::Kick& S = data.tree_scratch.kick;
  const double rate = std::max(out.nu.cwiseAbs().maxCoeff(),
                               td.state.v.size() ? td.state.v.cwiseAbs().maxCoeff() : 0.0);
  const double T = dynamics::kineticEnergy(tree, S.kin);
  S.M_nu_dot.noalias() = out.M * S.nu_dot;
  td.contact_energy_slack = h * h * S.nu_dot.dot(S.M_nu_dot) + (h * rate) * (h * rate) * T;
}

// With mimic joints the solver works on the independent coordinates ν_r: M_r = Gᵀ M G, and
// each joint's twist goes into its coordinate's column with its multiplier (pointJacobian).
void onIndependentCoordinates(Data& data, const dynamics::ArticulatedBody& tree, SolverTree& out) {
  TreeStageScratch::Kick& S = data.tree_scratch.kick;
  if (tree.hasMimic()) {
    dynamics::reduceVelocity(tree, out.nu, S.nu_dot);
    out.nu = S.nu_dot;
    dynamics::reduceMatrix(tree, out.M, S.M_r, data.tree_scratch.algorithms);
    out.M = S.M_r;
  }
}

// Per joint its column and multiplier, per coordinate its world twist (the floating base's six
// first), per body its parent: what a contact point's Jacobian is made of.
void makeCoordinates(const Model& model, const Data& data, const dynamics::ArticulatedBody& tree,
                     SolverTree& out) {
  const double lambda = model.lambda;
  const TreeStageScratch::Kick& S = data.tree_scratch.kick;
  out.column.resize(tree.jointCount());
  out.multiplier.resize(tree.jointCount());
  for (int k = 0; k < tree.jointCount(); ++k) {
    out.column[k] = tree.reducedIndex(k);
    out.multiplier[k] = tree.mimicMultiplier(k);
  }
  const int n = tree.velocityCount();
  out.twist.resize(6, n);
  out.floating = tree.floating();
  if (tree.floating()) {
    const Eigen::Matrix<double, 6, 6> X = dynamics::adjointMatrix(S.kin.M_W[0], lambda);
    for (int j = 0; j < 6; ++j) {
      out.twist.col(j) = X.col(j);
      out.twist(3 + 0, j) *= lambda;
      out.twist(3 + 1, j) *= lambda;
      out.twist(3 + 2, j) *= lambda;
    }
  }
  for (int k = 0; k < tree.jointCount(); ++k)
    out.twist.col(tree.velocityIndex(k)) = twistOf(S.kin.M_W[k + 1], tree.screwInChild(k), lambda);
  out.parent.resize(tree.bodyCount());
  out.parent[0] = -1;
  for (int b = 1; b < tree.bodyCount(); ++b) out.parent[b] = tree.parentOf(b);
  // The coordinates' parents, the sparsity of M the factor keeps (none with mimic joints).
  out.coordinate_parent.clear();
  if (tree.hasMimic()) return;
  const int base = tree.floating() ? 6 : 0;
  out.coordinate_parent.resize(n);
  for (int j = 0; j < base; ++j) out.coordinate_parent[j] = j - 1;
  for (int k = 0; k < tree.jointCount(); ++k) {
    const int p = tree.parentOf(k + 1);
    out.coordinate_parent[tree.velocityIndex(k)] = p == 0 ? base - 1 : tree.velocityIndex(p - 1);
  }
}

// Every coordinate with a position limit: a row the solver keeps within it (its column
// M⁻¹ e_k is made only when the row acts). With mimic joints the coordinates are the
// independent joints', with their followers' limits mapped onto them. The rows keep their
// storage from step to step.
void makeLimitRows(const dynamics::ArticulatedBody& tree, const TreeData& td, SolverTree& out) {
  std::size_t rows = 0;
  for (const dynamics::JointCoordinate& c : tree.coordinates()) rows += c.hasLimits() ? 1 : 0;
  out.limits.resize(rows);
  rows = 0;
  for (const dynamics::JointCoordinate& c : tree.coordinates()) {
    if (!c.hasLimits()) continue;
    SolverTree::LimitRow& r = out.limits[rows++];
    // The last step's impulses, kept as a warm start when the row is the same joint's.
    const bool same = r.index == tree.reducedIndex(c.joint);
    r.y_lower_last = same ? r.y_lower : 0.0;
    r.y_upper_last = same ? r.y_upper : 0.0;
    r.index = tree.reducedIndex(c.joint);
    r.q = td.state.q[c.joint];
    r.lower = c.lower;
    r.upper = c.upper;
    r.y_lower = r.y_upper = r.p_lower = r.p_upper = 0.0;
  }
}

}  // namespace

double treeEnergy(const Model& model, int t, const dynamics::TreeKinematics& kin) {
  const dynamics::ArticulatedBody& tree = model.trees[t].body;
  const double lambda = model.lambda;
  double E = dynamics::kineticEnergy(tree, kin);
  for (int b = tree.floating() ? 0 : 1; b < tree.bodyCount(); ++b)
    E -= tree.inertiaOf(b).mass() * model.scene.gravity_W.dot(kin.M_W[b].translation(lambda));
  return E;
}

double treeInputPower(const Model& model, const Data& data, int t,
                      const dynamics::TreeKinematics& kin, const Eigen::VectorXd& rates) {
  const TreeModel& tm = model.trees[t];
  const TreeData& td = data.trees[t];
  double P = td.loads.effort.dot(rates);
  for (int b = tm.body.floating() ? 0 : 1; b < tm.body.bodyCount(); ++b) {
    const dynamics::Loads* L = td.loads.applied[b];
    if (!L) continue;
    const cga::Moment T = L->appliedMoment_B(kin.M_W[b], model.lambda);
    P += T.rot.dot(kin.omega[b].rot) + T.trans.dot(kin.omega[b].trans);
  }
  return P;
}

void kickTree(const Model& model, Data& data, int t, SolverTree& out,
              dynamics::TreeKinematics& kicked) {
  const dynamics::ArticulatedBody& tree = model.trees[t].body;
  TreeData& td = data.trees[t];
  const double h = model.config.dt;
  TreeStageScratch::Kick& S = data.tree_scratch.kick;

  // The kinematics and M(q) the last contact step left, when the tree is still in its state.
  const TreeData::ContactEnd& end = td.contact_end;
  const bool from_end = end.valid && dynamics::identical(td.state, end.state);
  if (from_end)
    S.kin = end.kin;  // (copies into storage of the same size: no allocation)
  else
    dynamics::treeKinematics(tree, td.state, S.kin);
  td.contact_energy_start = treeEnergy(model, t, S.kin);
  if (from_end && end.has_mass)
    out.M = end.M;
  else
    dynamics::massMatrix(tree, S.kin, out.M, data.tree_scratch.algorithms);
  // M's factor, which the solve needs, also gives the kick's acceleration (without mimic
  // joints, whose solve works on M_r, and servos, whose kick is implicit).
  const bool by_factor = !tree.hasMimic() && !td.loads.servos.active();
  if (by_factor) {
    makeCoordinates(model, data, tree, out);
    out.factor.compute(out.M, out.coordinate_parent);
  }
  accelerationAtRest(model, data, t, by_factor && out.factor.ok() ? &out.factor : nullptr);
  if (td.loads.servos.active()) {  // their efforts for the step, then the kick with them
    kickServos(model, data, t, out.M);
    accelerationAtRest(model, data, t, nullptr);
  }
  td.contact_power_start = treeInputPower(model, data, t, S.kin, td.state.v);
  if (tree.floating()) noteExpectedMomentum(model, data, t);
  out.nu.resize(tree.velocityCount());
  if (tree.floating()) {
    out.nu.head<3>() = td.state.omega_0.rot;
    out.nu.segment<3>(3) = td.state.omega_0.trans;
  }
  out.nu.tail(tree.jointCount()) = td.state.v;
  out.nu += h * S.nu_dot;

  noteEnergySlack(model, data, t, out);
  onIndependentCoordinates(data, tree, out);
  if (!by_factor) {
    makeCoordinates(model, data, tree, out);
    out.factor.compute(out.M, out.coordinate_parent);
  }
  makeLimitRows(tree, td, out);

  S.state = td.state;
  dynamics::expandVelocity(tree, out.nu, S.nu_dot);
  dynamics::setVelocityVector(tree, S.nu_dot, S.state);
  kicked = S.kin;  // the kick changes the rates only: the same poses, new velocities
  dynamics::treeVelocities(tree, S.state, kicked);
  // The kick's work: what it adds to the kinetic energy, to the bit for a constant effort
  // (½ m (v'² − v²) = h F (v + v')/2), against which the energy guard measures the contacts.
  td.contact_kick_work =
      0.5 * h * (td.contact_power_start + treeInputPower(model, data, t, kicked, S.state.v));
}

void takeTreeImpulses(const Model& model, Data& data, int t, const SolverTree& solved,
                      const dynamics::TreeKinematics& kicked) {
  const dynamics::ArticulatedBody& tree = model.trees[t].body;
  TreeData& td = data.trees[t];
  // (ν and pν on the independent coordinates: every joint's from them.)
  dynamics::expandVelocity(tree, solved.nu, td.contact_nu);
  dynamics::setVelocityVector(tree, td.contact_nu, td.state);
  dynamics::expandVelocity(tree, solved.pnu, td.contact_shift);
  td.contact_kicked = true;
  // The impulses changed the rates only: the kick's poses with the velocities made anew are
  // the kinematics of the new state, and M(q) is the kick's (on every joint without mimic
  // joints). The drift starts from them (its integrator's cache dropped).
  dynamics::TreeKinematics& kin = data.tree_scratch.solved_kin;
  kin = kicked;  // (copies into storage of the same size: no allocation)
  dynamics::treeVelocities(tree, td.state, kin);
  if (tree.floating()) td.contact_momentum_solved = dynamics::worldMomentum(tree, kin);
  td.integrator->startFrom(td.state, kin, tree.hasMimic() ? nullptr : &solved.M);
}

}  // namespace sim
}  // namespace cga_rigid_sim
