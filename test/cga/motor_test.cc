// Every operation of the hot-path motor algebra (Motor, Bivelocity, Force, Point, exp, log)
// against the 32-blade reference algebra, on thousands of random inputs (fixed seeds) and on the
// edges: zero rotation, rotation by π, pure translation, angles down to 1e-9, translations of
// 1e6 m.
//
// Tolerances: one reference product of operands of coefficient size ≤ a, b rounds each
// coefficient by at most 32·ε·a·b (32 terms summed). The hot path rounds comparably; a chain of
// k products therefore stays within ~k·64·ε of the magnitudes involved. We allow 256·ε·scale
// for single products (a factor 4 of margin over that bound) — a wrong sign or blade produces an
// O(1) error, so the margin costs no power.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "cga_rigid_sim/cga/eigen.h"
#include "common/cga_embedding.h"

namespace cga_rigid_sim {
namespace motor_test {

using cga::Bivelocity;
using cga::Force;
using cga::Moment;
using cga::Motor;
using cga::Multivector;
using testing::pointMV;
using testing::Rng;
using testing::toMV;

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr int kSamples = 2000;
const double kLambdas[] = {1.0, 7.3};

double maxAbs(const Multivector& a) {
  double m = 0;
  for (unsigned i = 0; i < Multivector::kNumBlades; ++i) m = std::max(m, std::abs(a[i]));
  return m;
}
double relDiff(const Multivector& a, const Multivector& b) {
  return cga::maxAbsDiff(a, b) / std::max(1.0, std::max(maxAbs(a), maxAbs(b)));
}

// Truth: the reference geometric product. Motor::operator* must equal it blade for blade.
TEST(MotorVsReference, ProductEqualsGeometricProduct) {
  Rng rng(1);
  for (double lambda : kLambdas)
    for (int i = 0; i < kSamples; ++i) {
      const Motor A = rng.motor(10.0, lambda);
      const Motor B = rng.motor(10.0, lambda);
      ASSERT_LT(relDiff(toMV(A * B), toMV(A) * toMV(B)), 256 * kEps) << "sample " << i;
    }
}

// Truth: the reference reverse; and M M̃ = 1 for a unit motor (doc/conventions.md (E4)).
TEST(MotorVsReference, ReverseAndUnitNorm) {
  Rng rng(2);
  for (int i = 0; i < kSamples; ++i) {
    const Motor M = rng.motor(100.0, 1.0);
    ASSERT_LT(relDiff(toMV(M.reverse()), toMV(M).reverse()), 4 * kEps);
    // The product's coefficients cancel from terms of size |M|², so its error scales with it.
    const double m2 = std::pow(maxAbs(toMV(M)), 2);
    ASSERT_LT(cga::maxAbsDiff(toMV(M) * toMV(M).reverse(), Multivector::scalar(1.0)),
              256 * kEps * m2);
    ASSERT_LT(M.normDrift(), 64 * kEps * m2);
  }
}

// Truth: T X(x) T̃ = X(x + a) and R X(x) R̃ = X(R x) in the reference algebra
// (doc/conventions.md (E2), (E3));
// Motor::transformPoint must give the same null vector.
TEST(MotorVsReference, ActionOnPoints) {
  Rng rng(3);
  for (double lambda : kLambdas)
    for (int i = 0; i < kSamples; ++i) {
      const Motor M = rng.motor(5.0, lambda);
      const Eigen::Vector3d x = rng.vec(5.0);
      const Multivector X = toMV(M) * pointMV(x, lambda) * toMV(M).reverse();
      const Multivector Y = pointMV(M.transformPoint(x, lambda), lambda);
      ASSERT_LT(relDiff(X, Y), 2048 * kEps) << "sample " << i;
      const cga::Point p = M.apply(cga::Point(x), lambda);
      ASSERT_LT((p.x - M.transformPoint(x, lambda)).norm(), 0.0 + 1e-300);
    }
}

// Truth: M F M̃ in the reference algebra for a force vector F = f + αn; motors fix n, so the
// image is again a force vector (no n̄ or higher-grade part).
TEST(MotorVsReference, ActionOnForceVectors) {
  Rng rng(4);
  for (double lambda : kLambdas)
    for (int i = 0; i < kSamples; ++i) {
      const Motor M = rng.motor(5.0, lambda);
      const Eigen::Vector3d f = rng.vec(3.0);
      const Force F(f, rng.uniform(-2, 2));
      const Multivector ref = toMV(M) * toMV(F) * toMV(M).reverse();
      ASSERT_LT(relDiff(ref, toMV(M.apply(F, lambda))), 2048 * kEps) << "sample " << i;
      ASSERT_LT((M.transformVector(f) - M.rotation() * f).norm(), 8 * kEps * f.norm());
      // Motors fix n (doc/conventions.md#translators-and-rotors).
      ASSERT_LT(relDiff(toMV(M) * Multivector::n() * toMV(M).reverse(), Multivector::n()),
                512 * kEps);
    }
}

// Truth: M T M̃ in the reference algebra for a body trivector
// T = τ_i (I3 e_i)∧n + c_i e_i∧E (doc/architecture.md); a motor maps these six blades to
// themselves, so the image is again a Moment, with no other blade. Tolerance: the sandwich is a
// chain of two reference products, 2 · 64ε of the magnitudes involved (header), and those
// exceed the result's by up to the motor's largest coefficient squared (≤ 4.3² for translations
// ≤ 5√3 m), ≈ 2400ε: 4096ε as for the adjoint action on bivectors. A wrong sign or blade gives
// an O(1) error.
TEST(MotorVsReference, ActionOnMoments) {
  Rng rng(12);
  for (double lambda : kLambdas)
    for (int i = 0; i < kSamples; ++i) {
      const Motor M = rng.motor(5.0, lambda);
      const Eigen::Vector3d tau = rng.vec(3.0);
      const Moment T(tau, rng.vec(3.0));
      const Multivector ref = toMV(M) * toMV(T) * toMV(M).reverse();
      ASSERT_LT(relDiff(ref, toMV(M.apply(T, lambda))), 4096 * kEps) << "sample " << i;
    }
}

// Truth: the sandwich is a group action, (M1 M2) T (M1 M2)~ = M1 (M2 T M̃2) M̃1. Both sides
// are hot-path arithmetic: a few quaternion rotations and a cross product with translations
// |a1| + |a2| ≤ 10√3 m, each rounding a few ε of the largest size a coefficient reaches,
// (1 + (|a1| + |a2|)/λ) · max(|τ|, |λf|); 64ε of that leaves a wide margin.
TEST(Motor, MomentActionComposes) {
  Rng rng(13);
  for (double lambda : kLambdas)
    for (int i = 0; i < kSamples; ++i) {
      const Motor M1 = rng.motor(5.0, lambda);
      const Motor M2 = rng.motor(5.0, lambda);
      const Eigen::Vector3d tau = rng.vec(3.0);
      const Moment T(tau, rng.vec(3.0));
      const Moment once = (M1 * M2).apply(T, lambda);
      const Moment twice = M1.apply(M2.apply(T, lambda), lambda);
      const double scale =
          (1.0 + (M1.translation(lambda).norm() + M2.translation(lambda).norm()) / lambda) *
          std::max(T.rot.norm(), T.trans.norm());
      ASSERT_LT((once.rot - twice.rot).cwiseAbs().maxCoeff(), 64 * kEps * scale) << i;
      ASSERT_LT((once.trans - twice.trans).cwiseAbs().maxCoeff(), 64 * kEps * scale) << i;
    }
}

// Truth: the adjoint action M B M̃ and the commutator ½(AB − BA) in the reference algebra.
TEST(BivelocityVsReference, AdjointActionAndCommutator) {
  Rng rng(5);
  for (int i = 0; i < kSamples; ++i) {
    const Motor M = rng.motor(5.0, 1.0);
    const Bivelocity A(rng.vec(3.0), rng.vec(3.0));
    const Bivelocity B(rng.vec(3.0), rng.vec(3.0));
    ASSERT_LT(relDiff(toMV(M) * toMV(A) * toMV(M).reverse(), toMV(M.apply(A))), 4096 * kEps);
    ASSERT_LT(relDiff(cga::commutator(toMV(A), toMV(B)), toMV(cga::commutator(A, B))), 256 * kEps);
  }
}

// Truth: exp by scaling and squaring of the Taylor series in the reference algebra (a method
// sharing nothing with the closed form). Bounded exponents (coefficients ≤ 3) keep the
// reference's own rounding (≈ 32 squaring steps × 32ε × |B|) near 1e-14; 5e-14 is that bound.
TEST(ExpVsReference, ClosedFormEqualsSeries) {
  Rng rng(6);
  for (int i = 0; i < 500; ++i) {
    const Bivelocity B(rng.vec(1.7), rng.vec(3.0));
    ASSERT_LT(relDiff(toMV(cga::exp(B)), testing::expReference(toMV(B))), 5e-14) << i;
  }
}

// Truth: exp(log M) = ±M (log is exp's inverse up to the double cover: M and −M are the same
// motion); log(exp B) = B for rotation half-angles < π/2. Round trip to 1e-14 relative (the
// required bound), relative to the motor's largest coefficient.
TEST(ExpLog, RoundTripRandom) {
  Rng rng(7);
  for (double lambda : kLambdas)
    for (int i = 0; i < kSamples; ++i) {
      const Motor M = rng.motor(50.0, lambda);
      const Motor M2 = cga::exp(cga::log(M));
      ASSERT_LT(std::min(relDiff(toMV(M2), toMV(M)), relDiff(toMV(M2), -1.0 * toMV(M))), 1e-14)
          << i;
      const Bivelocity B(rng.vec(0.9), rng.vec(10.0));
      const Bivelocity B2 = cga::log(cga::exp(B));
      const double scale = std::max(B.rot.norm(), B.trans.norm());
      ASSERT_LT((B2.rot - B.rot).norm() / scale, 1e-14) << i;
      ASSERT_LT((B2.trans - B.trans).norm() / scale, 1e-14) << i;
    }
}

// Edges. Truth: closed forms of the special cases, written independently here.
TEST(ExpLog, Edges) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1, -2, 0.5).normalized();
  // Zero rotation and pure translation, up to 1e6 m: exp(−½ a∧n/λ)… is the translator exactly,
  // and log returns the translation bivector with no loss.
  for (double lambda : kLambdas)
    for (double d : {0.0, 1e-9, 1.0, 1e3, 1e6}) {
      const Eigen::Vector3d a = d * axis;
      const Motor T = Motor::translator(a, lambda);
      const Bivelocity B = cga::log(T);
      EXPECT_EQ(B.rot.norm(), 0.0);
      EXPECT_LE((B.trans + a / (2 * lambda)).norm(), 2 * kEps * a.norm());
      EXPECT_LE((cga::exp(B).translation(lambda) - a).norm(), 4 * kEps * a.norm());
    }
  // Small angles down to 1e-9: the rotor's vector part is sin(θ/2)·axis, and log must return θ
  // to full relative precision (atan2, sinc branches): 4ε relative.
  for (double theta : {1e-9, 1e-7, 1e-5, 1e-3, 0.1}) {
    const Motor R = cga::exp(Bivelocity(-0.5 * theta * axis, Eigen::Vector3d::Zero()));
    EXPECT_NEAR(R.rotation().vec().norm(), std::sin(theta / 2), 4 * kEps * std::sin(theta / 2));
    const Bivelocity B = cga::log(R);
    EXPECT_NEAR(B.rot.norm(), 0.5 * theta, 4 * kEps * theta) << theta;
    // Screw with a large translation and a tiny rotation: round trip relative to the scale.
    const Motor M = Motor::translator(1e6 * axis.cross(Eigen::Vector3d::UnitZ()), 1.0) * R;
    const Motor M2 = cga::exp(cga::log(M));
    EXPECT_LT(relDiff(toMV(M2), toMV(M)), 1e-14) << theta;
  }
  // Rotation by π (half-angle π/2): r_w = 0 exactly; log must not divide by it.
  const Motor Rpi = Motor::rotor(Eigen::Quaterniond(0, axis.x(), axis.y(), axis.z()));
  const Motor Mpi = Motor::translator(Eigen::Vector3d(3, -1, 2), 1.0) * Rpi;
  EXPECT_LT(relDiff(toMV(cga::exp(cga::log(Mpi))), toMV(Mpi)), 1e-14);
  EXPECT_NEAR(cga::log(Rpi).rot.norm(), M_PI / 2, 4 * kEps);
  // Identity.
  const Bivelocity Z = cga::log(Motor());
  EXPECT_EQ(Z.rot.norm() + Z.trans.norm(), 0.0);
}

