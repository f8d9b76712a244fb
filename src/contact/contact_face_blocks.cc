// The face blocks (doc/contacts.md#solver): consecutive rows between the same two bodies with
// one normal — a face's corners, at most four — take their normal impulses as one block
// (SolverWork::Group), which Gauss–Seidel corner by corner would trade between them for ever.
// Here: the blocks and each block's pseudo-inverse of its normal Delassus matrix.
#include <cmath>

#include "contact/contact_solver_internals.h"

namespace cga_rigid_sim {
namespace sim {
namespace detail {
namespace {

// The pseudo-inverse of a block's normal Delassus matrix K (size × size, a unit diagonal
// beyond). Four corners in one plane: K = Σ Jᵀ M⁻¹ J over both bodies, whose rows span the
// ones and the in-plane components of r_i × n, so z ⟂ those three (their generalised cross
// product) is K's null vector, and K⁺ = (K + s ẑẑᵀ)⁻¹ − ẑẑᵀ/s for any s > 0 (closed form, no
// eigen-decomposition). Fewer corners are regular. Anything else (a degenerate patch): the
// eigen-decomposition, eigenvalues below 1e-9 of the largest taken as zero.
Eigen::Matrix4d pseudoInverse(const Eigen::Matrix4d& K, int size, const Eigen::Vector3d& n,
                              const Eigen::Vector3d* rn) {
  const double s = K.trace() / 4;
  Eigen::Matrix4d out;
  bool invertible = false;
  if (size == 4) {
    // K = A B Aᵀ with A's columns the ones and the components of r_i × n, which lie in the
    // plane ⟂ n: two of them (p, q, leaving out n's largest) determine them. z ⟂ A's columns:
    // z_i = (−1)^i det of A's rows without i.
    int k = 0;
    n.cwiseAbs().maxCoeff(&k);
    const int p = (k + 1) % 3, q = (k + 2) % 3;
    Eigen::Vector4d z;
    for (int i = 0; i < 4; ++i) {
      Eigen::Matrix3d M;
      for (int j = 0, row = 0; j < 4; ++j)
        if (j != i) M.row(row++) << 1.0, rn[j](p), rn[j](q);
      z(i) = (i % 2 ? -1.0 : 1.0) * M.determinant();
    }
    const double scale =
        rn[0].squaredNorm() + rn[1].squaredNorm() + rn[2].squaredNorm() + rn[3].squaredNorm();
    if (z.norm() > 1e-9 * scale) {  // a patch, not a line
      z.normalize();
      const Eigen::Matrix4d zz = z * z.transpose();
      Eigen::Matrix4d inv;
      (K + s * zz).computeInverseWithCheck(inv, invertible, 1e-300);
      out = inv - zz / s;
    }
  } else {
    Eigen::Matrix4d inv;
    K.computeInverseWithCheck(inv, invertible, 1e-300);
    out = inv;
    for (int i = size; i < 4; ++i) out.row(i).setZero(), out.col(i).setZero();
    invertible = invertible && (K * out).topLeftCorner(size, size).isIdentity(1e-9);
  }
  if (invertible) return out;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(K);
  const double cutoff = 1e-9 * eig.eigenvalues().cwiseAbs().maxCoeff();
  out.setZero();
  for (int q = 0; q < 4; ++q)
    if (eig.eigenvalues()(q) > cutoff)
      out +=
          eig.eigenvectors().col(q) * eig.eigenvectors().col(q).transpose() / eig.eigenvalues()(q);
  for (int i = size; i < 4; ++i) out.row(i).setZero(), out.col(i).setZero();
  return out;
}

}  // namespace

// The runs of rows solved as blocks (SolverWork::Group), and each block's pseudo-inverse:
// K_ij = Σ over the movable sides of 1/m + (r_i × n)ᵀ I⁻¹ (r_j × n).
void makeGroups(std::vector<ContactRow>& rows, SolverWork& work) {
  work.groups.clear();
  for (std::size_t k = 0; k < rows.size();) {
    std::size_t e = k + 1;
    const ContactRow& c = rows[k];
    if (!onTree(c) && std::isfinite(c.k_nn))
      while (e < rows.size() && e - k < 4 && !onTree(rows[e]) && work.a[e] == work.a[k] &&
             work.b[e] == work.b[k] && (rows[e].n - c.n).squaredNorm() < 1e-18)
        ++e;
    SolverWork::Group g;
    g.first = static_cast<int>(k);
    g.size = static_cast<int>(e - k);
    for (std::size_t i = k; i < e; ++i) rows[i].face = g.size >= 3;
    if (g.size > 1) {
      Eigen::Matrix4d K = Eigen::Matrix4d::Identity();  // unused rows: a unit diagonal
      Eigen::Vector3d rn_a[4], rn_b[4];
      for (int i = 0; i < g.size; ++i) {
        rn_a[i] = rows[k + i].ra.cross(c.n);
        rn_b[i] = rows[k + i].rb.cross(c.n);
      }
      const SolverWork::Response& A = work.response[work.a[k]];
      const SolverWork::Response& B = work.response[work.b[k]];
      const bool b_moves = work.b[k] + 1 < static_cast<int>(work.response.size());
      Eigen::Vector3d Irn_a[4], Irn_b[4];
      for (int j = 0; j < g.size; ++j) {
        Irn_a[j].noalias() = A.inv_inertia * rn_a[j];
        if (b_moves) Irn_b[j].noalias() = B.inv_inertia * rn_b[j];
      }
      for (int i = 0; i < g.size; ++i)
        for (int j = i; j < g.size; ++j) {
          K(i, j) = A.inv_mass + B.inv_mass + rn_a[i].dot(Irn_a[j]);
          if (b_moves) K(i, j) += rn_b[i].dot(Irn_b[j]);
          K(j, i) = K(i, j);
        }
      g.pinv = pseudoInverse(K, g.size, c.n, rn_a);
    }
    work.groups.push_back(g);
    k = e;
  }
}

}  // namespace detail
}  // namespace sim
}  // namespace cga_rigid_sim
