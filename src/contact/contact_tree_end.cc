// The end of a tree's contact step (doc/contacts.md#trees, doc/articulated.md#faults): after
// the drift, the position correction and the step's energy book; the contact step's guards on
// energy and momentum.
#include <algorithm>
#include <cmath>
#include <limits>

#include "contact/contact_trees.h"
#include "sim/tree_faults.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// A contact step's energy may rise by the kick-and-drift's own error (symplectic Euler, first
// order: ½ h² (ν̇ᵀ M ν̇ − νᵀ ∂Q/∂q ν) per step, either sign, TreeData::contact_energy_slack
// bounds it), ten times that, plus the drift's and the energies' round-off. A contact solve that
// creates energy (the faults this guards against gained joules in one step) is far above.
constexpr double kEnergySlackFactor = 10.0;
constexpr double kEnergyTolerance = 1e-9;
// A floating tree's momentum after a contact step equals the one before plus the loads' and
// the external contacts' impulses, to round-off of the sums that carry it (the kick's M⁻¹, the
// midpoint's carried momentum, the links' momenta): relative to the momenta involved.
constexpr double kMomentumTolerance = 1e-9;

// The deepest contact of tree t in this step (its bodies, for the fault's message).
void deepestContactOf(const Model& model, const Data& data, int t, TreeFaults& f) {
  double deepest = -std::numeric_limits<double>::infinity();
  const auto inTree = [&](int j) {
    const int i = j < 0 ? -1 : model.moving_of_body[j];
    return i >= 0 && model.tree_of_moving[i] == t;
  };
  for (const Contact& c : data.contacts)
    if ((inTree(c.body_a) || inTree(c.body_b)) && c.depth > deepest) {
      deepest = c.depth;
      f.body_a = c.body_a;
      f.body_b = c.body_b;
    }
}

using Vector6 = Eigen::Matrix<double, 6, 1>;

// `E` plus the tree's potential energy in gravity at the poses of `kin`, added body by body as
// treeEnergy adds it: with E its kinetic energy, treeEnergy to the bit; with 0, the potential
// alone, which needs no velocities.
double plusPotential(const Model& model, int t, const dynamics::TreeKinematics& kin, double E) {
  const dynamics::ArticulatedBody& tree = model.trees[t].body;
  for (int b = tree.floating() ? 0 : 1; b < tree.bodyCount(); ++b)
    E -= tree.inertiaOf(b).mass() * model.scene.gravity_W.dot(kin.M_W[b].translation(model.lambda));
  return E;
}

// The world momentum Pi of a floating tree in its base's frame at the base pose of `s`, as the
// coefficients of M(q)'s first six rows.
Vector6 momentumInBase(const dynamics::TreeState& s, const cga::Moment& Pi, double lambda) {
  const cga::Moment base = s.M_W0.reverse().apply(Pi, lambda);
  Vector6 pi;
  pi << base.rot, base.trans;
  return pi;
}

// A floating tree at a pose where M(q) = [[B, C], [Cᵀ, D]] over (base, joints), with momentum
// π in its base's frame and joint rates q̇: the base bivelocity that gives it that momentum
// with those rates, Ω_0 = B⁻¹ π − B⁻¹ C q̇, and (with `energies`) its kinetic energy split
// into the part it would have with its joints locked and the joints' motion relative to the
// base, T = ½ πᵀ B⁻¹ π + ½ q̇ᵀ (D − Cᵀ B⁻¹ C) q̇. Keeps B⁻¹ π and B⁻¹ C q̇: at the same pose
// and momentum with the rates scaled by s, Ω_0 = B⁻¹ π − s B⁻¹ C q̇. `Dv`: work array.
struct MomentumSplit {
  Vector6 B_pi, B_Cv, omega_0;
  double T_locked = 0.0, T_internal = 0.0;
};
MomentumSplit splitMomentum(const Eigen::MatrixXd& M, const Vector6& pi, const Eigen::VectorXd& v,
                            Eigen::VectorXd& Dv, bool energies) {
  const int n = static_cast<int>(v.size());
  const Eigen::LLT<Eigen::Matrix<double, 6, 6>> B(M.topLeftCorner<6, 6>());
  const Vector6 Cv = M.topRightCorner(6, n) * v;
  MomentumSplit out;
  out.B_pi = B.solve(pi);
  out.B_Cv = B.solve(Cv);
  out.omega_0 = out.B_pi - out.B_Cv;
  if (energies) {
    Dv.noalias() = M.bottomRightCorner(n, n) * v;
    out.T_locked = 0.5 * pi.dot(out.B_pi);
    out.T_internal = 0.5 * (v.dot(Dv) - Cv.dot(out.B_Cv));
  }
  return out;
}

