// Tests of Inertia (inertia.h, inertia.cc): validation (each refusal names the body and the rule
// it broke), diagonalisation, the inertia classes and the axis conventions of B, and the 6×6
// map I∧n with its inverse. The map's agreement with the reference algebra's I(Ω) = λ² ∫ρ X∧(X·Ω)
// is in cga_identities_test.cc.
#include "cga_rigid_sim/body/inertia.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <string>

#include "common/cga_embedding.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace inertia_test {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

Matrix3d diag(double a, double b, double c) { return Vector3d(a, b, c).asDiagonal(); }

// The tensor in F that the inertia describes: R_FB diag(J) R_FBᵀ.
Matrix3d reconstructed(const Inertia& I) {
  const Matrix3d R = I.rotationFromPrincipal().toRotationMatrix();
  return R * I.principalMoments().asDiagonal() * R.transpose();
}

// Truth: the rules of Inertia::fromTensor; the messages are part of the interface (they reach
// the user through the URDF loader and the ROS node), so they are compared in full.
TEST(InertiaValidation, RefusesBadMassWithItsValue) {
  const Matrix3d J = diag(1, 2, 3);
  auto zero = Inertia::fromTensor("wheel", 0.0, J);
  ASSERT_FALSE(zero.ok());
  EXPECT_EQ(zero.error(), "body 'wheel': mass must be > 0 (got 0)");
  auto negative = Inertia::fromTensor("wheel", -2.5, J);
  ASSERT_FALSE(negative.ok());
  EXPECT_EQ(negative.error(), "body 'wheel': mass must be > 0 (got -2.5)");
  auto nan = Inertia::fromTensor("wheel", std::numeric_limits<double>::quiet_NaN(), J);
  ASSERT_FALSE(nan.ok());
  EXPECT_EQ(nan.error(), "body 'wheel': mass must be finite (got nan)");
  auto inf = Inertia::fromTensor("wheel", std::numeric_limits<double>::infinity(), J);
  ASSERT_FALSE(inf.ok());
  EXPECT_EQ(inf.error(), "body 'wheel': mass must be finite (got inf)");
}

TEST(InertiaValidation, RefusesNonFiniteAsymmetricAndIndefiniteTensors) {
  Matrix3d J = diag(1, 2, 3);
  J(1, 2) = J(2, 1) = std::numeric_limits<double>::quiet_NaN();
  auto nan = Inertia::fromTensor("arm", 1.0, J);
  ASSERT_FALSE(nan.ok());
  EXPECT_EQ(nan.error(), "body 'arm': inertia tensor entries must be finite");

  Matrix3d A = diag(1, 2, 3);
  A(0, 1) = 0.125;  // exactly representable, so the message shows them as written
  A(1, 0) = 0.25;
  auto asym = Inertia::fromTensor("arm", 1.0, A);
  ASSERT_FALSE(asym.ok());
  EXPECT_EQ(asym.error(),
            "body 'arm': inertia tensor is not symmetric (ixy = 0.125 but iyx = 0.25)");
  // A difference within the relative slack (1e-9 of the largest entry) is round-off: accepted.
  A(1, 0) = 0.125 + 1e-12;
  EXPECT_TRUE(Inertia::fromTensor("arm", 1.0, A).ok());

  auto indefinite = Inertia::fromTensor("arm", 1.0, diag(1, 1, -0.5));
  ASSERT_FALSE(indefinite.ok());
  EXPECT_EQ(indefinite.error(),
            "body 'arm': inertia tensor is not positive definite (principal moments -0.5, 1, 1 "
            "kg m^2)");
  auto singular = Inertia::fromTensor("arm", 1.0, diag(0, 1, 1));
  ASSERT_FALSE(singular.ok());
  EXPECT_EQ(singular.error(),
            "body 'arm': inertia tensor is not positive definite (principal moments 0, 1, 1 kg "
            "m^2)");
}

// The triangle inequality I1 + I2 ≥ I3 (the largest moment at most the sum of the others): refused
// by default; with kNearestPhysical the moments are projected along (1, 1, −1) onto I1 + I2 = I3
// (diag(1, 1, 3) → (4/3, 4/3, 8/3), which is symmetric) and the warning says what changed.
TEST(InertiaValidation, RefusesMomentsTooThinToSimulate) {
  // The bound is kMinMomentRatio (1e-12) of the largest moment; 0.5e-12 and 2e-12 are clear of
  // the diagonalisation's round-off (1e-16 of the largest) on either side.
  EXPECT_TRUE(Inertia::fromPrincipal("rod", 1.0, Vector3d(1, 1, 2e-12)).ok());
  auto thin = Inertia::fromPrincipal("rod", 1.0, Vector3d(1, 1, 0.5e-12));
  ASSERT_FALSE(thin.ok());
  EXPECT_EQ(thin.error(),
            "body 'rod': inertia is too thin to simulate: its smallest principal moment 5e-13 "
            "kg m^2 is below 1e-12 of its largest 1 kg m^2 (kMinMomentRatio: round-off would "
            "spin it about that axis)");
  // A subnormal moment (the URDF fuzz target's 2e-309 kg m^2) is positive but refused too.
  EXPECT_FALSE(Inertia::fromPrincipal("ball", 3.0, Vector3d(4.32e-4, 4.32e-4, 2e-309)).ok());
}

