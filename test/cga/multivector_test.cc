// Tests of the reference algebra Cl(4,1) itself, against facts that do not depend on it: the
// signature, textbook identities of geometric algebra, and the point/motion identities of
// doc/conventions.md checked against Eigen's Euclidean geometry.
//
// Tolerances. ε is machine epsilon and ‖·‖ the coefficient 2-norm (Multivector::norm2).
// - One geometric product: each coefficient of ab is a sum of 32 terms ±a_i b_{i^c}. Higham's
//   dot-product bound gives a round-off of at most γ_32 Σ_i |a_i||b_{i^c}| with
//   γ_32 = 32u/(1 − 32u) < 32ε (u = ε/2), and Σ_i |a_i||b_{i^c}| ≤ ‖a‖‖b‖ by Cauchy–Schwarz
//   (i ↦ i^c is a permutation). So each coefficient errs by ≤ 32ε‖a‖‖b‖; by the same argument
//   each coefficient of ab is ≤ ‖a‖‖b‖ in size, hence ‖ab‖ ≤ √32‖a‖‖b‖.
// - A product of k factors f_i, in any bracketing (induction on the product tree; the reverse
//   and grade projections are exact), whose inputs are each within ρ‖f_i‖ of exact, errs per
//   coefficient by at most  √32^(k−2) ((k−1)·32ε + kρ) Π‖f_i‖  (chainTol below).
// - Inputs built from a formula (points, translators, rotors) take a handful of roundings per
//   coefficient, and cos/sin are within an ulp: we allow ρ = 8ε.
// These are worst-case bounds, loose by orders of magnitude, yet any error of the algebra (a
// wrong sign, a wrong blade) shows up at O(1) relative size, far above them.
#include "cga_rigid_sim/cga/multivector.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>

#include "cga_rigid_sim/math/constants.h"

