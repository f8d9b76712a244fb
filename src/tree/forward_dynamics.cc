// ABA over an ArticulatedBody (doc/articulated.md#aba; Featherstone, Rigid Body Dynamics
// Algorithms, §7.3): three passes, O(n).
#include <Eigen/Cholesky>

#include "cga_rigid_sim/tree/articulated_body.h"
#include "tree/tree_math.h"

namespace cga_rigid_sim {
namespace dynamics {

using tree_math::Matrix6d;
using tree_math::Vector6d;

Eigen::VectorXd forwardDynamics(const ArticulatedBody& tree, const TreeState& state,
                                const TreeKinematics& kin, const Eigen::VectorXd& tau,
                                const BodyMoments& f_ext) {
  Eigen::VectorXd nu_dot;
  TreeWorkspace work;
  forwardDynamics(tree, state, kin, tau, f_ext, nu_dot, work);
  return nu_dot;
}

void forwardDynamics(const ArticulatedBody& tree, const TreeState& state, const TreeKinematics& kin,
                     const Eigen::VectorXd& tau, const BodyMoments& f_ext,
                     Eigen::VectorXd& nu_dot) {
  TreeWorkspace work;
  forwardDynamics(tree, state, kin, tau, f_ext, nu_dot, work);
}

namespace {
// With mimic joints the motion stays in ν = G ν_r (articulated_body.h): ν̇ = G M_r⁻¹ Gᵀ (τ − b)
// with M_r = Gᵀ M G (CRBA) and b the RNEA's forces at ν̇ = 0 (velocity terms, gravity, loads):
// d'Alembert's principle on the constrained motions. O(n²) for M and O(n_r³) for its factor,
// where ABA is O(n) — ABA's recursion has no room for a constraint between two branches.
void mimicForwardDynamics(const ArticulatedBody& tree, const TreeState& state,
                          const TreeKinematics& kin, const Eigen::VectorXd& tau,
                          const BodyMoments& f_ext, Eigen::VectorXd& nu_dot, TreeWorkspace& work) {
  TreeWorkspace::Mimic& S = work.mimic;
  S.zero.setZero(tree.velocityCount());
  S.Q = -inverseDynamics(tree, state, kin, S.zero, f_ext);
  S.Q.tail(tree.jointCount()) += tau;
  massMatrix(tree, kin, S.M, work);
  reduceForce(tree, S.Q, S.Q_r);
  reduceMatrix(tree, S.M, S.M_r, work);
  S.llt.compute(S.M_r);
  S.llt.solveInPlace(S.Q_r);
  expandVelocity(tree, S.Q_r, nu_dot);
}
}  // namespace

void forwardDynamics(const ArticulatedBody& tree, const TreeState& state, const TreeKinematics& kin,
                     const Eigen::VectorXd& tau, const BodyMoments& f_ext, Eigen::VectorXd& nu_dot,
                     TreeWorkspace& work) {
  if (tree.hasMimic()) return mimicForwardDynamics(tree, state, kin, tau, f_ext, nu_dot, work);
  const int n = tree.jointCount();
  const double lambda = tree.lambda();
  TreeWorkspace::Aba& scratch = work.aba;
  auto& IA = scratch.IA;
  auto& pA = scratch.pA;
  auto& c = scratch.c;
  auto& U = scratch.U;
  auto& a = scratch.a;
  auto& D = scratch.D;
  auto& u = scratch.u;
  IA.resize(n + 1);
  pA.resize(n + 1);
  c.resize(n + 1);
  U.resize(n + 1);
  a.resize(n + 1);
  D.resize(n + 1);
  u.resize(n + 1);
  // Pass 1: rigid-body inertias, bias moments −(Ω × I(Ω)) − f_ext, velocity-product terms
  // q̇ (s × Ω_b) of (A3). Body 0 of a fixed base is the world: it takes what reaches it.
  const int first = tree.floating() ? 0 : 1;
  if (first == 1) {
    IA[0].setZero();
    pA[0].setZero();
  }
  for (int b = first; b <= n; ++b) {
    const Inertia& I = tree.inertiaOf(b);
    IA[b] = tree_math::inertiaMatrix(I, lambda);
    pA[b] = tree_math::vec(cga::Moment() - I.gyroscopic(kin.omega[b], lambda) - f_ext[b]);
  }
  for (int k = 0; k < n; ++k) {
    const int b = k + 1;
    c[b] = tree_math::vec(cga::commutator(tree.screwInChild(k), kin.omega[b]) * state.v[k]);
  }
  // Pass 2: articulated inertias inward.
  for (int k = n - 1; k >= 0; --k) {
    const int b = k + 1, p = tree.joints()[k].parent;
    const cga::Bivelocity& s = tree.screwInChild(k);
    U[b] = IA[b].leftCols<3>() * s.rot + IA[b].rightCols<3>() * s.trans;
    D[b] = tree_math::pairing(U[b], s);
    u[b] = tau[k] - tree_math::pairing(pA[b], s);
    if (p == 0 && !tree.floating()) continue;  // the world takes what reaches it
    const Matrix6d Ia = IA[b] - U[b] * (U[b].transpose() / D[b]);
    const Vector6d pa = pA[b] + Ia * c[b] + U[b] * (u[b] / D[b]);
    tree_math::addToParent(kin, b, Ia, IA[p]);
    pA[p] += tree_math::vec(tree_math::toParent(kin, b, tree_math::moment(pa)));
  }
  // Pass 3: accelerations outward.
  nu_dot.resize(tree.velocityCount());
  a[0] = cga::Bivelocity();
  if (tree.floating()) {
    const Vector6d a0 = -IA[0].ldlt().solve(pA[0]);
    a[0] = tree_math::bivector(a0);
    nu_dot.head<6>() = a0;
  }
  for (int k = 0; k < n; ++k) {
    const int b = k + 1, p = tree.joints()[k].parent;
    const cga::Bivelocity& s = tree.screwInChild(k);
    const cga::Bivelocity ap = tree_math::toChild(kin, b, a[p]) + tree_math::bivector(c[b]);
    const double qdd = (u[b] - tree_math::pairing(U[b], ap)) / D[b];
    a[b] = ap + s * qdd;
    nu_dot[tree.velocityIndex(k)] = qdd;
  }
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
