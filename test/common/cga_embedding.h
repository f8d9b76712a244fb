// The hot-path value types written out as full Cl(4,1) multivectors, so tests can compare every
// operation with the reference algebra. Each function spells the blade sum of the type's
// documented coefficient order (doc/conventions.md#blade-orders) with the reference's own
// products, so nothing here shares code with the hot path.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <random>

#include "cga_rigid_sim/cga/bivelocity.h"
#include "cga_rigid_sim/cga/force.h"
#include "cga_rigid_sim/cga/moment.h"
#include "cga_rigid_sim/cga/motor.h"
#include "cga_rigid_sim/cga/multivector.h"

namespace cga_rigid_sim {
namespace testing {

using cga::Multivector;

inline Multivector e23() { return Multivector::e2() * Multivector::e3(); }
inline Multivector e31() { return Multivector::e3() * Multivector::e1(); }
inline Multivector e12() { return Multivector::e1() * Multivector::e2(); }
/// E = e∧ē = ½ n̄∧n.
inline Multivector E() { return (Multivector::e() ^ Multivector::ebar()); }
inline Multivector euclid(const Eigen::Vector3d& v) {
  return Multivector::vector(v.x(), v.y(), v.z(), 0, 0);
}

/// s + c23 e23 + c31 e31 + c12 e12 + c1 e1n + c2 e2n + c3 e3n + c123 e123n.
inline Multivector toMV(const cga::Motor& M) {
  const auto c = M.coefficients();
  const Multivector n = Multivector::n();
  return Multivector::scalar(c[0]) + c[1] * e23() + c[2] * e31() + c[3] * e12() +
         c[4] * (Multivector::e1() * n) + c[5] * (Multivector::e2() * n) +
         c[6] * (Multivector::e3() * n) + c[7] * (Multivector::I3() * n);
}
/// w1 e23 + w2 e31 + w3 e12 + u1 e1n + u2 e2n + u3 e3n.
inline Multivector toMV(const cga::Bivelocity& B) {
  const Multivector n = Multivector::n();
  return B.rot.x() * e23() + B.rot.y() * e31() + B.rot.z() * e12() +
         B.trans.x() * (Multivector::e1() ^ n) + B.trans.y() * (Multivector::e2() ^ n) +
         B.trans.z() * (Multivector::e3() ^ n);
}
/// τ1 e23∧n + τ2 e31∧n + τ3 e12∧n + c1 e1∧E + c2 e2∧E + c3 e3∧E.
inline Multivector toMV(const cga::Moment& T) {
  const Multivector n = Multivector::n();
  return T.rot.x() * (e23() ^ n) + T.rot.y() * (e31() ^ n) + T.rot.z() * (e12() ^ n) +
         T.trans.x() * (Multivector::e1() ^ E()) + T.trans.y() * (Multivector::e2() ^ E()) +
         T.trans.z() * (Multivector::e3() ^ E());
}
/// F = f + α n.
inline Multivector toMV(const cga::Force& F) { return euclid(F.f) + F.alpha * Multivector::n(); }
/// X(x) = (x² n + 2λx − λ² n̄) / (2λ²), the point of doc/conventions.md (E1).
inline Multivector pointMV(const Eigen::Vector3d& x, double lambda) {
  return (x.squaredNorm() * Multivector::n() + 2.0 * lambda * euclid(x) -
          lambda * lambda * Multivector::nbar()) /
         (2.0 * lambda * lambda);
}
/// exp by scaling and squaring of the plain Taylor series: a third opinion on exp, independent
/// of the closed form. For |A| ≤ 8, A/32 has size ≤ 0.25 and 30 terms leave a truncation error
/// 0.25^30/30! far below ε; five squarings amplify the series' rounding only ~32-fold.
inline Multivector expReference(const Multivector& A) {
  Multivector X = cga::expSeries(A / 32.0, 30);
  for (int i = 0; i < 5; ++i) X = X * X;
  return X;
}

/// Uniform random numbers with a fixed seed, drawn one statement at a time (argument
/// evaluation order is unspecified in C++).
class Rng {
 public:
  explicit Rng(unsigned seed) : gen_(seed) {}
  double uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(gen_);
  }
  Eigen::Vector3d vec(double scale) {
    Eigen::Vector3d v;
    v.x() = uniform(-scale, scale);
    v.y() = uniform(-scale, scale);
    v.z() = uniform(-scale, scale);
    return v;
  }
  Eigen::Quaterniond rotation() {
    Eigen::Vector4d c;
    for (int i = 0; i < 4; ++i) c[i] = std::normal_distribution<double>(0.0, 1.0)(gen_);
    c.normalize();
    return Eigen::Quaterniond(c[0], c[1], c[2], c[3]);
  }
  cga::Motor motor(double translation_scale, double lambda) {
    const Eigen::Quaterniond R = rotation();
    const Eigen::Vector3d x = vec(translation_scale);
    return cga::Motor::fromPose(R, x, lambda);
  }
  std::mt19937_64& engine() { return gen_; }

 private:
  std::mt19937_64 gen_;
};

}  // namespace testing
}  // namespace cga_rigid_sim