namespace cga_rigid_sim {
namespace cga {
namespace multivector_test {

using MV = Multivector;

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kInputRelErr = 8 * kEps;
const double kSqrt32 = std::sqrt(32.0);
using math::kPi;

// Round-off bound, per coefficient, of a product of factors with coefficient norms `norms`
// (derivation in the file comment).
double chainTol(std::initializer_list<double> norms, double inputRelErr = kInputRelErr) {
  const int k = static_cast<int>(norms.size());
  double product = 1.0;
  for (double norm : norms) product *= norm;
  return std::pow(kSqrt32, k - 2) * ((k - 1) * 32 * kEps + k * inputRelErr) * product;
}

// Round-off and truncation bound, per coefficient, of expSeries(a, terms) for ‖a‖ = normA.
// The k-th term is a product of k factors a (and k exact-ish divisions), so by chainTol it errs
// by ≈ kε(√32‖a‖)^k/k!; summed over k: √32‖a‖ε e^{√32‖a‖}. The additions add ≤ terms·ε times
// Σ|terms| ≤ e^{√32‖a‖}. The tail beyond `terms` is ≤ (√32‖a‖)^terms/terms! · e^{√32‖a‖}.
double seriesTol(double normA, int terms) {
  const double x = kSqrt32 * normA;
  const double tail = std::pow(x, terms) / std::tgamma(terms + 1.0);
  return ((x + terms) * kEps + tail) * std::exp(x);
}

MV randomMultivector(std::mt19937* rng) {
  std::uniform_real_distribution<double> coeff(-1.0, 1.0);
  MV m;
  for (unsigned i = 0; i < MV::kNumBlades; ++i) m[i] = coeff(*rng);
  return m;
}

// (Draws are sequenced one per statement: the evaluation order of function arguments is
// unspecified, and the samples must not depend on the compiler.)
MV randomVector(std::mt19937* rng) {
  std::uniform_real_distribution<double> coeff(-1.0, 1.0);
  MV v;
  for (unsigned mask : {MV::kE1, MV::kE2, MV::kE3, MV::kE, MV::kEbar}) v[mask] = coeff(*rng);
  return v;
}

Eigen::Vector3d randomPosition(std::mt19937* rng) {
  std::uniform_real_distribution<double> coeff(-3.0, 3.0);  // metres
  Eigen::Vector3d x;
  for (int i = 0; i < 3; ++i) x[i] = coeff(*rng);
  return x;
}

// A Euclidean vector x as the grade-1 element x1 e1 + x2 e2 + x3 e3.
MV euclidean(const Eigen::Vector3d& x) { return MV::vector(x.x(), x.y(), x.z(), 0.0, 0.0); }

// doc/conventions.md (E1): X(x) = (x² n + 2λx − λ² n̄) / (2λ²).
MV point(const Eigen::Vector3d& x, double lambda) {
  return (x.squaredNorm() * MV::n() + 2.0 * lambda * euclidean(x) - lambda * lambda * MV::nbar()) /
         (2.0 * lambda * lambda);
}

// doc/conventions.md (E2): T(a) = 1 + n a / (2λ).
MV translator(const Eigen::Vector3d& a, double lambda) {
  return 1.0 + MV::n() * euclidean(a) / (2.0 * lambda);
}

// doc/conventions.md (E3): R = exp(−θB/2) = cos(θ/2) − sin(θ/2) B for a unit bivector B of
// 3-space (B² = −1).
MV rotor(const MV& B, double theta) { return std::cos(theta / 2) - std::sin(theta / 2) * B; }

// The unit bivector of the plane normal to the unit vector u: B = I3 u (I3 e3 = e1e2).
MV planeOf(const Eigen::Vector3d& u) { return MV::I3() * euclidean(u); }

const double kLambdas[] = {1.0, 7.3};

// Truth: the signature (4,1) of doc/conventions.md#algebra: e1² = e2² = e3² = e² = +1, ē² = −1.
// Products of two basis vectors with one nonzero coefficient are exact, hence tolerance 0.
TEST(MultivectorTest, BasisVectorSquares) {
  const MV basis[] = {MV::e1(), MV::e2(), MV::e3(), MV::e(), MV::ebar()};
  const double squares[] = {+1, +1, +1, +1, -1};
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(maxAbsDiff(basis[i] * basis[i], MV::scalar(squares[i])), 0.0) << "basis " << i;
  }
}

// Truth: distinct orthonormal basis vectors anticommute (e_i e_j = −e_j e_i, i ≠ j), and their
// product is the blade e_i∧e_j with the + sign when i < j. Exact products: tolerance 0.
TEST(MultivectorTest, DistinctBasisVectorsAnticommute) {
  for (unsigned i = 0; i < 5; ++i) {
    for (unsigned j = i + 1; j < 5; ++j) {
      const MV ei = MV::blade(1u << i);
      const MV ej = MV::blade(1u << j);
      EXPECT_EQ(maxAbsDiff(ei * ej, -(ej * ei)), 0.0) << i << ", " << j;
      EXPECT_EQ(maxAbsDiff(ei * ej, MV::blade((1u << i) | (1u << j))), 0.0) << i << ", " << j;
    }
  }
}

// Truth: textbook squares of pseudoscalars. I3² = −1 (Euclidean 3-space). For Cl(p,q) with
// N = p + q, I² = (−1)^(N(N−1)/2) (−1)^q; for Cl(4,1): (+1)(−1) = −1. E = e∧ē squares to +1.
// I3 anticommutes with e and ē (three swaps). All exact: tolerance 0.
TEST(MultivectorTest, PseudoscalarSquares) {
  const MV I5 = MV::blade(31);
  const MV E = (MV::e() ^ MV::ebar());
  EXPECT_EQ(maxAbsDiff(MV::I3() * MV::I3(), MV::scalar(-1.0)), 0.0);
  EXPECT_EQ(maxAbsDiff(I5 * I5, MV::scalar(-1.0)), 0.0);
  EXPECT_EQ(maxAbsDiff(E * E, MV::scalar(1.0)), 0.0);
  EXPECT_EQ(maxAbsDiff(MV::I3() * MV::e(), -(MV::e() * MV::I3())), 0.0);
  EXPECT_EQ(maxAbsDiff(MV::I3() * MV::ebar(), -(MV::ebar() * MV::I3())), 0.0);
}

// Truth: the geometric product is associative. 1000 random triples with coefficients in
// [−1, 1] (seed 1). Both bracketings of the same exact inputs are within chainTol(ρ = 0) of
// the exact product, so they differ by at most twice that.
TEST(MultivectorTest, GeometricProductIsAssociative) {
  std::mt19937 rng(1);
  for (int sample = 0; sample < 1000; ++sample) {
    const MV a = randomMultivector(&rng);
    const MV b = randomMultivector(&rng);
    const MV c = randomMultivector(&rng);
    const double tol = 2 * chainTol({a.norm2(), b.norm2(), c.norm2()}, 0.0);
    ASSERT_LE(maxAbsDiff((a * b) * c, a * (b * c)), tol) << "sample " << sample;
  }
}

// Truth: the outer product is associative and alternating on vectors (a∧a = 0). Tolerance: a
// coefficient of a∧b collects, from at most 6 pairs of grades, a subset of the 32 terms of the
// same coefficient of ab, so it errs by ≤ (32 + 6)ε‖a‖‖b‖ < 2·32ε‖a‖‖b‖ and is itself
// ≤ ‖a‖‖b‖: chainTol's argument holds with its constant doubled, for each of the two sides.
TEST(MultivectorTest, OuterProductIsAssociativeAndAlternating) {
  std::mt19937 rng(2);
  for (int sample = 0; sample < 100; ++sample) {
    const MV a = randomMultivector(&rng);
    const MV b = randomMultivector(&rng);
    const MV c = randomMultivector(&rng);
    const double tol = 2 * 2 * chainTol({a.norm2(), b.norm2(), c.norm2()}, 0.0);
    ASSERT_LE(maxAbsDiff((a ^ b) ^ c, a ^ (b ^ c)), tol) << "sample " << sample;
    const MV v = randomVector(&rng);
    ASSERT_LE(maxAbsDiff(v ^ v, MV()), 2 * chainTol({v.norm2(), v.norm2()}, 0.0)) << sample;
  }
}

// Truth: the null basis of doc/conventions.md#algebra: n² = n̄² = 0, n·n̄ = 2 (Hestenes inner
// product), and E = e∧ē = ½ n̄∧n. Coefficients 0 and ±1: all exact, tolerance 0.
TEST(MultivectorTest, NullBasis) {
  const MV n = MV::n();
  const MV nbar = MV::nbar();
  EXPECT_EQ(maxAbsDiff(n * n, MV()), 0.0);
  EXPECT_EQ(maxAbsDiff(nbar * nbar, MV()), 0.0);
  EXPECT_EQ(maxAbsDiff(inner(n, nbar), MV::scalar(2.0)), 0.0);
  EXPECT_EQ(maxAbsDiff(inner(nbar, n), MV::scalar(2.0)), 0.0);
  EXPECT_EQ(maxAbsDiff((MV::e() ^ MV::ebar()), 0.5 * (nbar ^ n)), 0.0);
}

// Truth: for vectors, a·b = ½(ab + ba) (a scalar, the symmetric bilinear form of the metric)
// and a∧b = ½(ab − ba); the left contraction agrees with the inner product on vectors. Also
// a⌋(b∧c) = (a·b)c − (a·c)b, and for a bivector B: B × a = ½(Ba − aB) = B·a. Random vectors
// (seed 3); each side is a few products of two or three factors: 4·chainTol of a triple.
TEST(MultivectorTest, VectorProductsAreSymmetricAndAntisymmetricParts) {
  std::mt19937 rng(3);
  for (int sample = 0; sample < 100; ++sample) {
    const MV a = randomVector(&rng);
    const MV b = randomVector(&rng);
    const MV c = randomVector(&rng);
    const double tol2 = 4 * chainTol({a.norm2(), b.norm2()}, 0.0);
    const double tol3 = 4 * chainTol({a.norm2(), b.norm2(), c.norm2()}, 0.0);
    const MV dot = 0.5 * (a * b + b * a);
    ASSERT_LE(maxAbsDiff(dot, dot.grade(0)), tol2);
    ASSERT_LE(maxAbsDiff(inner(a, b), dot), tol2);
    ASSERT_LE(maxAbsDiff(leftContract(a, b), dot), tol2);
    ASSERT_LE(maxAbsDiff((a ^ b), 0.5 * (a * b - b * a)), tol2);
    ASSERT_LE(maxAbsDiff(leftContract(a, (b ^ c)), inner(a, b) * c - inner(a, c) * b), tol3);
    const MV B = (b ^ c);
    ASSERT_LE(maxAbsDiff(commutator(B, a), inner(B, a)), tol3);
  }
}

// Truth: the definitions of reverse and grade involution on a basis blade e_i1 e_i2 … e_ik
// (i1 < … < ik): the reverse is the product of the same factors in the opposite order, the
// involution the product of the negated factors. Products of basis vectors are exact: tol 0.
TEST(MultivectorTest, ReverseAndInvolutionOfBasisBlades) {
  for (unsigned mask = 0; mask < MV::kNumBlades; ++mask) {
    MV reversed = MV::scalar(1.0);
    MV involuted = MV::scalar(1.0);
    for (unsigned i = 0; i < 5; ++i) {
      if ((mask >> i) & 1u) {
        reversed = MV::blade(1u << i) * reversed;
        involuted = involuted * -MV::blade(1u << i);
      }
    }
    EXPECT_EQ(maxAbsDiff(MV::blade(mask).reverse(), reversed), 0.0) << MV::blade(mask);
    EXPECT_EQ(maxAbsDiff(MV::blade(mask).gradeInvolution(), involuted), 0.0) << MV::blade(mask);
  }
}

// Truth: the reverse is an anti-automorphism: (ab)~ = b̃ ã; and the grade involution an
// automorphism: (ab)^ = â b̂. Both sides are one product of the same (exactly negated) inputs.
TEST(MultivectorTest, ReverseAndInvolutionOfProducts) {
  std::mt19937 rng(4);
  for (int sample = 0; sample < 100; ++sample) {
    const MV a = randomMultivector(&rng);
    const MV b = randomMultivector(&rng);
    const double tol = 2 * chainTol({a.norm2(), b.norm2()}, 0.0);
    ASSERT_LE(maxAbsDiff((a * b).reverse(), b.reverse() * a.reverse()), tol);
    ASSERT_LE(maxAbsDiff((a * b).gradeInvolution(), a.gradeInvolution() * b.gradeInvolution()),
              tol);
  }
}

// Truth: the grade projections partition the blades, so they sum back to the multivector
// exactly (each coefficient is added to zeros only: tolerance 0), and ⟨A⟩_k holds only grade k.
TEST(MultivectorTest, GradeProjectionsSumBack) {
  std::mt19937 rng(5);
  const MV a = randomMultivector(&rng);
  MV sum;
  for (int k = 0; k <= 5; ++k) {
    const MV ak = a.grade(k);
    for (unsigned mask = 0; mask < MV::kNumBlades; ++mask) {
      if (MV::bladeGrade(mask) != k) {
        EXPECT_EQ(ak[mask], 0.0);
      }
    }
    sum += ak;
  }
  EXPECT_EQ(maxAbsDiff(sum, a), 0.0);
  EXPECT_EQ(a.scalarPart(), a[0]);
  EXPECT_EQ(maxAbsDiff(a.grade(6), MV()), 0.0);
  EXPECT_EQ(maxAbsDiff(a.grade(-1), MV()), 0.0);
}

// Truth: Hestenes' inner product vanishes when either side is a scalar
// (doc/conventions.md#algebra); the left contraction of a scalar s is s·B. Exact (no product is
// formed, or one scalar scaling).
TEST(MultivectorTest, InnerProductWithScalarIsZero) {
  std::mt19937 rng(6);
  const MV a = randomMultivector(&rng);
  const MV s = MV::scalar(2.5);
  EXPECT_EQ(maxAbsDiff(inner(s, a), MV()), 0.0);
  EXPECT_EQ(maxAbsDiff(inner(a, s), MV()), 0.0);
  EXPECT_EQ(maxAbsDiff(leftContract(s, a), 2.5 * a), 0.0);
}

// Truth: doc/conventions.md (E1): X(x)² = 0 and X·n = −1 for every x and λ, and the origin is
// X(0) = −n̄/2.
// Random x in [−3, 3]³ m (seed 7); X² is a product of two inputs: chainTol({‖X‖, ‖X‖}).
TEST(MultivectorTest, PointsAreNullAndNormalised) {
  std::mt19937 rng(7);
  for (double lambda : kLambdas) {
    EXPECT_EQ(maxAbsDiff(point(Eigen::Vector3d::Zero(), lambda), -0.5 * MV::nbar()), 0.0);
    for (int sample = 0; sample < 100; ++sample) {
      const MV X = point(randomPosition(&rng), lambda);
      ASSERT_LE(maxAbsDiff(X * X, MV()), chainTol({X.norm2(), X.norm2()})) << lambda;
      ASSERT_LE(maxAbsDiff(inner(X, MV::n()), MV::scalar(-1.0)),
                chainTol({X.norm2(), MV::n().norm2()}))
          << lambda;
    }
  }
}

// Truth: doc/conventions.md (E2): T(a) X(x) T̃(a) = X(x + a), with x + a computed in Euclidean
// space. Three factors, plus the rounding of the reference point:
// chainTol({T, X, T}) + ρ‖X(x + a)‖.
TEST(MultivectorTest, TranslatorMovesPoints) {
  std::mt19937 rng(8);
  for (double lambda : kLambdas) {
    for (int sample = 0; sample < 100; ++sample) {
      const Eigen::Vector3d x = randomPosition(&rng);
      const Eigen::Vector3d a = randomPosition(&rng);
      const MV T = translator(a, lambda);
      const MV X = point(x, lambda);
      const MV expected = point(x + a, lambda);
      const double tol =
          chainTol({T.norm2(), X.norm2(), T.norm2()}) + kInputRelErr * expected.norm2();
      ASSERT_LE(maxAbsDiff(T * X * T.reverse(), expected), tol) << lambda;
    }
  }
}

// Truth: the sign check of doc/conventions.md (E3): for B = e1e2, R = exp(−θB/2) rotates e1
// towards e2, i.e. about +e3: R e1 R̃ = cos θ e1 + sin θ e2 (and e3 is fixed). Three factors of
// norm ≈ 1, plus an ulp in each of cos θ, sin θ on the reference side.
TEST(MultivectorTest, RotorRotatesE1TowardsE2) {
  const MV B = MV::e1() * MV::e2();
  for (double theta : {0.3, 1.0, 2.5, -0.7}) {
    const MV R = rotor(B, theta);
    const MV expected = std::cos(theta) * MV::e1() + std::sin(theta) * MV::e2();
    const double tol = chainTol({R.norm2(), 1.0, R.norm2()}) + kEps;
    EXPECT_LE(maxAbsDiff(R * MV::e1() * R.reverse(), expected), tol) << theta;
    EXPECT_LE(maxAbsDiff(R * MV::e3() * R.reverse(), MV::e3()), tol) << theta;
    // The same rotation as Eigen's right-handed rotation about +e3.
    const Eigen::Vector3d rotated =
        Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()) * Eigen::Vector3d::UnitX();
    EXPECT_LE(maxAbsDiff(euclidean(rotated), expected), 2 * kEps) << theta;
  }
}

// Truth: doc/conventions.md (E3): R X(x) R̃ = X(R x) for R = exp(−θB/2), B = I3 u; the reference
// rotation is Eigen's AngleAxis(θ, u) (right-handed about u). Random unit u, θ ∈ [−π, π],
// x ∈ [−3, 3]³ m (seed 9). Three factors; the reference point carries its own rounding (ρ) and the
// rotation's few roundings of x (relative ≤ ρ), which reach X amplified by at most 2.3 (‖dX‖/‖X‖
// over |dx|/|x|, maximised over |x|/λ), so we allow 4ρ‖X(Rx)‖.
TEST(MultivectorTest, RotorMapsPoints) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  for (double lambda : kLambdas) {
    for (int sample = 0; sample < 100; ++sample) {
      const Eigen::Vector3d u = randomPosition(&rng).normalized();
      const double theta = angle(rng);
      const Eigen::Vector3d x = randomPosition(&rng);
      const MV R = rotor(planeOf(u), theta);
      const MV X = point(x, lambda);
      const MV expected = point(Eigen::AngleAxisd(theta, u) * x, lambda);
      const double tol =
          chainTol({R.norm2(), X.norm2(), R.norm2()}) + 4 * kInputRelErr * expected.norm2();
      ASSERT_LE(maxAbsDiff(R * X * R.reverse(), expected), tol) << lambda << " " << theta;
      // R is a rotor: R R̃ = 1.
      ASSERT_LE(maxAbsDiff(R * R.reverse(), MV::scalar(1.0)), chainTol({R.norm2(), R.norm2()}));
    }
  }
}

