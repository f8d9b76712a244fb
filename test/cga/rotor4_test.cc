// Tests of the 1-up algebra (cga/rotor4.h, cga/bivector4.h) against the reference algebra.
//
// Truth: cga::Multivector, the 32-blade Cl(4,1), with e4 ↦ e (σ = +1, Cl(4,0)) or e4 ↦ ē
// (σ = −1, Cl(3,1)); exp against the scaling-and-squaring Taylor series of the reference
// (test/common/cga_embedding.h expReference). Tolerances: the quantities are O(1) and each is
// a handful of products and sums, so a few tens of ε (1e-14) separates round-off from any wrong
// sign or table entry (which would be O(1)). exp: the reference's own error is ~32 squarings of
// round-off on |exp| ≤ e^8, so the tolerance is relative to the size of the result.
#include "cga_rigid_sim/cga/rotor4.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/cga_embedding.h"
#include "common/curved_embedding.h"

namespace cga_rigid_sim {
namespace cga {
namespace rotor4_test {

using testing::Rng;
using testing::toMV;

Rotor4 randomEven(Rng& rng, double scale) {
  Rotor4 r;
  for (double& x : r.c) x = rng.uniform(-scale, scale);
  return r;
}
Bivector4 randomBivector(Rng& rng, double scale) {
  return Bivector4(rng.vec(scale), rng.vec(scale));
}

class Rotor4Test : public ::testing::TestWithParam<int> {};
INSTANTIATE_TEST_SUITE_P(BothSignatures, Rotor4Test, ::testing::Values(1, -1),
                         [](const ::testing::TestParamInfo<int>& i) {
                           return i.param > 0 ? std::string("sphere") : std::string("hyperbolic");
                         });

TEST_P(Rotor4Test, ProductMatchesReferenceAlgebra) {
  const int sigma = GetParam();
  Rng rng(11);
  for (int i = 0; i < 200; ++i) {
    const Rotor4 a = randomEven(rng, 1.0), b = randomEven(rng, 1.0);
    const Multivector ref = toMV(a, sigma) * toMV(b, sigma);
    EXPECT_LE(maxAbsDiff(toMV(multiply(a, b, sigma), sigma), ref), 1e-14);
    EXPECT_LE(maxAbsDiff(toMV(reverse(a), sigma), toMV(a, sigma).reverse()), 0.0);
  }
}

TEST_P(Rotor4Test, BivectorProductsMatchReferenceAlgebra) {
  const int sigma = GetParam();
  Rng rng(12);
  for (int i = 0; i < 200; ++i) {
    const Bivector4 A = randomBivector(rng, 1.0), B = randomBivector(rng, 1.0);
    const Multivector a = toMV(A, sigma), b = toMV(B, sigma);
    EXPECT_LE(maxAbsDiff(toMV(commutator(A, B, sigma), sigma), commutator(a, b)), 1e-14);
    EXPECT_NEAR(scalarProduct(A, B, sigma), (a * b).scalarPart(), 1e-14);
    // A∧B = wedge4 · I with I = e1e2e3e4.
    const Multivector I = testing::basis4(0, sigma) * testing::basis4(1, sigma) *
                          testing::basis4(2, sigma) * testing::basis4(3, sigma);
    EXPECT_LE(maxAbsDiff(wedge4(A, B) * I, (a ^ b)), 1e-14);
    // Vectors: v·B, ψvψ̃, a∧b.
    Eigen::Vector4d v;
    v << rng.vec(1.0), rng.uniform(-1, 1);
    Eigen::Vector4d w;
    w << rng.vec(1.0), rng.uniform(-1, 1);
    const Multivector vm = testing::vectorMV(v, sigma);
    EXPECT_LE((dot(v, B, sigma) - testing::vectorOf(cga::inner(vm, b), sigma)).norm(), 1e-14);
    EXPECT_LE(maxAbsDiff(toMV(wedge(v, w), sigma), (vm ^ testing::vectorMV(w, sigma))), 1e-15);
    EXPECT_NEAR(dot(v, w, sigma), cga::inner(vm, testing::vectorMV(w, sigma)).scalarPart(), 1e-15);
  }
}

TEST_P(Rotor4Test, ExpMatchesTaylorSeriesAndIsARotor) {
  const int sigma = GetParam();
  Rng rng(13);
  // Sizes from the series branch (|B²| < 1e-2) to |B| ~ 6, and the special bivectors: simple
  // rotations, simple boosts, isoclinic (α ± β = 0 on one side), and zero.
  std::vector<Bivector4> cases;
  for (double scale : {1e-4, 0.03, 0.3, 1.0, 3.0})
    for (int i = 0; i < 40; ++i) cases.push_back(randomBivector(rng, scale));
  cases.push_back(Bivector4({0, 0, 2.5}, {0, 0, 0}));
  cases.push_back(Bivector4({0, 0, 0}, {1.7, 0, 0}));
  cases.push_back(Bivector4({0.8, 0, 0}, {0.8, 0, 0}));  // e23 + e14: B∧B ≠ 0, isoclinic for σ=+1
  cases.push_back(Bivector4({0.8, 0, 0}, {-0.8, 0, 0}));
  cases.push_back(Bivector4());
  for (const Bivector4& B : cases) {
    const Rotor4 R = exp(B, sigma);
    const Multivector ref = testing::expReference(toMV(B, sigma));
    const double size = std::max(1.0, ref.norm2());
    EXPECT_LE(maxAbsDiff(toMV(R, sigma), ref), 4e-14 * size) << toMV(B, sigma);
    // ψψ̃ = 1 (relative to |ψ|², which grows for boosts).
    EXPECT_LE(unitDrift(R, sigma), 4e-15 * size * size) << toMV(B, sigma);
  }
}

TEST_P(Rotor4Test, ExpBladeIsExpOfTheBlade) {
  const int sigma = GetParam();
  for (int k = 0; k < 6; ++k)
    for (double theta : {-2.0, -0.1, 1e-5, 0.7, 3.0}) {
      Bivector4 B;
      B[k] = theta;
      EXPECT_LE(maxAbsDiff(toMV(expBlade(k, theta, sigma), sigma), toMV(exp(B, sigma), sigma)),
                1e-14 * std::cosh(theta))
          << k << " " << theta;
    }
}

TEST_P(Rotor4Test, RotationsKeepTheMetricAndMatchTheSandwich) {
  const int sigma = GetParam();
  Rng rng(14);
  const Eigen::Matrix4d G = Eigen::Vector4d(1, 1, 1, sigma).asDiagonal();
  for (int i = 0; i < 50; ++i) {
    const Rotor4 psi = exp(randomBivector(rng, 1.0), sigma);
    const Eigen::Matrix4d M = toMatrix(psi, sigma);
    EXPECT_LE((M.transpose() * G * M - G).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_NEAR(M.determinant(), 1.0, 1e-12);  // proper: a rotor, not a reflection
    Eigen::Vector4d v;
    v << rng.vec(1.0), rng.uniform(-1, 1);
    const Multivector ref =
        toMV(psi, sigma) * testing::vectorMV(v, sigma) * toMV(psi, sigma).reverse();
    EXPECT_LE((rotate(psi, v, sigma) - testing::vectorOf(ref, sigma)).norm(), 1e-13);
    const Bivector4 B = randomBivector(rng, 1.0);
    const Multivector refB = toMV(psi, sigma) * toMV(B, sigma) * toMV(psi, sigma).reverse();
    EXPECT_LE(maxAbsDiff(toMV(rotate(psi, B, sigma), sigma), refB), 1e-13);
    const Multivector refBack = toMV(psi, sigma).reverse() * toMV(B, sigma) * toMV(psi, sigma);
    EXPECT_LE(maxAbsDiff(toMV(rotateBack(psi, B, sigma), sigma), refBack), 1e-13);
  }
}

// The signed permutations of bladeAction (the hot path of curved2) are the products they
// stand for: ψ e_k and e_k × L, exactly (each is a copy with a sign, no rounding).
TEST_P(Rotor4Test, BladeActionsAreTheProductsWithTheBlade) {
  const int sigma = GetParam();
  Rng rng(15);
  for (int k = 0; k < 6; ++k) {
    const BladeAction& a = bladeAction(k, sigma);
    Bivector4 e;
    e[k] = 1.0;
    Rotor4 eR = Rotor4::fromCoefficients({0, 0, 0, 0, 0, 0, 0, 0});
    eR.c[k + 1] = 1.0;
    for (int i = 0; i < 10; ++i) {
      const Rotor4 psi = randomEven(rng, 1.0);
      const Rotor4 pe = multiply(psi, eR, sigma);
      for (int m = 0; m < 8; ++m) EXPECT_EQ(pe.c[m], a.rightSign[m] * psi.c[a.rightIndex[m]]);
      const Bivector4 L = randomBivector(rng, 1.0);
      const Bivector4 X = commutator(e, L, sigma);
      for (int m = 0; m < 6; ++m) EXPECT_EQ(X[m], a.bracketSign[m] * L[a.bracketIndex[m]]);
    }
  }
}

// Sense checks of doc/curved_space.md: exp(−½θ e12) turns e1 towards e2 (the sense of
// doc/conventions.md (E3)), and exp(−½θ e14) carries the origin O = −R e4 towards +e1 on both
// the sphere (by R sin θ) and the hyperboloid (by |R| sinh θ).
TEST_P(Rotor4Test, RotationAndTranslationSense) {
  const int sigma = GetParam();
  const double theta = 0.3;
  const Eigen::Vector4d e1 =
      rotate(expBlade(2, -0.5 * theta, sigma), Eigen::Vector4d::Unit(0), sigma);
  EXPECT_NEAR(e1[0], std::cos(theta), 1e-15);
  EXPECT_NEAR(e1[1], std::sin(theta), 1e-15);
  const double R = 5.0 * sigma;
  const Eigen::Vector4d O(0, 0, 0, -R);
  const Eigen::Vector4d X = rotate(expBlade(3, -0.5 * theta, sigma), O, sigma);
  const double expected = std::abs(R) * (sigma > 0 ? std::sin(theta) : std::sinh(theta));
  EXPECT_NEAR(X[0], expected, 1e-14);
  EXPECT_NEAR(dot(X, X, sigma), sigma * R * R, 1e-13);
}

}  // namespace rotor4_test
}  // namespace cga
}  // namespace cga_rigid_sim
