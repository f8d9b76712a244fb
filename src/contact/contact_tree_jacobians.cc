// A contact's side on a link of an articulated tree (doc/contacts.md#trees): the link has no
// velocity of its own, so the side reads and changes its tree's generalized velocity ν through
// the contact point's Jacobian J (u = J ν) and the response W = M(q)⁻¹ Jᵀ (Δν = W P); its part
// of the contact's Delassus block is J W = Yᵀ Y, Y = L⁻ᵀ Jᵀ the first half of W, on which the
// sweeps work (W itself is not made).
#include <vector>

#include "contact/contact_solver_internals.h"

namespace cga_rigid_sim {
namespace sim {
namespace detail {
namespace {

// The Jacobian of world point p on body b of tree T: column j is the point's velocity under a
// unit rate of coordinate j, v_o + ω × p, for the coordinates that move b (the joints on its
// path to the base, and the base's six).
void pointJacobian(const SolverTree& T, int b, const Eigen::Vector3d& p,
                   Eigen::Matrix<double, 3, Eigen::Dynamic>& J) {
  J.setZero(3, T.M.cols());
  const int base = T.floating ? 6 : 0;
  // A joint's column goes to its coordinate's, times its multiplier (mimic joints; else itself).
  for (int x = b; x > 0; x = T.parent[x]) {
    const int j = base + x - 1;
    J.col(T.column[x - 1]) +=
        T.multiplier[x - 1] * (T.twist.col(j).tail<3>() + T.twist.col(j).head<3>().cross(p));
  }
  for (int j = 0; j < base; ++j)
    J.col(j) = T.twist.col(j).tail<3>() + T.twist.col(j).head<3>().cross(p);
}

// The coordinate whose path to the base holds the joints that move tree body b (−1: none).
int leafOf(const SolverTree& T, int b) {
  if (b == 0) return T.floating ? 5 : -1;
  return T.column[b - 1];
}

// Y = the first half of M⁻¹ jᵀ for the side's Jacobian j on tree T, whose nonzeros are on the
// paths from the leaves to the base; returns j M⁻¹ jᵀ = Yᵀ Y. On the tree's sparsity Y is zero
// off those paths, so the product sums their rows alone, walked as halfSolve walks them (a
// general matrix product of 3 × n by n × 3 would cost several times the rows' sums).
Eigen::Matrix3d halfResponse(const SolverTree& T, const Eigen::Matrix<double, 3, Eigen::Dynamic>& j,
                             int leaf, int leaf2, TreeFactor::Columns& Y) {
  Y = j.transpose();
  T.factor.halfSolve(Y, leaf, leaf2);
  if (!T.factor.sparse()) return Y.transpose() * Y;
  Eigen::Matrix3d K = Eigen::Matrix3d::Zero();
  const std::vector<int>& parent = T.coordinate_parent;
  for (int a = leaf, b = leaf2; a >= 0 || b >= 0;) {
    const int i = a > b ? a : b;
    const Eigen::Vector3d y = Y.row(i).transpose();
    K.noalias() += y * y.transpose();
    if (a == i) a = parent[a];
    if (b == i) b = parent[b];
  }
  return K;
}

}  // namespace

void takeTreeSides(const std::vector<SolverBody>& bodies, const std::vector<SolverTree>& trees,
                   const Eigen::Vector3d& point_W, ContactRow& c) {
  c.ta = c.a >= 0 ? bodies[c.a].tree : -1;
  c.tb = c.b >= 0 ? bodies[c.b].tree : -1;
  c.leaf_a = c.leaf_a2 = c.leaf_b = -1;
  if (c.ta >= 0) {
    pointJacobian(trees[c.ta], bodies[c.a].tree_body, point_W, c.ja);
    c.leaf_a = leafOf(trees[c.ta], bodies[c.a].tree_body);
    c.a = -1;
  }
  if (c.tb >= 0) {
    pointJacobian(trees[c.tb], bodies[c.b].tree_body, point_W, c.jb);
    c.leaf_b = leafOf(trees[c.tb], bodies[c.b].tree_body);
    c.b = -1;
    if (c.tb == c.ta) {
      c.ja -= c.jb;
      c.leaf_a2 = c.leaf_b;
      c.leaf_b = -1;
      c.tb = -1;
    }
  }
}

void addTreeSides(const std::vector<SolverTree>& trees, ContactRow& c, Eigen::Matrix3d& Kc) {
  Eigen::Matrix3d K = Eigen::Matrix3d::Zero();
  c.ka.setZero();
  c.kb.setZero();
  if (c.ta >= 0) {
    c.ka = halfResponse(trees[c.ta], c.ja, c.leaf_a, c.leaf_a2, c.wa);
    K += c.ka;
  }
  if (c.tb >= 0) {
    c.kb = halfResponse(trees[c.tb], c.jb, c.leaf_b, -1, c.wb);
    K += c.kb;
  }
  Eigen::Matrix3d B;
  B << c.n, c.t1, c.t2;
  Kc += B.transpose() * K * B;  // its upper triangle is kept
  c.k_n += K * c.n;
}

}  // namespace detail
}  // namespace sim
}  // namespace cga_rigid_sim
