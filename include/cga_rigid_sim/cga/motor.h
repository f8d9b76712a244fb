// Motor: a rigid motion M = T(x) R of the conformal model (doc/conventions.md (E4)), the even
// element
//   M = s + c23 e23 + c31 e31 + c12 e12 + c1 e1n + c2 e2n + c3 e3n + c123 e123n.
//
// How it computes (derivation in doc/conventions.md#motor-algebra-as-dual-quaternions): writing
// M = R + (I3 Q) n, with R and Q in the even subalgebra of Cl(3), the pair (R, Q) multiplies
// like a dual quaternion, because n commutes with even and anticommutes with odd elements of
// Cl(3), and n² = 0. The motor keeps that pair as two Hamilton quaternions (i = −e23, j = −e31,
// k = −e12):
//   rotor r = (s, −c23, −c31, −c12),   dual part q = (c123, c1, c2, c3).
// Every operation below is the algebra's product written out in this form; test/cga checks each
// against the 32-blade reference multivector.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <iosfwd>
#include <limits>

#include "cga_rigid_sim/cga/bivelocity.h"
#include "cga_rigid_sim/cga/force.h"
#include "cga_rigid_sim/cga/moment.h"
#include "cga_rigid_sim/cga/point.h"

namespace cga_rigid_sim {
namespace cga {

class Motor {
 public:
  /// The identity motion.
  Motor() : r_(1, 0, 0, 0), q_(0, 0, 0, 0) {}

  /// Motor from its rotor and dual quaternions (see the header comment).
  static Motor fromQuaternions(const Eigen::Quaterniond& r, const Eigen::Quaterniond& q) {
    Motor m;
    m.r_ = r;
    m.q_ = q;
    return m;
  }
  static Motor identity() { return Motor(); }
  /// The rotor R of a unit quaternion (R x R̃ rotates x as the quaternion does).
  static Motor rotor(const Eigen::Quaterniond& R) {
    return fromQuaternions(R, Eigen::Quaterniond(0, 0, 0, 0));
  }
  /// The translator T(a) = 1 + n a / (2λ).
  static Motor translator(const Eigen::Vector3d& a, double lambda) {
    const double k = -0.5 / lambda;
    return fromQuaternions(Eigen::Quaterniond(1, 0, 0, 0),
                           Eigen::Quaterniond(0, k * a.x(), k * a.y(), k * a.z()));
  }
  /// M = T(x) R: rotate by R, then translate by x.
  static Motor fromPose(const Eigen::Quaterniond& R, const Eigen::Vector3d& x, double lambda) {
    const double k = -0.5 / lambda;
    return fromQuaternions(R, Eigen::Quaterniond(0, k * x.x(), k * x.y(), k * x.z()) * R);
  }
  static Motor fromIsometry(const Eigen::Isometry3d& T, double lambda) {
    return fromPose(Eigen::Quaterniond(T.rotation()), T.translation(), lambda);
  }
  /// From blade coefficients in the order 1, e23, e31, e12, e1n, e2n, e3n, e123n.
  static Motor fromCoefficients(const std::array<double, 8>& c) {
    return fromQuaternions(Eigen::Quaterniond(c[0], -c[1], -c[2], -c[3]),
                           Eigen::Quaterniond(c[7], c[4], c[5], c[6]));
  }
  /// Blade coefficients in the order 1, e23, e31, e12, e1n, e2n, e3n, e123n.
  std::array<double, 8> coefficients() const {
    return {r_.w(), -r_.x(), -r_.y(), -r_.z(), q_.x(), q_.y(), q_.z(), q_.w()};
  }

  const Eigen::Quaterniond& rotorQuaternion() const { return r_; }
  const Eigen::Quaterniond& dualQuaternion() const { return q_; }