TEST(InertiaValidation, TriangleInequalityRefuseOrNearestPhysical) {
  auto refused = Inertia::fromTensor("rod", 1.0, diag(1, 1, 3));
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error(),
            "body 'rod': inertia breaks the triangle inequality I1 + I2 >= I3 (principal moments "
            "1 + 1 < 3 kg m^2)");
  std::string warning;
  auto fixed =
      Inertia::fromTensor("rod", 1.0, diag(1, 1, 3), TrianglePolicy::kNearestPhysical, &warning);
  ASSERT_TRUE(fixed.ok()) << fixed.error();
  EXPECT_EQ(warning,
            "body 'rod': inertia breaks the triangle inequality I1 + I2 >= I3 (principal moments "
            "1 + 1 < 3 kg m^2); using the nearest physical moments 1.3333333333333333, "
            "1.3333333333333333, 2.6666666666666665");
  EXPECT_EQ(fixed->inertiaClass(), InertiaClass::kSymmetric);
  EXPECT_NEAR((fixed->principalMoments() - Vector3d(4, 4, 8) / 3).norm(), 0.0, 1e-15);
  // A flat body sits on the boundary (I1 + I2 = I3) and is accepted as it is.
  std::string none;
  auto flat = Inertia::fromTensor("plate", 1.0, diag(1, 2, 3), TrianglePolicy::kRefuse, &none);
  EXPECT_TRUE(flat.ok());
  EXPECT_TRUE(none.empty());
}

// Truth: J_F = R_FB diag(J) R_FBᵀ. For random rotations of diag(1, 2, 3) the diagonalisation
// finds (1, 2, 3) and a proper rotation that reproduces the tensor; the eigen-solver's error is a
// few ε of the largest moment: bound 1e-12 (absolute, moments ~1).
TEST(InertiaDiagonalisation, RotatedTensorIsReproduced) {
  testing::Rng rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    const Matrix3d R = rng.rotation().toRotationMatrix();
    const Matrix3d J_F = R * diag(1, 2, 3) * R.transpose();
    auto I = Inertia::fromTensor("body", 2.0, J_F);
    ASSERT_TRUE(I.ok()) << I.error();
    EXPECT_EQ(I->inertiaClass(), InertiaClass::kAsymmetric);
    EXPECT_LE((I->principalMoments() - Vector3d(1, 2, 3)).norm(), 1e-12);
    EXPECT_LE((reconstructed(*I) - J_F).norm(), 1e-12);
    EXPECT_NEAR(I->rotationFromPrincipal().toRotationMatrix().determinant(), 1.0, 1e-14);
  }
}

// Symmetric bodies: the distinct axis goes to e3 of B, oblate (distinct largest) or prolate
// (distinct smallest), by a proper rotation; the moments come out exactly equal (the exact
// symmetric paths need J1 == J2). Same truth and bound as above.
TEST(InertiaDiagonalisation, SymmetricBodiesHaveTheirDistinctAxisOnE3) {
  testing::Rng rng(4);
  for (const Vector3d& moments : {Vector3d(2, 2, 3), Vector3d(2, 2, 1)}) {
    for (int trial = 0; trial < 10; ++trial) {
      const Matrix3d R = rng.rotation().toRotationMatrix();
      const Matrix3d J_F = R * moments.asDiagonal() * R.transpose();
      auto I = Inertia::fromTensor("top", 1.0, J_F);
      ASSERT_TRUE(I.ok()) << I.error();
      ASSERT_EQ(I->inertiaClass(), InertiaClass::kSymmetric);
      const Vector3d& J = I->principalMoments();
      EXPECT_EQ(J[0], J[1]);
      EXPECT_NEAR(J[2], moments[2], 1e-12);
      EXPECT_NEAR(J[0], 2.0, 1e-12);
      // B's e3, seen in F, is the distinct axis R e3 (up to sign).
      const Vector3d e3_F = I->rotationFromPrincipal() * Vector3d::UnitZ();
      EXPECT_NEAR(std::abs(e3_F.dot(R.col(2))), 1.0, 1e-12);
      EXPECT_LE((reconstructed(*I) - J_F).norm(), 1e-12);
    }
  }
}

