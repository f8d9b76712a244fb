// ABA over an ArticulatedBody (doc/articulated.md#aba; Featherstone, Rigid Body Dynamics
// Algorithms, §7.3): three passes, O(n).
#include <Eigen/Cholesky>

#include "cga_rigid_sim/dynamics/articulated_body.h"
#include "tree_math.h"

namespace cga_rigid_sim {
namespace dynamics {

using tree_math::Matrix6d;
using tree_math::Vector6d;

Eigen::VectorXd forwardDynamics(const ArticulatedBody& tree, const TreeState& state,
                                const TreeKinematics& kin, const Eigen::VectorXd& tau,
                                const BodyMoments& f_ext) {
  Eigen::VectorXd nu_dot;
  forwardDynamics(tree, state, kin, tau, f_ext, nu_dot);
  return nu_dot;
}

void forwardDynamics(const ArticulatedBody& tree, const TreeState& state, const TreeKinematics& kin,
                     const Eigen::VectorXd& tau, const BodyMoments& f_ext,
                     Eigen::VectorXd& nu_dot) {
  const int n = tree.jointCount();
  const double lambda = tree.lambda();
  // Scratch (no allocation once grown). X[b]: motion from b's parent's frame to b's.
  static thread_local std::vector<Matrix6d, Eigen::aligned_allocator<Matrix6d>> IA, X;
  static thread_local std::vector<Vector6d, Eigen::aligned_allocator<Vector6d>> pA, c, U, a;
  static thread_local std::vector<double> D, u;
  IA.assign(n + 1, Matrix6d::Zero());
  pA.assign(n + 1, Vector6d::Zero());
  a.assign(n + 1, Vector6d::Zero());
  X.resize(n + 1);
  c.resize(n + 1);
  U.resize(n + 1);
  D.resize(n + 1);
  u.resize(n + 1);
  // Pass 1: rigid-body inertias, bias moments −(Ω × I(Ω)) − f_ext, velocity-product terms.
  for (int b = tree.floating() ? 0 : 1; b <= n; ++b) {
    const Inertia& I = tree.inertiaOf(b);
    IA[b] = tree_math::inertiaMatrix(I, lambda);
    pA[b] = tree_math::vec(cga::Moment() - I.gyroscopic(kin.omega[b], lambda) - f_ext[b]);
  }
  for (int k = 0; k < n; ++k) {
    const int b = k + 1;
    c[b] = tree_math::vec(cga::commutator(tree.screwInChild(k), kin.omega[b]) * state.v[k]);
    X[b] = adjointMatrix(kin.M_P[b].reverse(), lambda);
  }
  // Pass 2: articulated inertias inward.
  for (int k = n - 1; k >= 0; --k) {
    const int b = k + 1, p = tree.joints()[k].parent;
    const Vector6d s = tree_math::vec(tree.screwInChild(k));
    U[b] = IA[b] * s;
    D[b] = s.dot(U[b]);
    u[b] = tau[k] - s.dot(pA[b]);
    if (p == 0 && !tree.floating()) continue;  // the world takes what reaches it
    const Matrix6d Ia = IA[b] - U[b] * U[b].transpose() / D[b];
    const Vector6d pa = pA[b] + Ia * c[b] + U[b] * (u[b] / D[b]);
    IA[p] += X[b].transpose() * Ia * X[b];
    pA[p] += X[b].transpose() * pa;
  }
  // Pass 3: accelerations outward.
  nu_dot.resize(tree.velocityCount());
  if (tree.floating()) {
    a[0] = -IA[0].ldlt().solve(pA[0]);
    nu_dot.head<6>() = a[0];
  }
  for (int k = 0; k < n; ++k) {
    const int b = k + 1, p = tree.joints()[k].parent;
    const Vector6d s = tree_math::vec(tree.screwInChild(k));
    const Vector6d ap = X[b] * a[p] + c[b];
    const double qdd = (u[b] - U[b].dot(ap)) / D[b];
    a[b] = ap + s * qdd;
    nu_dot[tree.velocityIndex(k)] = qdd;
  }
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
