// The identities of doc/conventions.md that tie the hot-path dynamics to the algebra, checked
// against the 32-blade reference on a body made of point masses (so I(Ω) = λ² Σ m X∧(X·Ω) is
// computed from its definition, third moments and all):
//   - the moment of a force: (M̃ (λ X_c∧F) M)∧n = (x∧f)∧n − (λ/2) n̄∧f∧n = Moment::ofForceAt;
//   - α drops out of it exactly;
//   - I(Ω)∧n = Inertia::apply(Ω) (the 6×6 map: mass and J only);
//   - the equation of motion I(Ω̇)∧n = (Ω×I(Ω))∧n + T with Ω̇ = Inertia::solve(gyroscopic + T),
//     and its Euclidean equivalent J ẇ + w × J w = τ, v̇ = −w × v + f/m;
//   - kinetic energy −½ Ω·I(Ω) = ½ m v² + ½ w·J w.
// Tolerances: sums over 8 particles of reference products (32ε each) of operands of size
// ≤ λ²·m·|x|²·|Ω| ≈ 1e2: 1e-11 absolute is ~4× that bound.
#include <gtest/gtest.h>

#include <vector>

#include "cga_rigid_sim/body/inertia.h"
#include "common/cga_embedding.h"

namespace cga_rigid_sim {
namespace cga_identities_test {

using cga::Bivelocity;
using cga::Moment;
using cga::Multivector;
using testing::pointMV;
using testing::Rng;
using testing::toMV;

struct Particle {
  double m;
  Eigen::Vector3d x;  // body frame B
};

// A random cloud of point masses, shifted so its centre of mass is at the origin and rotated
// onto its principal axes, so its tensor is diagonal in B like the simulator's reference body.
std::vector<Particle> principalCloud(Rng& rng, dynamics::Inertia* inertia) {
  std::vector<Particle> ps(8);
  double mass = 0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (auto& p : ps) {
    p.m = rng.uniform(0.5, 2.0);
    p.x = rng.vec(1.0);
    mass += p.m;
    c += p.m * p.x;
  }
  c /= mass;
  Eigen::Matrix3d J = Eigen::Matrix3d::Zero();
  for (auto& p : ps) {
    p.x -= c;
    J += p.m * (p.x.squaredNorm() * Eigen::Matrix3d::Identity() - p.x * p.x.transpose());
  }
  auto I = dynamics::Inertia::fromTensor("cloud", mass, J);
  EXPECT_TRUE(I.ok()) << I.error();
  const Eigen::Quaterniond R_BF = I->rotationFromPrincipal().conjugate();
  for (auto& p : ps) p.x = R_BF * p.x;
  *inertia = *I;
  return ps;
}

// I(Ω) = λ² Σ m X∧(X·Ω), from the definition.
Multivector inertiaMap(const std::vector<Particle>& ps, const Multivector& Om, double lambda) {
  Multivector sum;
  for (const auto& p : ps) {
    const Multivector X = pointMV(p.x, lambda);
    sum += (lambda * lambda * p.m) * (X ^ cga::inner(X, Om));
  }
  return sum;
}

constexpr double kTol = 1e-11;

TEST(CgaIdentities, MomentOfForceAndAlphaDropsOut) {
  Rng rng(21);
  for (double lambda : {1.0, 7.3})
    for (int i = 0; i < 300; ++i) {
      const cga::Motor M = rng.motor(3.0, lambda);
      const Eigen::Vector3d x_B = rng.vec(1.0), f_W = rng.vec(5.0);
      const Multivector Xc = toMV(M) * pointMV(x_B, lambda) * toMV(M).reverse();
      const Eigen::Vector3d f_B = M.rotation().conjugate() * f_W;
      const Moment expected = Moment::ofForceAt(f_B, x_B, lambda);
      // The closed form (E13) (x∧f)∧n − (λ/2) n̄∧f∧n, written in the reference.
      const Multivector n = Multivector::n(), nbar = Multivector::nbar();
      const Multivector closed = ((testing::euclid(x_B) ^ testing::euclid(f_B)) ^ n) -
                                 (lambda / 2) * ((nbar ^ testing::euclid(f_B)) ^ n);
      ASSERT_LT(cga::maxAbsDiff(closed, toMV(expected)), kTol);
      Multivector T[2];
      const double alphas[2] = {0.0, 1e3};
      for (int k = 0; k < 2; ++k) {
        const Multivector F = toMV(cga::Force(f_W, alphas[k]));
        const Multivector Mspace = lambda * (Xc ^ F);
        T[k] = (toMV(M).reverse() * Mspace * toMV(M)) ^ n;
        ASSERT_LT(cga::maxAbsDiff(T[k], toMV(expected)), kTol * (1 + alphas[k]))
            << "alpha " << alphas[k];
      }
      // α drops out: the two trivectors agree to the rounding of the α-sized terms that cancel.
      ASSERT_LT(cga::maxAbsDiff(T[0], T[1]), kTol * 1e3);
    }
}

TEST(CgaIdentities, InertiaMapEnergyAndEquationOfMotion) {
  Rng rng(22);
  for (double lambda : {1.0, 7.3})
    for (int i = 0; i < 200; ++i) {
      dynamics::Inertia I = *dynamics::Inertia::fromPrincipal("x", 1, {1, 1, 1});
      const auto ps = principalCloud(rng, &I);
      const Eigen::Vector3d w = rng.vec(2.0), v = rng.vec(2.0);
      const Bivelocity Om = Bivelocity::fromVelocities(w, v, lambda);
      const Multivector n = Multivector::n();
      const Multivector IOm = inertiaMap(ps, toMV(Om), lambda);
      // I(Ω)∧n: only mass and J survive.
      ASSERT_LT(cga::maxAbsDiff(IOm ^ n, toMV(I.apply(Om, lambda))), kTol * lambda * lambda);
      // Kinetic energy −½ Ω·I(Ω) = ½ m v² + ½ w·J w (Euclidean, from the particles).
      double T_particles = 0;
      for (const auto& p : ps) T_particles += 0.5 * p.m * (v + w.cross(p.x)).squaredNorm();
      const double T_cga = -0.5 * cga::inner(toMV(Om), IOm).scalarPart();
      ASSERT_NEAR(T_cga, T_particles, kTol * lambda * lambda);
      ASSERT_NEAR(I.kineticEnergy(Om, lambda), T_particles, 1e-12 * (1 + T_particles));
      // Equation of motion with a random body moment T.
      const Moment T(rng.vec(3.0), lambda * rng.vec(3.0));
      const Bivelocity Omdot = I.solve(I.gyroscopic(Om, lambda) + T, lambda);
      const Multivector lhs = inertiaMap(ps, toMV(Omdot), lambda) ^ n;
      const Multivector rhs = (cga::commutator(toMV(Om), IOm) ^ n) + toMV(T);
      ASSERT_LT(cga::maxAbsDiff(lhs, rhs), kTol * lambda * lambda * 10);
      // Euclidean equivalent: J ẇ + w × J w = τ and v̇ = −w × v + f/m.
      const Eigen::Vector3d J = I.principalMoments();
      const Eigen::Vector3d tau = T.torque(), f = T.force(lambda);
      ASSERT_LT((J.cwiseProduct(Omdot.rot) + w.cross(J.cwiseProduct(w)) - tau).norm(), 1e-12 * 50);
      ASSERT_LT((Omdot.linear(lambda) + w.cross(v) - f / I.mass()).norm(), 1e-12 * 50);
    }
}

}  // namespace cga_identities_test
}  // namespace cga_rigid_sim
