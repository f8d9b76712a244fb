// RNEA over an ArticulatedBody (doc/articulated.md#rnea): velocities and accelerations outward,
// forces inward.
#include "cga_rigid_sim/tree/articulated_body.h"
#include "cga_rigid_sim/tree/tree_workspace.h"
#include "tree/tree_math.h"

namespace cga_rigid_sim {
namespace dynamics {

Eigen::VectorXd inverseDynamics(const ArticulatedBody& tree, const TreeState& state,
                                const TreeKinematics& kin, const Eigen::VectorXd& nu_dot,
                                const BodyMoments& f_ext) {
  const int n = tree.jointCount();
  const double lambda = tree.lambda();
  std::vector<cga::Bivelocity> a(n + 1);
  std::vector<cga::Moment> f(n + 1);
  if (tree.floating()) {
    a[0] = tree_math::bivector(nu_dot.head<6>());
    const Inertia& I = tree.inertiaOf(0);
    // Net moment the base needs: I(Ω̇) − (Ω × I(Ω)) − external.
    f[0] = I.apply(a[0], lambda) - I.gyroscopic(kin.omega[0], lambda) - f_ext[0];
  }
  for (int k = 0; k < n; ++k) {
    const int b = k + 1, p = tree.joints()[k].parent;
    const cga::Bivelocity& s = tree.screwInChild(k);
    const double qd = state.v[k], qdd = nu_dot[tree.velocityIndex(k)];
    // (A3): a_b = M_bp a_p M̃_bp + q̈ s + q̇ (s × Ω_b).
    a[b] = tree_math::toChild(kin, b, a[p]) + s * qdd + cga::commutator(s, kin.omega[b]) * qd;
    const Inertia& I = tree.inertiaOf(b);
    f[b] = I.apply(a[b], lambda) - I.gyroscopic(kin.omega[b], lambda) - f_ext[b];
  }
  Eigen::VectorXd out(tree.velocityCount());
  for (int k = n - 1; k >= 0; --k) {
    const int b = k + 1, p = tree.joints()[k].parent;
    out[tree.velocityIndex(k)] = tree_math::pairing(f[b], tree.screwInChild(k));
    if (p != 0 || tree.floating()) f[p] += tree_math::toParent(kin, b, f[b]);
  }
  if (tree.floating()) out.head<6>() = tree_math::vec(f[0]);
  return out;
}

void forcesAtRest(const ArticulatedBody& tree, const TreeKinematics& kin,
                  const Eigen::VectorXd& tau, const BodyMoments& f_ext, Eigen::VectorXd& Q,
                  TreeWorkspace& work) {
  const int n = tree.jointCount();
  // The RNEA's inward pass alone: at rest no body accelerates and none has a gyroscopic
  // moment, so each body's force is its external moment, summed over its subtree.
  std::vector<cga::Moment>& F = work.subtree_moments;
  F.assign(f_ext.begin(), f_ext.end());
  Q.resize(tree.velocityCount());
  for (int k = n - 1; k >= 0; --k) {
    const int b = k + 1, p = tree.joints()[k].parent;
    Q[tree.velocityIndex(k)] = tau[k] + tree_math::pairing(F[b], tree.screwInChild(k));
    if (p != 0 || tree.floating()) F[p] += tree_math::toParent(kin, b, F[b]);
  }
  if (tree.floating()) Q.head<6>() = tree_math::vec(F[0]);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
