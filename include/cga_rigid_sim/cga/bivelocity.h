// Bivelocity: the body velocity bivector Ω_B = I3 w + (1/λ) v∧n (doc/conventions.md (E6)).
//
// Stored as its six blade coefficients on the null basis, in the order
//   e23, e31, e12 (rotation part: the angular velocity vector w, body axes)
//   e1n, e2n, e3n (translation part: u = v/λ, v the centre-of-mass velocity, body axes).
// The same type also holds any bivector of this six-dimensional subspace (e.g. the exponent
// −½hΩ of a step), since the motor Lie algebra is exactly that subspace.
#pragma once

#include <Eigen/Core>
#include <array>

namespace cga_rigid_sim {
namespace cga {

struct Bivelocity {
  Eigen::Vector3d rot = Eigen::Vector3d::Zero();    ///< e23, e31, e12 coefficients (= w)
  Eigen::Vector3d trans = Eigen::Vector3d::Zero();  ///< e1n, e2n, e3n coefficients (= v/λ)

  Bivelocity() = default;
  Bivelocity(const Eigen::Vector3d& rot_coeffs, const Eigen::Vector3d& trans_coeffs)
      : rot(rot_coeffs), trans(trans_coeffs) {}

  /// Ω from the angular velocity w and the centre-of-mass velocity v, both in body axes.
  static Bivelocity fromVelocities(const Eigen::Vector3d& w, const Eigen::Vector3d& v,
                                   double lambda) {
    return Bivelocity(w, v / lambda);
  }
  /// Angular velocity vector w (body axes), rad/s.
  const Eigen::Vector3d& angular() const { return rot; }
  /// Centre-of-mass velocity v (body axes), m/s.
  Eigen::Vector3d linear(double lambda) const { return lambda * trans; }

  /// Coefficients in blade order e23, e31, e12, e1n, e2n, e3n.
  std::array<double, 6> coefficients() const {
    return {rot.x(), rot.y(), rot.z(), trans.x(), trans.y(), trans.z()};
  }
  static Bivelocity fromCoefficients(const std::array<double, 6>& c) {
    return Bivelocity({c[0], c[1], c[2]}, {c[3], c[4], c[5]});
  }
  bool allFinite() const { return rot.allFinite() && trans.allFinite(); }

  Bivelocity operator+(const Bivelocity& o) const { return {rot + o.rot, trans + o.trans}; }
  Bivelocity operator-(const Bivelocity& o) const { return {rot - o.rot, trans - o.trans}; }
  Bivelocity operator-() const { return {-rot, -trans}; }
  Bivelocity operator*(double k) const { return {k * rot, k * trans}; }
  Bivelocity& operator+=(const Bivelocity& o) {
    rot += o.rot;
    trans += o.trans;
    return *this;
  }
};

inline Bivelocity operator*(double k, const Bivelocity& b) { return b * k; }

/// Commutator product A × B = ½(AB − BA) of two bivectors of the motor algebra. The result
/// stays in the six-dimensional subspace (it is the Lie bracket of se(3) in CGA form).
/// Derivation: as dual pure quaternions (−w, u) the bracket is (a1×a2, a1×b2 + b1×a2).
inline Bivelocity commutator(const Bivelocity& A, const Bivelocity& B) {
  return {-A.rot.cross(B.rot), -(A.rot.cross(B.trans) + A.trans.cross(B.rot))};
}

}  // namespace cga
}  // namespace cga_rigid_sim
