// Mass matrix (CRBA), momentum map, Lagrangian gradient and energy of an ArticulatedBody
// (doc/articulated.md#momentum).
#include "cga_rigid_sim/math/mat3.h"
#include "cga_rigid_sim/tree/articulated_body.h"
#include "tree/tree_math.h"

namespace cga_rigid_sim {
namespace dynamics {

using tree_math::Matrix6d;
using tree_math::Vector6d;

namespace {

// A composite rigid-body inertia about its frame's origin in the coefficients of
// tree_math::inertiaMatrix (lengths over λ, m' = m λ²): the 6×6 map
//   (w, u) ↦ (I_o w + h × u, w × h + m' u),   I_o symmetric, h = m' c (c the centre of mass),
// kept as its ten numbers (tree_math::Composite) instead of 36: carrying it to the parent and
// adding it there cost a tenth of the 6×6 congruence.
using tree_math::Composite;

// Composite of body b in its parent's frame (R_P, t_P: Eigen's column-major R as row-major
// numbers), added to `parent` (tree_math::addCompositeToParent).
void addToParent(const Eigen::Matrix3d& R, const Eigen::Vector3d& tv, const Composite& c,
                 Composite& parent) {
  const double Rr[9] = {R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1),
                        R(1, 2), R(2, 0), R(2, 1), R(2, 2)};
  const double t[3] = {tv.x(), tv.y(), tv.z()};
  tree_math::addCompositeToParent(Rr, t, c, parent);
}

// The moment I_c s of a composite on a screw s = (w, u).
cga::Moment apply(const Composite& c, const cga::Bivelocity& s) {
  const Eigen::Vector3d& w = s.rot;
  const Eigen::Vector3d h(c.h[0], c.h[1], c.h[2]);
  Eigen::Vector3d Iw;
  math::mulSymmetric(c.I, w.data(), Iw.data());
  return {Iw + h.cross(s.trans), w.cross(h) + c.m * s.trans};
}

Matrix6d matrix(const Composite& c) {
  Matrix6d out;
  const double* I = c.I;
  out.topLeftCorner<3, 3>() << I[0], I[3], I[4], I[3], I[1], I[5], I[4], I[5], I[2];
  Eigen::Matrix3d hx;
  hx << 0, -c.h[2], c.h[1], c.h[2], 0, -c.h[0], -c.h[1], c.h[0], 0;
  out.topRightCorner<3, 3>() = hx;
  out.bottomLeftCorner<3, 3>() = hx.transpose();
  out.bottomRightCorner<3, 3>() = c.m * Eigen::Matrix3d::Identity();
  return out;
}

}  // namespace

void massMatrix(const ArticulatedBody& tree, const TreeKinematics& kin, Eigen::MatrixXd& M) {
  TreeWorkspace work;
  massMatrix(tree, kin, M, work);
}

void massMatrix(const ArticulatedBody& tree, const TreeKinematics& kin, Eigen::MatrixXd& M,
                TreeWorkspace& work) {
  const int n = tree.jointCount(), off = tree.floating() ? 6 : 0;
  const double lambda = tree.lambda();
  M.setZero(tree.velocityCount(), tree.velocityCount());
  // Composite inertias inward, each in its own body's frame.
  std::vector<Composite>& Ic = work.composites;
  Ic.resize(n + 1);
  for (int b = 0; b <= n; ++b) {
    Composite& c = Ic[b];
    c = Composite{{0, 0, 0, 0, 0, 0}, {0, 0, 0}, 0.0};
    if (b == 0 && !tree.floating()) continue;
    const Inertia& I = tree.inertiaOf(b);
    for (int i = 0; i < 3; ++i) c.I[i] = I.principalMoments()[i];
    c.m = I.mass() * lambda * lambda;
  }
  for (int b = n; b >= 1; --b) {
    const int p = tree.parentOf(b);
    if (p != 0 || tree.floating()) addToParent(kin.R_P[b], kin.t_P[b], Ic[b], Ic[p]);
  }
  for (int k = 0; k < n; ++k) {
    int b = k + 1;
    const cga::Bivelocity& s = tree.screwInChild(k);
    cga::Moment F = apply(Ic[b], s);
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
  if (tree.floating()) M.topLeftCorner<6, 6>() = matrix(Ic[0]);
}

Eigen::VectorXd momentumAndGradient(const ArticulatedBody& tree, const TreeKinematics& kin,
                                    const BodyMoments& f_ext, Eigen::VectorXd* gradient) {
  Eigen::VectorXd p;
  momentumAndGradient(tree, kin, f_ext, p, gradient);
  return p;
}

void momentumAndGradient(const ArticulatedBody& tree, const TreeKinematics& kin,
                         const BodyMoments& f_ext, Eigen::VectorXd& p, Eigen::VectorXd* gradient) {
  TreeWorkspace work;
  momentumAndGradient(tree, kin, f_ext, p, gradient, work);
}

void momentumAndGradient(const ArticulatedBody& tree, const TreeKinematics& kin,
                         const BodyMoments& f_ext, Eigen::VectorXd& p, Eigen::VectorXd* gradient,
                         TreeWorkspace& work) {
  const int n = tree.jointCount();
  const double lambda = tree.lambda();
  std::vector<cga::Moment>& H = work.subtree_momentum;
  std::vector<cga::Moment>& F = work.subtree_moments;
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