// After a contact step's drift: the position correction moves the tree by h pν, paid for from
// its kinetic energy when it raises the tree's energy (as for free bodies,
// doc/contacts.md#energy). A floating tree keeps its world momentum through the move: its
// joints move at their rates, its base's bivelocity is solved from the momentum at the moved
// pose, and what the move costs is paid from the energy of the joints' motion relative to the
// base (T = T_locked + s² T_internal with the rates scaled by s), so that a correction — an
// internal contact's above all — never changes the tree's momentum. Leaves the kinematics of
// the corrected state in end_kin.
void correctTree(const Model& model, Data& data, int t) {
  const TreeModel& tm = model.trees[t];
  TreeData& td = data.trees[t];
  const dynamics::ArticulatedBody& tree = tm.body;
  const double h = model.config.dt, lambda = model.lambda;
  const int n = tree.jointCount();
  dynamics::TreeKinematics& kin = data.tree_scratch.end_kin;
  dynamics::TreeState& moved = data.tree_scratch.moved;
  const dynamics::TreeKinematics* drifted = td.integrator->lastExactKinematics();
  if (!drifted) {
    dynamics::treeKinematics(tree, td.state, kin);
    drifted = &kin;
  }
  const double T = dynamics::kineticEnergy(tree, *drifted);
  const double E0 = plusPotential(model, t, *drifted, T);  // treeEnergy's, to the bit
  const cga::Moment Pi = dynamics::worldMomentum(tree, *drifted);
  const auto moveBy = [&](double f, dynamics::TreeState& s) {
    s = td.state;
    if (tree.floating())
      s.M_W0 = s.M_W0 * cga::exp(cga::Bivelocity(td.contact_shift.head<3>(),
                                                 td.contact_shift.segment<3>(3)) *
                                 (-0.5 * f * h));
    s.q += f * h * td.contact_shift.tail(n);
    for (int k = 0; k < n; ++k) {  // within the limits (the solver kept it so, to round-off)
      const dynamics::TreeJoint& j = tree.joints()[k];
      if (j.hasLimits()) s.q[k] = std::clamp(s.q[k], j.lower, j.upper);
    }
    if (tree.hasMimic()) dynamics::applyMimicPositions(tree, s.q);  // followers on leaders
  };
  moveBy(1.0, moved);
  // The tree moved by f h pν: with f = 1 the moved state itself (a copy: the same bits).
  const auto moveTreeBy = [&](double f) {
    if (f == 1.0)
      td.state = moved;  // (copies into storage of the same size: no allocation)
    else
      moveBy(f, td.state);
  };
  if (!tree.floating()) {
    dynamics::treeKinematics(tree, moved, kin);
    const double dU = treeEnergy(model, t, kin) - E0;
    double f = 1.0, scale = 1.0;
    if (dU > 0) {
      f = std::min(1.0, 0.5 * T / dU);
      if (T > 0) scale = std::sqrt(std::max(0.0, 1.0 - f * dU / T));
    }
    moveTreeBy(f);
    td.state.v *= scale;
    if (f == 1.0)  // the moved pose itself, to the bit
      dynamics::treeVelocities(tree, td.state, kin);
    else
      dynamics::treeKinematics(tree, td.state, kin);
  } else {
    // The split and the potential read the moved pose's poses and M(q) alone, not its
    // velocities. M(q) is computed here only because the next step's kick factors it at the
    // tree's end pose (finishTreeContactStep keeps it), which is this pose when f = 1.
    Eigen::MatrixXd& M = data.tree_scratch.split_M;
    Eigen::VectorXd& Dv = data.tree_scratch.split_Dv;
    dynamics::treePoses(tree, moved, kin);
    dynamics::massMatrix(tree, kin, M, data.tree_scratch.algorithms);
    const MomentumSplit full =
        splitMomentum(M, momentumInBase(moved, Pi, lambda), moved.v, Dv, true);
    const double U_moved = plusPotential(model, t, kin, 0.0);
    const double dU = U_moved + full.T_locked + full.T_internal - E0;
    double f = 1.0, s = 1.0;
    if (dU > 0) {
      f = full.T_internal > 0 ? std::min(1.0, 0.5 * full.T_internal / dU) : 0.0;
      if (full.T_internal > 0) s = std::sqrt(std::max(0.0, 1.0 - f * dU / full.T_internal));
    }
    moveTreeBy(f);
    td.state.v *= s;
    Vector6 omega_0;
    if (f == 1.0) {
      // The moved pose to the bit: B, π and C q̇ are the split's, and the rates scaled by s
      // scale C q̇ (s = 1: the split's Ω_0 to the bit).
      omega_0 = full.B_pi - s * full.B_Cv;
    } else {
      dynamics::treePoses(tree, td.state, kin);
      dynamics::massMatrix(tree, kin, M, data.tree_scratch.algorithms);
      omega_0 =
          splitMomentum(M, momentumInBase(td.state, Pi, lambda), td.state.v, Dv, false).omega_0;
    }
    td.state.omega_0 = cga::Bivelocity(omega_0.head<3>(), omega_0.tail<3>());
    dynamics::treeVelocities(tree, td.state, kin);
  }
}