  /// Geometric product M1 M2 (apply M2 first, then M1).
  Motor operator*(const Motor& o) const {
    Motor m;
    m.r_ = r_ * o.r_;
    m.q_.coeffs() = (r_ * o.q_).coeffs() + (q_ * o.r_).coeffs();
    return m;
  }
  Motor& operator*=(const Motor& o) { return *this = *this * o; }
  /// Reverse M̃ (the inverse of a unit motor).
  Motor reverse() const { return fromQuaternions(r_.conjugate(), q_.conjugate()); }

  /// The attitude R as a unit quaternion.
  const Eigen::Quaterniond& rotation() const { return r_; }
  /// The translation x of M = T(x) R.
  Eigen::Vector3d translation(double lambda) const {
    return -2.0 * lambda * (q_ * r_.conjugate()).vec();
  }
  Eigen::Isometry3d toIsometry(double lambda) const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = r_.toRotationMatrix();
    T.translation() = translation(lambda);
    return T;
  }

  /// M X(x) M̃ = X(R x R̃ + a): the image of a point.
  Eigen::Vector3d transformPoint(const Eigen::Vector3d& x, double lambda) const {
    return r_ * x + translation(lambda);
  }
  Point apply(const Point& p, double lambda) const { return Point(transformPoint(p.x, lambda)); }
  /// The Euclidean part of M v M̃ for a vector v: the rotated direction R v R̃.
  Eigen::Vector3d transformVector(const Eigen::Vector3d& v) const { return r_ * v; }
  /// M F M̃ for a force vector F = f + αn: (R f R̃) + (α + a·(R f R̃)/λ) n. Motors fix n, so a
  /// force stays a force.
  Force apply(const Force& F, double lambda) const {
    const Eigen::Vector3d f = r_ * F.f;
    return Force(f, F.alpha + translation(lambda).dot(f) / lambda);
  }
  /// M B M̃ for a bivector B of the motor Lie algebra (the adjoint action): carries a body
  /// bivelocity to world axes.
  Bivelocity apply(const Bivelocity& B) const {
    // As dual quaternions: (r, q)(a, b)(r*, q*) = (r a r*, r a q* + q a r* + r b r*).
    const Eigen::Quaterniond a(0, -B.rot.x(), -B.rot.y(), -B.rot.z());
    const Eigen::Quaterniond b(0, B.trans.x(), B.trans.y(), B.trans.z());
    const Eigen::Quaterniond ra = r_ * a;
    const Eigen::Vector3d a_out = (ra * r_.conjugate()).vec();
    const Eigen::Vector3d b_out = (ra * q_.conjugate()).vec() + (q_ * a * r_.conjugate()).vec() +
                                  (r_ * b * r_.conjugate()).vec();
    return Bivelocity(-a_out, b_out);
  }
  /// M T M̃ for a body trivector T (a moment, momentum or impulse, cga/moment.h): carries it
  /// between frames. For M = T(a) R: (τ, λf) ↦ (R τ + a × (R f), λ R f).
  ///
  /// Derivation: the moment of a force F = f + αn at the point X = X(x) is
  /// T = λ X∧F∧n = (x × f)_i (I3 e_i)∧n + λ f_i e_i∧E. A motor is a versor, so its sandwich
  /// distributes over ∧, and it maps X(x) to X(R x + a), F to R f + α'n and n to n. Hence
  /// M T M̃ = λ X(R x + a)∧(R f + α'n)∧n is the moment of R f at R x + a:
  /// τ' = (R x + a) × R f = R τ + a × R f, and f' = R f. The moments (x × f, λ f) span all
  /// trivectors (a couple (τ, 0) is the difference of one force at two points), and the action
  /// is linear, so the formula holds for every T.
  Moment apply(const Moment& T, double lambda) const {
    const Eigen::Vector3d trans = r_ * T.trans;  // λ R f
    return Moment(r_ * T.rot + translation(lambda).cross(trans) / lambda, trans);
  }

