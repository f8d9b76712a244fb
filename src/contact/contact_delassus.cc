// The solver's rows (doc/contacts.md#solver): per contact its bodies' slots, lever arms, basis
// (n, t1, t2) and Delassus block K, the velocity change at the contact point per unit impulse
// there, with the inverses the sweeps step by. Tree sides add their J M⁻¹ Jᵀ
// (contact_tree_jacobians.cc).
#include <algorithm>
#include <cmath>
#include <limits>

#include "contact/contact_solver_internals.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// A tangent basis of the plane ⟂ n (any; the friction cone is circular).
void tangents(const Eigen::Vector3d& n, Eigen::Vector3d& t1, Eigen::Vector3d& t2) {
  const Eigen::Vector3d ref =
      std::abs(n.x()) < 0.57735 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  t1 = n.cross(ref).normalized();
  t2 = n.cross(t1);
}

// The movable bodies' part of K: Σ (1/m) 1 − [r]× I⁻¹ [r]×. In the contact basis
// B = (n, t1, t2) a body's part is Kc_ij = δ_ij / m + (r × b_i)ᵀ I⁻¹ (r × b_j) (the upper
// triangle is filled), and K n = n / m − r × I⁻¹ (r × n): three lever arms and their
// responses, not 3 × 3 products.
void addBodySides(const std::vector<SolverBody>& bodies, ContactRow& c, Eigen::Matrix3d& Kc) {
  for (int side = 0; side < 2; ++side) {
    const int s = side ? c.b : c.a;
    if (s < 0) continue;
    const Eigen::Vector3d& r = side ? c.rb : c.ra;
    const Eigen::Matrix3d& Iinv = bodies[s].inv_inertia;
    const Eigen::Vector3d rn = r.cross(c.n), r1 = r.cross(c.t1), r2 = r.cross(c.t2);
    const Eigen::Vector3d In = Iinv * rn, I1 = Iinv * r1, I2 = Iinv * r2;
    const double m = bodies[s].inv_mass;
    Kc(0, 0) += m + rn.dot(In);
    Kc(0, 1) += rn.dot(I1);
    Kc(0, 2) += rn.dot(I2);
    Kc(1, 1) += m + r1.dot(I1);
    Kc(1, 2) += r1.dot(I2);
    Kc(2, 2) += m + r2.dot(I2);
    c.k_n += m * c.n - r.cross(In);
  }
}

// The row's normal and tangent responses from Kc (upper triangle filled): k_nn, the tangent
// block's inverse and largest eigenvalue k_t, and their inverses.
void invertBlock(Eigen::Matrix3d& Kc, ContactRow& c) {
  Kc(1, 0) = Kc(0, 1);
  Kc(2, 0) = Kc(0, 2);
  Kc(2, 1) = Kc(1, 2);
  const double trace = Kc.trace();  // K's: B is orthonormal
  // A free body's K is positive definite; a tree side's J M⁻¹ Jᵀ has the rank of the motions
  // the link can make at the point (one for a pendulum's bob): directions it cannot move in
  // get no impulse (their inverse is taken as zero, their k as infinite), and an impulse
  // that could only act along them is none. Round-off decides below 1e-12 of K's trace.
  const double cutoff = 1e-12 * trace;
  const double inf = std::numeric_limits<double>::infinity();
  c.k_nn = Kc(0, 0) > cutoff ? Kc(0, 0) : inf;
  const double tr = Kc(1, 1) + Kc(2, 2), det = Kc(1, 1) * Kc(2, 2) - Kc(1, 2) * Kc(2, 1);
  if (det > 1e-12 * tr * tr) {  // both tangent directions movable (always for free bodies)
    c.k_t = 0.5 * tr + std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
    c.k_tt_inv << Kc(2, 2) / det, -Kc(1, 2) / det, -Kc(2, 1) / det, Kc(1, 1) / det;
  } else {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> tangent(Kc.bottomRightCorner<2, 2>());
    c.k_tt_inv.setZero();
    const double top = tangent.eigenvalues()(1);
    if (top > cutoff)
      c.k_tt_inv = tangent.eigenvectors().col(1) * tangent.eigenvectors().col(1).transpose() / top;
    c.k_t = top > cutoff ? top : inf;
  }
  c.inv_k_nn = 1.0 / c.k_nn;  // 0 for an infinite k: no impulse
  c.inv_k_t = 1.0 / c.k_t;
}

// The contact's surface parameters and depth; the impulses of the extensions and of the
// position correction cleared (the warm start sets lambda_n and lambda_t: contact_rows.cc).
void startRow(const Contact& ct, ContactRow& c) {
  c.mu = c.mu_surface = ct.mu;
  c.restitution = ct.restitution;
  c.depth = ct.depth;
  c.lambda_p = 0.0;
  c.lambda_spin = 0.0;
  c.lambda_roll.setZero();
  c.couple.setZero();
  c.compliant = false;
  c.lambda_fixed = 0.0;
  c.target_t.setZero();
}

}  // namespace

void prepareRows(const std::vector<Contact>& contacts, const std::vector<SolverBody>& bodies,
                 const std::vector<SolverTree>& trees, const std::vector<int>& slot_a,
                 const std::vector<int>& slot_b, std::vector<ContactRow>& rows) {
  rows.resize(contacts.size());
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const Contact& ct = contacts[k];
    ContactRow& c = rows[k];
    c.a = slot_a[k];
    c.b = slot_b[k];
    c.n = ct.normal_W;
    tangents(c.n, c.t1, c.t2);
    c.ra = c.a >= 0 ? Eigen::Vector3d(ct.point_W - bodies[c.a].x) : Eigen::Vector3d::Zero();
    c.rb = c.b >= 0 ? Eigen::Vector3d(ct.point_W - bodies[c.b].x) : Eigen::Vector3d::Zero();
    detail::takeTreeSides(bodies, trees, ct.point_W, c);
    // K = Σ (1/m) 1 − [r]× I⁻¹ [r]× over the movable bodies, + J M⁻¹ Jᵀ over the tree sides.
    Eigen::Matrix3d Kc = Eigen::Matrix3d::Zero();
    c.k_n.setZero();
    addBodySides(bodies, c, Kc);
    if (c.ta >= 0 || c.tb >= 0) detail::addTreeSides(trees, c, Kc);
    invertBlock(Kc, c);
    startRow(ct, c);
  }
}

}  // namespace sim
}  // namespace cga_rigid_sim