// The correction (correctTree), then the step's energy booked: what the tree had plus the
// inputs' work (trapezoidal) minus what it has now. Returns what was booked, J (negative: the
// step created energy); leaves the kinematics of the tree's end state in end_kin and its kinetic
// energy in T_end.
double correctAndBook(const Model& model, Data& data, int t, double& T_end) {
  TreeData& td = data.trees[t];
  const dynamics::ArticulatedBody& tree = model.trees[t].body;
  const double h = model.config.dt;
  dynamics::TreeKinematics& kin = data.tree_scratch.end_kin;
  // The drift's end state's kinematics when its integrator has them to the bit and no
  // correction moves it.
  const dynamics::TreeKinematics* drifted = td.integrator->lastExactKinematics();
  if (!td.contact_shift.isZero(0.0)) {
    correctTree(model, data, t);  // (leaves the kinematics of the corrected state in kin)
  } else if (drifted) {
    kin = *drifted;  // (copies into storage of the same size: no allocation)
  } else {
    dynamics::treeKinematics(tree, td.state, kin);
  }
  // The inputs' work, trapezoidal from the rates before the kick to those at the end: for a
  // constant effort ½ h τ·(ν + ν'), exactly what it adds to the kinetic energy when nothing else
  // acts, and none while a contact or a stop holds the effort (the kick's own work, ½ h τ·(ν +
  // ν + h M⁻¹τ), would book a phantom input and its dissipation in every step a gripper holds).
  td.contact_book_work =
      0.5 * h * (td.contact_power_start + treeInputPower(model, data, t, kin, td.state.v));
  T_end = dynamics::kineticEnergy(tree, kin);
  const double E_end = plusPotential(model, t, kin, T_end);  // treeEnergy's, to the bit
  const double booked = td.contact_energy_start + td.contact_book_work - E_end;
  td.contact_kicked = false;
  td.integrator->reset();
  return booked;
}

// A contact step's fault of `rule`: its value and bound, named by the tree's deepest contact.
void contactFault(const Model& model, Data& data, int t, TreeFaults::Rule rule, double value,
                  double bound) {
  TreeFaults& f = recordTreeFault(data, t, rule);
  f.value = value;
  f.bound = bound;
  deepestContactOf(model, data, t, f);
}