  /// |M M̃ − 1| (max coefficient): zero for a unit motor; reported as drift.
  double normDrift() const {
    const double rr = r_.coeffs().squaredNorm() - 1.0;
    const double rq = 2.0 * r_.coeffs().dot(q_.coeffs());
    return std::max(std::abs(rr), std::abs(rq));
  }
  /// The nearest unit motor: rotor normalised, and the part of q along r removed (the e123n
  /// coefficient of M M̃, which must vanish for a rigid motion).
  Motor normalized() const {
    const double inv = 1.0 / r_.norm();
    Eigen::Quaterniond r(r_.coeffs() * inv);
    Eigen::Quaterniond q(q_.coeffs() * inv);
    q.coeffs() -= r.coeffs().dot(q.coeffs()) * r.coeffs();
    return fromQuaternions(r, q);
  }
  bool allFinite() const { return r_.coeffs().allFinite() && q_.coeffs().allFinite(); }

 private:
  Eigen::Quaterniond r_;  ///< rotor part
  Eigen::Quaterniond q_;  ///< dual part (coefficients of e123n, e1n, e2n, e3n)
};

namespace detail {
// sin θ / θ. Below θ = ε^(1/4) the truncation error of 1 − θ²/6 (θ⁴/120) is below ε.
inline double sinc(double t) {
  static const double kThreshold = std::pow(std::numeric_limits<double>::epsilon(), 0.25);
  return std::abs(t) < kThreshold ? 1.0 - t * t / 6.0 : std::sin(t) / t;
}
// (cos θ − sin θ/θ)/θ² = −1/3 + θ²/30 − θ⁴/840 + θ⁶/45360 − … Below θ = ε^(1/6) the terms
// kept leave a truncation error (θ⁶/45360) far below ε/3; above it the direct form loses at
// most ε/θ² ≤ ε^(2/3) relative, and the result is multiplied by θ² where it is used.
inline double cosMinusSincOverT2(double t) {
  static const double kThreshold = std::pow(std::numeric_limits<double>::epsilon(), 1.0 / 6.0);
  const double t2 = t * t;
  if (std::abs(t) < kThreshold) return -1.0 / 3.0 + t2 / 30.0 - t2 * t2 / 840.0;
  return (std::cos(t) - std::sin(t) / t) / t2;
}
}  // namespace detail

/// The exact exponential exp(B) of a bivector B of the motor algebra: a screw motion, in closed
/// form (no series beyond the small-angle branches of sinc). With B ↔ (a, b) = (−rot, trans) as
/// dual pure quaternions, θ = |a|: exp = (cos θ + sinc θ a, −(a·b) sinc θ + (a·b) c(θ) a +
/// sinc θ b), c(θ) = (cos θ − sinc θ)/θ². exp(−½ h Ω) is the motion of a body that keeps the
/// bivelocity Ω for a time h: M(t + h) = M(t) exp(−½ h Ω).
inline Motor exp(const Bivelocity& B) {
  const Eigen::Vector3d a = -B.rot;
  const Eigen::Vector3d& b = B.trans;
  const double theta = a.norm();
  const double sc = detail::sinc(theta);
  const double ab = a.dot(b);
  const Eigen::Vector3d rv = sc * a;
  const Eigen::Vector3d qv = (ab * detail::cosMinusSincOverT2(theta)) * a + sc * b;
  return Motor::fromQuaternions(Eigen::Quaterniond(std::cos(theta), rv.x(), rv.y(), rv.z()),
                                Eigen::Quaterniond(-ab * sc, qv.x(), qv.y(), qv.z()));
}

/// The principal logarithm of a unit motor: the bivector B of the shortest screw, with
/// exp(B) = ±M (M and −M are the same rigid motion; the sign is the one with r_w ≥ 0). The
/// rotation half-angle θ = atan2(|r_vec|, |r_w|) ∈ [0, π/2] (atan2 keeps full relative precision
/// at small angles); at a rotation by π exactly (θ = π/2) the screw axis direction is either.
Bivelocity log(const Motor& M);

std::ostream& operator<<(std::ostream& os, const Motor& M);

}  // namespace cga
}  // namespace cga_rigid_sim
