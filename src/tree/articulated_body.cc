// ArticulatedBody: the tree's constants and its forward kinematics (doc/articulated.md).
#include "cga_rigid_sim/tree/articulated_body.h"

#include <algorithm>
#include <cmath>

#include "tree/tree_math.h"

namespace cga_rigid_sim {
namespace dynamics {

ArticulatedBody::ArticulatedBody(std::optional<Inertia> base_inertia, std::vector<TreeJoint> joints,
                                 double lambda)
    : base_(std::move(base_inertia)), joints_(std::move(joints)), lambda_(lambda) {
  for (const TreeJoint& j : joints_) {
    const Eigen::Vector3d a = j.axis.normalized();
    const cga::Bivelocity S = j.kind == JointKind::kRevolute
                                  ? cga::Bivelocity(a, Eigen::Vector3d::Zero())
                                  : cga::Bivelocity(Eigen::Vector3d::Zero(), a / lambda_);
    S_J_.push_back(S);
    s_C_.push_back(j.M_JC.reverse().apply(S));
    M_PC_.push_back(j.M_PJ * j.M_JC);
  }
  // The independent coordinates (doc/articulated.md#mimic-joints): one per joint that follows
  // none, carrying what its followers impose (their limits mapped to it, friction and damping
  // weighted by the multiplier: the same power).
  const int n = jointCount();
  coordinate_of_.assign(n, -1);
  for (int k = 0; k < n; ++k) {
    const TreeJoint& j = joints_[k];
    if (j.mimic >= 0) continue;
    coordinate_of_[k] = static_cast<int>(coordinates_.size());
    coordinates_.push_back({k, j.lower, j.upper, j.friction, j.damping});
  }
  for (int k = 0; k < n; ++k) {
    const TreeJoint& j = joints_[k];
    if (j.mimic < 0) continue;
    has_mimic_ = true;
    const int c = coordinate_of_[k] = coordinate_of_[j.mimic];
    JointCoordinate& x = coordinates_[c];
    const double m = j.mimic_multiplier, o = j.mimic_offset;
    x.friction += std::abs(m) * j.friction;
    x.damping += m * m * j.damping;
    const auto [lo, hi] = leaderLimits(j.lower, j.upper, m, o);
    x.lower = std::max(x.lower, lo);
    x.upper = std::min(x.upper, hi);
  }
}

void TreeKinematics::resize(int bodies) {
  M_W.resize(bodies);
  M_P.resize(bodies);
  omega.resize(bodies);
  R_P.resize(bodies);
  t_P.resize(bodies);
}

namespace {

// M_pb(q) = M_PJ exp(−½ q S) M_JC = M_PC exp(−½ q s), s = M̃_JC S M_JC the screw in the child's
// frame (conjugating the exponent by M_JC). The exponential in closed form (cga::exp): a
// revolute s = (u, m), |u| = 1, is a line (u·m = 0), so exp(−½ q s) = (cos ½q + sin ½q u,
// −sin ½q m) as (rotor, dual) quaternions; a prismatic s = (0, m) gives (1, −½ q m).
cga::Motor jointMotor(JointKind kind, const cga::Motor& M_PC, const cga::Bivelocity& s, double q) {
  if (kind == JointKind::kRevolute) {
    const double half = 0.5 * q, c = std::cos(half), sh = std::sin(half);
    return M_PC *
           cga::Motor::fromQuaternions(
               Eigen::Quaterniond(c, sh * s.rot.x(), sh * s.rot.y(), sh * s.rot.z()),
               Eigen::Quaterniond(0.0, -sh * s.trans.x(), -sh * s.trans.y(), -sh * s.trans.z()));
  }
  const Eigen::Vector3d b = (-0.5 * q) * s.trans;
  return M_PC * cga::Motor::fromQuaternions(Eigen::Quaterniond(1, 0, 0, 0),
                                            Eigen::Quaterniond(0.0, b.x(), b.y(), b.z()));
}

}  // namespace

void treeKinematics(const ArticulatedBody& tree, const TreeState& state, TreeKinematics& kin) {
  treePoses(tree, state, kin);
  treeVelocities(tree, state, kin);
}

void treePoses(const ArticulatedBody& tree, const TreeState& state, TreeKinematics& kin) {
  const int n = tree.jointCount();
  const double lambda = tree.lambda();
  kin.resize(n + 1);
  kin.M_W[0] = tree.floating() ? state.M_W0 : cga::Motor();
  for (int k = 0; k < n; ++k) {
    const TreeJoint& j = tree.joints()[k];
    const int b = k + 1, p = j.parent;
    // The child's frame in the parent's: M_pb = M_PJ exp(−½ q S) M_JC (A0).
    const cga::Motor& M = kin.M_P[b] =
        jointMotor(j.kind, tree.childAtZero(k), tree.screwInChild(k), state.q[k]);
    kin.M_W[b] = kin.M_W[p] * M;
    kin.R_P[b] = M.rotation().toRotationMatrix();
    kin.t_P[b] = M.translation(lambda) / lambda;
  }
}

void treeVelocities(const ArticulatedBody& tree, const TreeState& state, TreeKinematics& kin) {
  kin.omega[0] = tree.floating() ? state.omega_0 : cga::Bivelocity();
  for (int k = 0; k < tree.jointCount(); ++k) {
    const int b = k + 1;
    // Ω_b = M_bp Ω_p M̃_bp + q̇ s (doc/articulated.md (A2)).
    kin.omega[b] = tree_math::toChild(kin, b, kin.omega[tree.joints()[k].parent]) +
                   tree.screwInChild(k) * state.v[k];
  }
}

Eigen::VectorXd velocityVector(const ArticulatedBody& tree, const TreeState& state) {
  Eigen::VectorXd nu(tree.velocityCount());
  if (tree.floating()) nu.head<6>() = tree_math::vec(state.omega_0);
  nu.tail(tree.jointCount()) = state.v;
  return nu;
}

void setVelocityVector(const ArticulatedBody& tree, const Eigen::VectorXd& nu, TreeState& state) {
  if (tree.floating()) state.omega_0 = tree_math::bivector(nu.head<6>());
  state.v = nu.tail(tree.jointCount());
}

void gravityMoments(const ArticulatedBody& tree, const TreeKinematics& kin,
                    const Eigen::Vector3d& g_W, BodyMoments& out) {
  const double lambda = tree.lambda();
  out.assign(tree.bodyCount(), cga::Moment());
  for (int b = tree.floating() ? 0 : 1; b < tree.bodyCount(); ++b)
    out[b].trans = (lambda * tree.inertiaOf(b).mass()) * (kin.M_W[b].rotation().conjugate() * g_W);
}

Eigen::Matrix<double, 6, 6> adjointMatrix(const cga::Motor& M, double lambda) {
  // M maps x ↦ R x + a; a bivector (w, u) goes to (R w, R u + (a/λ) × R w)
  // (doc/articulated.md (A1); test/tree checks it against Motor::apply).
  const Eigen::Matrix3d R = M.rotation().toRotationMatrix();
  const Eigen::Vector3d a = M.translation(lambda) / lambda;
  Eigen::Matrix3d ax;
  ax << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  Eigen::Matrix<double, 6, 6> X;
  X << R, Eigen::Matrix3d::Zero(), ax * R, R;
  return X;
}

// Plain loops: Eigen's == costs a call per comparison here.
bool identical(const TreeState& a, const TreeState& b) {
  const auto same = [](const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
    if (x.size() != y.size()) return false;
    for (Eigen::Index i = 0; i < x.size(); ++i)
      if (x[i] != y[i]) return false;
    return true;
  };
  const auto same3 = [](const Eigen::Vector3d& x, const Eigen::Vector3d& y) {
    return x[0] == y[0] && x[1] == y[1] && x[2] == y[2];
  };
  return a.M_W0.coefficients() == b.M_W0.coefficients() && same(a.q, b.q) && same(a.v, b.v) &&
         same3(a.omega_0.rot, b.omega_0.rot) && same3(a.omega_0.trans, b.omega_0.trans);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