// Classes and the axis order of B: spherical keeps F's axes; a diagonal tensor is sorted by an
// exact permutation (no eigen-solver round-off): asymmetric ascending, right-handed; moments
// equal to 1e-12 relative count as equal (kEqualMomentsRelTol).
TEST(InertiaClasses, ClassesAndAxisOrder) {
  auto sphere = Inertia::fromPrincipal("ball", 1.0, Vector3d(0.4, 0.4, 0.4));
  ASSERT_TRUE(sphere.ok());
  EXPECT_EQ(sphere->inertiaClass(), InertiaClass::kSpherical);
  EXPECT_TRUE(sphere->rotationFromPrincipal().coeffs().isApprox(Quaterniond::Identity().coeffs()));
  auto nearly = Inertia::fromPrincipal("ball", 1.0, Vector3d(0.4, 0.4 * (1 + 1e-13), 0.4));
  ASSERT_TRUE(nearly.ok());
  EXPECT_EQ(nearly->inertiaClass(), InertiaClass::kSpherical);
  EXPECT_STREQ(toString(InertiaClass::kSpherical), "spherical");
  EXPECT_STREQ(toString(InertiaClass::kSymmetric), "symmetric");
  EXPECT_STREQ(toString(InertiaClass::kAsymmetric), "asymmetric");

  // diag(3, 1, 2) in F: B = (1, 2, 3) exactly, axes a proper permutation of F's (up to sign).
  auto box = Inertia::fromPrincipal("box", 1.0, Vector3d(3, 1, 2));
  ASSERT_TRUE(box.ok());
  EXPECT_EQ(box->inertiaClass(), InertiaClass::kAsymmetric);
  EXPECT_EQ(box->principalMoments(), Vector3d(1, 2, 3));
  const Matrix3d R = box->rotationFromPrincipal().toRotationMatrix();
  EXPECT_NEAR(R.determinant(), 1.0, 1e-15);
  EXPECT_NEAR(std::abs(R.col(0).dot(Vector3d::UnitY())), 1.0, 1e-15);  // J = 1 was F's y
  EXPECT_NEAR(std::abs(R.col(1).dot(Vector3d::UnitZ())), 1.0, 1e-15);  // J = 2 was F's z
  EXPECT_NEAR(std::abs(R.col(2).dot(Vector3d::UnitX())), 1.0, 1e-15);  // J = 3 was F's x
}

// Truth: the map I∧n ↔ diag(J1, J2, J3, mλ², mλ², mλ²) on the coefficients (inertia.h) and its
// inverse; T = ½ w·Jw + ½ m v²; the gyroscopic term in Euclidean form (Jw × w, m v × w)·(1, λ).
// Products of a few numbers: 1e-14 relative.
TEST(InertiaMap, ApplySolveEnergyAndGyroscopicTerm) {
  auto I = Inertia::fromPrincipal("body", 2.5, Vector3d(0.5, 0.7, 1.1));
  ASSERT_TRUE(I.ok());
  for (double lambda : {1.0, 7.3}) {
    const Vector3d w(0.3, -2, 1.5), v(1, 2, -0.5);
    const cga::Bivelocity omega = cga::Bivelocity::fromVelocities(w, v, lambda);
    const cga::Moment P = I->apply(omega, lambda);
    EXPECT_LE((P.rot - Vector3d(0.5 * 0.3, 0.7 * -2, 1.1 * 1.5)).norm(), 1e-14);
    EXPECT_LE((P.trans - 2.5 * lambda * v).norm(), 1e-14 * lambda);
    const cga::Bivelocity back = I->solve(P, lambda);
    EXPECT_LE((back.rot - omega.rot).norm(), 1e-14);
    EXPECT_LE((back.trans - omega.trans).norm(), 1e-14);
    const Vector3d Jw = I->principalMoments().cwiseProduct(w);
    EXPECT_NEAR(I->kineticEnergy(omega, lambda), 0.5 * w.dot(Jw) + 0.5 * 2.5 * v.squaredNorm(),
                1e-13);
    const cga::Moment G = I->gyroscopic(omega, lambda);
    EXPECT_LE((G.torque() - Jw.cross(w)).norm(), 1e-14);
    EXPECT_LE((G.force(lambda) - 2.5 * v.cross(w)).norm(), 1e-13);
  }
}

}  // namespace inertia_test
}  // namespace dynamics
}  // namespace cga_rigid_sim
