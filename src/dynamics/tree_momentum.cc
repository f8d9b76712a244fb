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
  // Composite inertias inward, each in its own body's frame (scratch: no allocation once grown).
  static thread_local std::vector<Matrix6d, Eigen::aligned_allocator<Matrix6d>> Ic_scratch;
  auto& Ic = Ic_scratch;
  Ic.resize(n + 1);
  if (!tree.floating()) Ic[0].setZero();
  for (int b = tree.floating() ? 0 : 1; b <= n; ++b)
    Ic[b] = tree_math::inertiaMatrix(tree.inertiaOf(b), lambda);
  for (int b = n; b >= 1; --b) {
    const int p = tree.parentOf(b);
    if (p != 0 || tree.floating()) tree_math::addToParent(kin, b, Ic[b], Ic[p]);
  }
  for (int k = 0; k < n; ++k) {
    int b = k + 1;
    const cga::Bivelocity& s = tree.screwInChild(k);
    cga::Moment F = tree_math::moment(Ic[b].leftCols<3>() * s.rot + Ic[b].rightCols<3>() * s.trans);
    M(off + k, off + k) = tree_math::pairing(F, s);
    while (tree.parentOf(b) != 0) {
      F = tree_math::toParent(kin, b, F);  // to the parent's frame
      b = tree.parentOf(b);
      const double m = tree_math::pairing(F, tree.screwInChild(b - 1));
      M(off + k, off + b - 1) = m;
      M(off + b - 1, off + k) = m;
    }
    if (tree.floating()) {
      F = tree_math::toParent(kin, b, F);
      M.block<6, 1>(0, off + k) = tree_math::vec(F);
      M.block<1, 6>(off + k, 0) = tree_math::vec(F).transpose();
    }
  }
  if (tree.floating()) M.topLeftCorner<6, 6>() = Ic[0];
}

Eigen::VectorXd momentumAndGradient(const ArticulatedBody& tree, const TreeKinematics& kin,
                                    const BodyMoments& f_ext, Eigen::VectorXd* gradient) {
  Eigen::VectorXd p;
  momentumAndGradient(tree, kin, f_ext, p, gradient);
  return p;
}

void momentumAndGradient(const ArticulatedBody& tree, const TreeKinematics& kin,
                         const BodyMoments& f_ext, Eigen::VectorXd& p, Eigen::VectorXd* gradient) {
  const int n = tree.jointCount();
  const double lambda = tree.lambda();
  static thread_local std::vector<cga::Moment> H, F;  // scratch: no allocation once grown
  H.assign(n + 1, cga::Moment());
  F.assign(n + 1, cga::Moment());
  for (int b = tree.floating() ? 0 : 1; b <= n; ++b) {
    H[b] = tree.inertiaOf(b).apply(kin.omega[b], lambda);
    F[b] = f_ext[b];
  }
  p.resize(tree.velocityCount());
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
      H[q] += tree_math::toParent(kin, b, H[b]);
      F[q] += tree_math::toParent(kin, b, F[b]);
    }
  }
  if (tree.floating()) p.head<6>() = tree_math::vec(H[0]);
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