// Truth: doc/conventions.md#translators-and-rotors: motors fix the point at infinity,
// M n M̃ = n, for M = T(a) R. The product (T R) n (T R)~ has five factors T, R, n, R̃, T̃ in the
// chainTol sense.
TEST(MultivectorTest, MotorsFixInfinity) {
  std::mt19937 rng(10);
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  const MV n = MV::n();
  for (double lambda : kLambdas) {
    for (int sample = 0; sample < 100; ++sample) {
      const MV T = translator(randomPosition(&rng), lambda);
      const Eigen::Vector3d u = randomPosition(&rng).normalized();
      const MV R = rotor(planeOf(u), angle(rng));
      const MV M = T * R;
      const double tol = chainTol({T.norm2(), R.norm2(), n.norm2(), R.norm2(), T.norm2()});
      ASSERT_LE(maxAbsDiff(M * n * M.reverse(), n), tol) << lambda;
    }
  }
}

// Truth: the Taylor series of exp (a third opinion) against the closed forms (E2), (E3) of
// doc/conventions.md:
// exp(−θB/2) = cos(θ/2) − sin(θ/2)B for B² = −1, and exp(n a/(2λ)) = 1 + n a/(2λ) since
// (n a)² = 0. Tolerance: seriesTol (round-off and truncation of the series) plus the closed
// form's input rounding.
TEST(MultivectorTest, ExpSeriesMatchesClosedForms) {
  constexpr int kTerms = 30;
  std::mt19937 rng(11);
  for (double theta : {0.1, -0.9, 2.0}) {
    const MV B = planeOf(randomPosition(&rng).normalized());
    const MV arg = -0.5 * theta * B;
    const double tol = seriesTol(arg.norm2(), kTerms) + kInputRelErr;
    EXPECT_LE(maxAbsDiff(expSeries(arg, kTerms), rotor(B, theta)), tol) << theta;
  }
  for (double lambda : kLambdas) {
    const Eigen::Vector3d a = randomPosition(&rng);
    const MV arg = MV::n() * euclidean(a) / (2.0 * lambda);
    const MV T = translator(a, lambda);
    const double tol = seriesTol(arg.norm2(), kTerms) + kInputRelErr * T.norm2();
    EXPECT_LE(maxAbsDiff(expSeries(arg, kTerms), T), tol) << lambda;
  }
  EXPECT_EQ(maxAbsDiff(expSeries(MV::e1(), 0), MV()), 0.0);
}