// Truth: the rotation sense of doc/conventions.md (E3) — R = exp(−½θ e1e2) rotates e1 towards
// e2 (about +e3).
TEST(Motor, RotationSense) {
  const double theta = 0.3;
  const Motor R =
      cga::exp(Bivelocity(Eigen::Vector3d(0, 0, -0.5 * theta), Eigen::Vector3d::Zero()));
  const Eigen::Vector3d x = R.transformVector(Eigen::Vector3d::UnitX());
  EXPECT_NEAR(x.x(), std::cos(theta), 2 * kEps);
  EXPECT_NEAR(x.y(), std::sin(theta), 2 * kEps);
  // The same rotor built in the reference algebra as cos(θ/2) − sin(θ/2) e1e2.
  const Multivector Rref =
      Multivector::scalar(std::cos(theta / 2)) - std::sin(theta / 2) * testing::e12();
  EXPECT_LT(relDiff(toMV(R), Rref), 2 * kEps);
}

// Truth: the kinematics of doc/conventions.md (E5)-(E6), Ṁ = −½ M Ω_B with Ω_B = I3 w + (1/λ) v∧n:
// along the curve M(t) = M0 exp(−½ t Ω), the centre moves with world velocity R v and the attitude
// turns with body angular velocity w. Central differences at step 1e-5 have truncation error
// ~1e-10·|Ω|³; we allow 1e-8.
TEST(Motor, KinematicsMatchVelocitySplit) {
  Rng rng(8);
  for (double lambda : kLambdas)
    for (int i = 0; i < 200; ++i) {
      const Motor M0 = rng.motor(3.0, lambda);
      const Eigen::Vector3d w = rng.vec(2.0), v = rng.vec(2.0);
      const Bivelocity Om = Bivelocity::fromVelocities(w, v, lambda);
      const double dt = 1e-5;
      const Motor Mp = M0 * cga::exp(-0.5 * dt * Om), Mm = M0 * cga::exp(0.5 * dt * Om);
      const Eigen::Vector3d xdot = (Mp.translation(lambda) - Mm.translation(lambda)) / (2 * dt);
      EXPECT_LT((xdot - M0.rotation() * v).norm(), 1e-8);
      // Body angular velocity from the rotor: 2 r̃ ṙ = (0, w).
      const Eigen::Quaterniond rdot((Mp.rotation().coeffs() - Mm.rotation().coeffs()) / (2 * dt));
      const Eigen::Vector3d w_est = 2.0 * (M0.rotation().conjugate() * rdot).vec();
      EXPECT_LT((w_est - w).norm(), 1e-8);
    }
}

