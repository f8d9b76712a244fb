// Moment: the body trivector torque T = (x∧f)∧n − (λ/2) n̄∧f∧n (doc/conventions.md (E13)).
//
// With E = e∧ē = ½ n̄∧n, n̄∧e_i∧n = −2 e_i∧E, so T = τ_i (I3 e_i)∧n + λ f_i e_i∧E with τ = x×f.
// Stored as six blade coefficients in the order
//   e23n, e31n, e12n (rotation part: the torque τ about the centre of mass, body axes)
//   e1E, e2E, e3E    (translation part: λ f, f the force, body axes).
// Moments, momenta (I(Ω)∧n) and impulses all live in this space.
#pragma once

#include <Eigen/Core>
#include <array>

namespace cga_rigid_sim {
namespace cga {

struct Moment {
  Eigen::Vector3d rot = Eigen::Vector3d::Zero();    ///< e23n, e31n, e12n coefficients (= τ)
  Eigen::Vector3d trans = Eigen::Vector3d::Zero();  ///< e1E, e2E, e3E coefficients (= λ f)

  Moment() = default;
  Moment(const Eigen::Vector3d& rot_coeffs, const Eigen::Vector3d& trans_coeffs)
      : rot(rot_coeffs), trans(trans_coeffs) {}

  /// A pure couple τ (body axes).
  static Moment couple(const Eigen::Vector3d& tau) { return {tau, Eigen::Vector3d::Zero()}; }
  /// The moment of a Euclidean force f applied at x (both body axes, x from the centre of
  /// mass). This is λ X∧F back-rotated and wedged with n; the multiplier α of F = f + αn drops
  /// out exactly, which is why it does not appear here.
  static Moment ofForceAt(const Eigen::Vector3d& f, const Eigen::Vector3d& x, double lambda) {
    return {x.cross(f), lambda * f};
  }
  /// Torque about the centre of mass, body axes.
  const Eigen::Vector3d& torque() const { return rot; }
  /// Force, body axes.
  Eigen::Vector3d force(double lambda) const { return trans / lambda; }

  /// Coefficients in blade order e23n, e31n, e12n, e1E, e2E, e3E.
  std::array<double, 6> coefficients() const {
    return {rot.x(), rot.y(), rot.z(), trans.x(), trans.y(), trans.z()};
  }
  bool allFinite() const { return rot.allFinite() && trans.allFinite(); }

  Moment operator+(const Moment& o) const { return {rot + o.rot, trans + o.trans}; }
  Moment operator-(const Moment& o) const { return {rot - o.rot, trans - o.trans}; }
  Moment operator*(double k) const { return {k * rot, k * trans}; }
  Moment& operator+=(const Moment& o) {
    rot += o.rot;
    trans += o.trans;
    return *this;
  }
};

inline Moment operator*(double k, const Moment& m) { return m * k; }

}  // namespace cga
}  // namespace cga_rigid_sim
