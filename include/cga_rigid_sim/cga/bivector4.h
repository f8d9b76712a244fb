// Bivector4: a bivector of the "1 up" algebra on e1, e2, e3, e4 (doc/curved_space.md#algebra),
// the Lie algebra of rigid motions of a space of constant curvature: so(4) on the sphere
// (e4 = e, e4² = +1), so(3,1) on the hyperboloid (e4 = ē, e4² = −1).
//
// Stored as six blade coefficients in the order
//   e23, e31, e12      (rotation part: the angular velocity vector w, as in cga::Bivelocity)
//   e14, e24, e34      (translation part e_i∧e4: u = v/|R|, v the velocity of the centre)
// which is cga::Bivelocity's order with n replaced by e4. The storage does not depend on the
// signature; products that do take σ = e4² (cga/rotor4.h).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>

namespace cga_rigid_sim {
namespace cga {

struct Bivector4 {
  Eigen::Vector3d rot = Eigen::Vector3d::Zero();    ///< e23, e31, e12 coefficients
  Eigen::Vector3d trans = Eigen::Vector3d::Zero();  ///< e14, e24, e34 coefficients

  Bivector4() = default;
  Bivector4(const Eigen::Vector3d& rot_coeffs, const Eigen::Vector3d& trans_coeffs)
      : rot(rot_coeffs), trans(trans_coeffs) {}

  /// Coefficient k in storage order (0..5).
  double operator[](int k) const { return k < 3 ? rot[k] : trans[k - 3]; }
  double& operator[](int k) { return k < 3 ? rot[k] : trans[k - 3]; }

  std::array<double, 6> coefficients() const {
    return {rot.x(), rot.y(), rot.z(), trans.x(), trans.y(), trans.z()};
  }
  static Bivector4 fromCoefficients(const std::array<double, 6>& c) {
    return Bivector4({c[0], c[1], c[2]}, {c[3], c[4], c[5]});
  }
  bool allFinite() const { return rot.allFinite() && trans.allFinite(); }
  /// Euclidean norm of the six coefficients (a magnitude for tolerances, not a metric norm).
  double coefficientNorm() const { return std::sqrt(rot.squaredNorm() + trans.squaredNorm()); }

  Bivector4 operator+(const Bivector4& o) const { return {rot + o.rot, trans + o.trans}; }
  Bivector4 operator-(const Bivector4& o) const { return {rot - o.rot, trans - o.trans}; }
  Bivector4 operator-() const { return {-rot, -trans}; }
  Bivector4 operator*(double k) const { return {k * rot, k * trans}; }
  Bivector4& operator+=(const Bivector4& o) {
    rot += o.rot;
    trans += o.trans;
    return *this;
  }
};

inline Bivector4 operator*(double k, const Bivector4& B) { return B * k; }

/// The outer product a∧b of two vectors of the 1-up space (coefficients (x1, x2, x3, x4)), which
/// does not depend on the signature.
inline Bivector4 wedge(const Eigen::Vector4d& a, const Eigen::Vector4d& b) {
  return Bivector4(
      {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]},
      {a[0] * b[3] - a[3] * b[0], a[1] * b[3] - a[3] * b[1], a[2] * b[3] - a[3] * b[2]});
}

}  // namespace cga
}  // namespace cga_rigid_sim
