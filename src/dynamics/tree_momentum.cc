// Mass matrix (CRBA), momentum map, Lagrangian gradient and energy of an ArticulatedBody
// (doc/articulated.md#momentum).
#include "cga_rigid_sim/dynamics/articulated_body.h"
#include "tree_math.h"

namespace cga_rigid_sim {
namespace dynamics {

using tree_math::Matrix6d;
using tree_math::Vector6d;

void massMatrix(const ArticulatedBody& tree, const TreeKinematics& kin, Eigen::MatrixXd& M) {
  const int n = tree.jointCount(), off = tree.floating() ? 6 : 0;
  const double lambda = tree.lambda();
  M.setZero(tree.velocityCount(), tree.velocityCount());
  // Composite inertias inward, each in its own body's frame.
  std::vector<Matrix6d, Eigen::aligned_allocator<Matrix6d>> Ic(n + 1, Matrix6d::Zero()), X(n + 1);
  for (int b = tree.floating() ? 0 : 1; b <= n; ++b)
    Ic[b] = tree_math::inertiaMatrix(tree.inertiaOf(b), lambda);
  for (int b = 1; b <= n; ++b) X[b] = adjointMatrix(kin.M_P[b].reverse(), lambda);
  for (int b = n; b >= 1; --b) {
    const int p = tree.parentOf(b);
    if (p != 0 || tree.floating()) Ic[p] += X[b].transpose() * Ic[b] * X[b];
  }
  for (int k = 0; k < n; ++k) {
    int b = k + 1;
    Vector6d F = Ic[b] * tree_math::vec(tree.screwInChild(k));
    M(off + k, off + k) = tree_math::vec(tree.screwInChild(k)).dot(F);
    while (tree.parentOf(b) != 0) {
      F = X[b].transpose() * F;  // to the parent's frame
      b = tree.parentOf(b);
      const double m = tree_math::vec(tree.screwInChild(b - 1)).dot(F);
      M(off + k, off + b - 1) = m;
      M(off + b - 1, off + k) = m;
    }
    if (tree.floating()) {
      F = X[b].transpose() * F;
      M.block<6, 1>(0, off + k) = F;
      M.block<1, 6>(off + k, 0) = F.transpose();
    }
  }
  if (tree.floating()) M.topLeftCorner<6, 6>() = Ic[0];
}

Eigen::VectorXd momentumAndGradient(const ArticulatedBody& tree, const TreeKinematics& kin,
                                    const BodyMoments& f_ext, Eigen::VectorXd* gradient) {
  const int n = tree.jointCount();
  const double lambda = tree.lambda();
  std::vector<cga::Moment> H(n + 1), F(n + 1);
  for (int b = tree.floating() ? 0 : 1; b <= n; ++b) {
    H[b] = tree.inertiaOf(b).apply(kin.omega[b], lambda);
    F[b] = f_ext[b];
  }
  Eigen::VectorXd p(tree.velocityCount());
  if (gradient) gradient->resize(n);
  for (int k = n - 1; k >= 0; --k) {
    const int b = k + 1, q = tree.joints()[k].parent;
    const cga::Bivelocity& s = tree.screwInChild(k);
    p[tree.velocityIndex(k)] = tree_math::pairing(H[b], s);
    // (A7): ∂L/∂q_k + Q_k = ⟨H_k, s × Ω_b⟩ + ⟨F_k, s⟩.
    if (gradient)
      (*gradient)[k] =
          tree_math::pairing(H[b], cga::commutator(s, kin.omega[b])) + tree_math::pairing(F[b], s);
    if (q != 0 || tree.floating()) {
      H[q] += kin.M_P[b].apply(H[b], lambda);
      F[q] += kin.M_P[b].apply(F[b], lambda);
    }
  }
  if (tree.floating()) p.head<6>() = tree_math::vec(H[0]);
  return p;
}

cga::Moment worldMomentum(const ArticulatedBody& tree, const TreeKinematics& kin) {
  cga::Moment total;
  for (int b = tree.floating() ? 0 : 1; b < tree.bodyCount(); ++b)
    total += kin.M_W[b].apply(tree.inertiaOf(b).apply(kin.omega[b], tree.lambda()), tree.lambda());
  return total;
}

double kineticEnergy(const ArticulatedBody& tree, const TreeKinematics& kin) {
  double T = 0.0;
  for (int b = tree.floating() ? 0 : 1; b < tree.bodyCount(); ++b)
    T += tree.inertiaOf(b).kineticEnergy(kin.omega[b], tree.lambda());
  return T;
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