// Truth: the documented print format (orthonormal names e1..e5, by grade then mask).
TEST(MultivectorTest, StreamOutput) {
  std::ostringstream os;
  os << 1.0 + MV::blade(MV::kE1 | MV::kE, 0.5) - 2.0 * MV::ebar();
  EXPECT_EQ(os.str(), "1 - 2*e5 + 0.5*e1^e4");
  std::ostringstream zero;
  zero << MV();
  EXPECT_EQ(zero.str(), "0");
  std::ostringstream negative;
  negative << -MV::I3();
  EXPECT_EQ(negative.str(), "-1*e1^e2^e3");
}

// Truth: indexing is by bitmask and out-of-range masks are rejected.
TEST(MultivectorTest, IndexingByMask) {
  MV m = MV::vector(1, 2, 3, 4, 5);
  EXPECT_EQ(m[MV::kE1], 1.0);
  EXPECT_EQ(m[MV::kE2], 2.0);
  EXPECT_EQ(m[MV::kE3], 3.0);
  EXPECT_EQ(m[MV::kE], 4.0);
  EXPECT_EQ(m[MV::kEbar], 5.0);
  EXPECT_EQ(basisProductSign(MV::kE2, MV::kE1), -1);
  EXPECT_THROW(m[32] = 1.0, std::out_of_range);
}

}  // namespace multivector_test
}  // namespace cga
}  // namespace cga_rigid_sim