// Truth: the rigid-motion composition of Eigen's Isometry3d; conversions both ways.
TEST(Motor, EigenConversionsRoundTrip) {
  Rng rng(9);
  for (double lambda : kLambdas)
    for (int i = 0; i < kSamples; ++i) {
      const Motor A = rng.motor(10.0, lambda), B = rng.motor(10.0, lambda);
      const Eigen::Isometry3d TA = cga::toIsometry(A, lambda), TB = cga::toIsometry(B, lambda);
      const Eigen::Isometry3d TAB = cga::toIsometry(A * B, lambda);
      ASSERT_LT((TAB.matrix() - (TA * TB).matrix()).cwiseAbs().maxCoeff(), 256 * kEps * 10);
      const Motor A2 = cga::toMotor(TA, lambda);
      // Quaternion from a rotation matrix is defined up to sign: compare M or −M.
      const double d1 = relDiff(toMV(A2), toMV(A)), d2 = relDiff(toMV(A2), -1.0 * toMV(A));
      ASSERT_LT(std::min(d1, d2), 1e-14);
    }
}

// Truth: normalized() returns a unit motor (M M̃ = 1 to round-off) describing the same motion
// as the slightly perturbed input, to first order in the perturbation.
TEST(Motor, RenormalisationRemovesDrift) {
  Rng rng(10);
  for (int i = 0; i < kSamples; ++i) {
    const Motor M = rng.motor(10.0, 1.0);
    auto c = M.coefficients();
    for (double& ci : c) ci *= 1.0 + rng.uniform(-1e-6, 1e-6);
    const Motor P = Motor::fromCoefficients(c);
    ASSERT_GT(P.normDrift(), 1e-9);
    const Motor N = P.normalized();
    ASSERT_LT(N.normDrift(), 16 * kEps);
    ASSERT_LT((N.translation(1.0) - M.translation(1.0)).norm(), 1e-4);
  }
}

// Truth: the point identities (E1) of doc/conventions.md on the hot-path Point's null-vector
// coefficients:
// X² = 0 and X·n = −1, with n = e + ē, n̄ = e − ē written out in the reference.
TEST(Point, NullVectorIdentities) {
  Rng rng(11);
  for (double lambda : kLambdas)
    for (int i = 0; i < kSamples; ++i) {
      const Eigen::Vector3d x = rng.vec(100.0);
      const auto c = cga::Point(x).nullCoefficients(lambda);
      const Multivector X = Multivector::vector(c[0], c[1], c[2], 0, 0) + c[3] * Multivector::n() +
                            c[4] * Multivector::nbar();
      ASSERT_LT(relDiff(X, pointMV(x, lambda)), 4 * kEps);
      const double scale = 1.0 + x.squaredNorm() / (lambda * lambda);
      ASSERT_LT(std::abs((X * X).scalarPart()), 64 * kEps * scale * scale);
      ASSERT_NEAR(cga::inner(X, Multivector::n()).scalarPart(), -1.0, 16 * kEps * scale);
    }
}

}  // namespace motor_test
}  // namespace cga_rigid_sim