// The checks of a contact step (doc/articulated.md#faults): the energy may not rise beyond the
// inputs' work, a floating tree's momentum must be the expected one. Records the fault and
// returns true when one is broken. T: the kinetic energy at the end (correctAndBook's).
bool contactStepBroken(const Model& model, Data& data, int t, double booked, double T) {
  const TreeModel& tm = model.trees[t];
  const TreeData& td = data.trees[t];
  const dynamics::TreeKinematics& kin = data.tree_scratch.end_kin;  // correctAndBook's
  const double energy_bound = kEnergySlackFactor * td.contact_energy_slack +
                              kEnergyTolerance * (T + std::abs(td.contact_energy_start)) + 1e-12;
  // What the contacts did to the energy the kick left (the kick's work is what it added, and
  // the transfer is what impulses of other moving bodies handed over at the same velocities);
  // the book holds the trapezoidal work instead, which differs by what the contact took of the
  // kick's rates, ½ h τ·(ν_kicked − ν').
  const double rise = -(booked + td.contact_kick_work - td.contact_book_work) - td.contact_transfer;
  if (rise > energy_bound) {
    contactFault(model, data, t, TreeFaults::Rule::kEnergy, rise, energy_bound);
    return true;
  }
  if (!tm.body.floating()) return false;
  const double lambda = model.lambda;
  const cga::Moment Pi = dynamics::worldMomentum(tm.body, kin);
  const cga::Moment& expected = td.contact_momentum_expected;
  double reach = 0.0;  // the links' distance from the world origin: the moments' lever arms
  for (int b = 0; b < tm.body.bodyCount(); ++b)
    reach = std::max(reach, kin.M_W[b].translation(lambda).norm());
  // The impulses keep it (a tree's contacts with itself cancel); the drift keeps it too, to
  // round-off where the integrator conserves momentum, else to its truncation (not checked).
  const auto distance = [&](const cga::Moment& a, const cga::Moment& b) {
    return std::max((a.force(lambda) - b.force(lambda)).norm(),
                    (a.torque() - b.torque()).norm() / std::max(reach, 1.0));
  };
  const cga::Moment& solved = td.contact_momentum_solved;
  double error = distance(solved, expected);
  if (td.integrator->conservesMomentum()) error = std::max(error, distance(Pi, solved));
  const double momentum_bound = kMomentumTolerance * (td.contact_momentum_scale + 1e-9);
  if (error > momentum_bound) {
    contactFault(model, data, t, TreeFaults::Rule::kMomentum, error, momentum_bound);
    return true;
  }
  return false;
}

}  // namespace

bool finishTreeContactStep(const Model& model, Data& data, int t) {
  TreeData& td = data.trees[t];
  TreeData::ContactEnd& e = td.contact_end;  // (copies into storage of the same size)
  e.valid = false;
  // M(q) at the end pose: a floating tree's correction leaves it in split_M (correctTree);
  // without a correction the end pose is the drift's, where its integrator may have made it
  // (taken before the book resets the integrator).
  const bool corrected = !td.contact_shift.isZero(0.0);
  const Eigen::MatrixXd* drift_M = corrected ? nullptr : td.integrator->lastMass();
  if (drift_M) e.M = *drift_M;
  const bool mass = corrected ? model.trees[t].body.floating() : drift_M != nullptr;
  double T_end = 0.0;
  const double booked = correctAndBook(model, data, t, T_end);
  if (contactStepBroken(model, data, t, booked, T_end)) return false;
  data.dissipated_energy += booked;
  // What the next contact step's kick would make again if it starts from this state.
  e.kin = data.tree_scratch.end_kin;
  e.has_mass = mass;
  if (mass && corrected) e.M = data.tree_scratch.split_M;
  e.state = td.state;
  e.valid = true;
  return true;
}

}  // namespace sim
}  // namespace cga_rigid_sim
