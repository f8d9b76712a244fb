// Tests of Loads (loads.h): the body moment of forces and couples fixed in the world or in the
// body, at a pose; gravity; the multiplier α; the predicates the integrators use to skip work.
#include "cga_rigid_sim/body/loads.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "common/cga_embedding.h"
#include "common/dynamics_fixtures.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace loads_test {

using cga::Multivector;
using Eigen::Quaterniond;
using Eigen::Vector3d;
using testing::pointMV;
using testing::toMV;

// The body moment from its definition (doc/conventions.md (E13)), in the reference algebra: the
// force F_W (a CGA force vector in world axes) acts at the world point X_c = M X(p_B) M̃; its
// moment is M_space = λ X_c∧F, back-rotated into the body and wedged with n.
Multivector referenceMoment(const cga::Motor& M, const Vector3d& p_B, const cga::Force& F_W,
                            double lambda) {
  const Multivector Mm = toMV(M), Mr = Mm.reverse();
  const Multivector X_c = Mm * pointMV(p_B, lambda) * Mr;
  const Multivector M_space = lambda * (X_c ^ toMV(F_W));
  return (Mr * M_space * Mm) ^ Multivector::n();
}

// Truth: the reference algebra (above). A world-fixed force keeps its world direction whatever
// the pose, so its body moment changes with the pose; a body-fixed force is R f_B in the world
// and its body moment does not depend on the pose. Reference products of operands of size
// ≤ λ|p||f| ≈ 20: bound 1e-12 absolute (≈ 100 ε·20).
TEST(Loads, WorldAndBodyFixedForcesAgainstTheReferenceAlgebra) {
  testing::Rng rng(17);
  for (int trial = 0; trial < 10; ++trial) {
    const double lambda = trial % 2 ? 1.0 : 7.3;
    const cga::Motor M = rng.motor(3.0, lambda);
    const Quaterniond R = M.rotation();
    const Vector3d p_B = rng.vec(1.0), f = rng.vec(2.0);
    const double alpha = rng.uniform(-5, 5);

    Loads world;
    AppliedLoad w;
    w.axes = Axes::kWorld;
    w.F = cga::Force(f, alpha);
    w.point_B = p_B;
    world.add(w);
    const Multivector expected_world = referenceMoment(M, p_B, cga::Force(f, alpha), lambda);
    EXPECT_LE(cga::maxAbsDiff(toMV(world.appliedMoment_B(M, lambda)), expected_world), 1e-12);

    Loads body;
    AppliedLoad b = w;
    b.axes = Axes::kBody;
    body.add(b);
    const Multivector expected_body = referenceMoment(M, p_B, cga::Force(R * f, alpha), lambda);
    EXPECT_LE(cga::maxAbsDiff(toMV(body.appliedMoment_B(M, lambda)), expected_body), 1e-12);
    // … which is the pose-independent (p_B × f_B, λ f_B).
    const cga::Moment T_body = body.appliedMoment_B(M, lambda);
    EXPECT_LE((T_body.torque() - p_B.cross(f)).norm(), 1e-14);
    EXPECT_LE((T_body.force(lambda) - f).norm(), 1e-14);
  }
}

// Truth: a pure couple fixed in the world is R̃ τ_W in the body; fixed in the body, τ_B. Couples
// exert no force. Gravity's moment is the force m g through the centre of mass: (0, λ m R̃ g).
// One rotation: 1e-15 relative.
TEST(Loads, CouplesAndGravity) {
  const Quaterniond R(Eigen::AngleAxisd(1.1, Vector3d(1, -2, 0.5).normalized()));
  const cga::Motor M = cga::Motor::fromPose(R, Vector3d(4, 5, 6), 2.0);
  const Vector3d tau(0.3, -0.1, 0.7), g(0, 0, -9.81);
  Loads loads;
  AppliedLoad world_couple;
  world_couple.axes = Axes::kWorld;
  world_couple.couple = tau;
  loads.add(world_couple);
  cga::Moment T = loads.appliedMoment_B(M, 2.0);
  EXPECT_LE((T.torque() - R.conjugate() * tau).norm(), 1e-15);
  EXPECT_EQ(T.trans, Vector3d::Zero());

  Loads body_loads;
  AppliedLoad body_couple = world_couple;
  body_couple.axes = Axes::kBody;
  body_loads.add(body_couple);
  EXPECT_EQ(body_loads.appliedMoment_B(M, 2.0).torque(), tau);

  loads.setGravity(g);
  const cga::Moment G = loads.gravityMoment_B(3.0, M, 2.0);
  EXPECT_EQ(G.rot, Vector3d::Zero());
  EXPECT_LE((G.force(2.0) - 3.0 * (R.conjugate() * g)).norm(), 1e-14);
}

// Truth: moment_B, the general evaluation. When every applied load is fixed in the world and
// acts at the centre of mass (or is a couple), worldSums gives m g + Σ f and Σ τ, and the body
// moment is (R̃ Σ τ, λ R̃ (m g + Σ f)): equal to moment_B to the round-off of one rotation of
// vectors of size ~30 (1e-13). A load at another point or fixed in the body: false.
TEST(Loads, WorldSumsAtTheCentre) {
  const Quaterniond R(Eigen::AngleAxisd(0.8, Vector3d(-1, 2, 0.3).normalized()));
  const double lambda = 1.5, m = 2.5;
  const cga::Motor M = cga::Motor::fromPose(R, Vector3d(1, -2, 3), lambda);
  Loads loads;
  loads.setGravity(Vector3d(0, 0, -9.81));
  AppliedLoad push = testing::appliedLoad(Axes::kWorld, Vector3d(3, -1, 2), Vector3d::Zero(),
                                          Vector3d(0.5, 0.25, -1));
  loads.add(push);
  Vector3d f_W, couple_W;
  ASSERT_TRUE(loads.worldSums(m, f_W, couple_W));
  EXPECT_EQ(f_W, m * Vector3d(0, 0, -9.81) + Vector3d(3, -1, 2));
  EXPECT_EQ(couple_W, Vector3d(0.5, 0.25, -1));
  const cga::Moment T = loads.moment_B(m, M, lambda);
  EXPECT_LE((T.rot - R.conjugate() * couple_W).norm(), 1e-13);
  EXPECT_LE((T.trans - lambda * (R.conjugate() * f_W)).norm(), 1e-13);

  Loads off_centre = loads;
  push.point_B = Vector3d(0.1, 0, 0);
  off_centre.add(push);
  EXPECT_FALSE(off_centre.worldSums(m, f_W, couple_W));
  Loads in_body = loads;
  AppliedLoad thruster;
  thruster.axes = Axes::kBody;
  in_body.add(thruster);
  EXPECT_FALSE(in_body.worldSums(m, f_W, couple_W));
}

// Truth: the sums worldSums reads are kept as loads arrive (Loads::add), so clearApplied() must
// start them over: after clearing a body-axes load and an off-centre push, the next step's world
// loads alone make the sums, exactly (two additions to zero, compared bit for bit), and a cleared
// load set with gravity alone gives m g and no couple.
TEST(Loads, ClearAppliedStartsTheWorldSumsOver) {
  const double m = 2.5;
  Loads loads;
  loads.setGravity(Vector3d(0, 0, -9.81));
  AppliedLoad thruster;
  thruster.axes = Axes::kBody;
  thruster.F = cga::Force(Vector3d(7, 0, 0));
  loads.add(thruster);
  AppliedLoad off_centre =
      testing::appliedLoad(Axes::kWorld, Vector3d(1, 2, 3), Vector3d(0.1, 0, 0), Vector3d(4, 5, 6));
  loads.add(off_centre);
  Vector3d f_W, couple_W;
  ASSERT_FALSE(loads.worldSums(m, f_W, couple_W));

  loads.clearApplied();
  ASSERT_TRUE(loads.worldSums(m, f_W, couple_W));
  EXPECT_EQ(f_W, m * Vector3d(0, 0, -9.81));
  EXPECT_EQ(couple_W, Vector3d::Zero());

  const AppliedLoad push = testing::appliedLoad(Axes::kWorld, Vector3d(3, -1, 2), Vector3d::Zero(),
                                                Vector3d(0.5, 0.25, -1));
  loads.add(push);
  ASSERT_TRUE(loads.worldSums(m, f_W, couple_W));
  EXPECT_EQ(f_W, m * Vector3d(0, 0, -9.81) + Vector3d(3, -1, 2));
  EXPECT_EQ(couple_W, Vector3d(0.5, 0.25, -1));
}

// Truth (doc/conventions.md (E12)): α drops out of T = (M̃ λ X∧F M)∧n exactly (λ X∧(αn)∧n = 0), so
// loads that differ only in α give the same moment, bit for bit, and the reference algebra's moment
// of αn alone is zero.
TEST(Loads, AlphaDropsOut) {
  testing::Rng rng(23);
  const cga::Motor M = rng.motor(2.0, 1.5);
  auto moment = [&](double alpha, Axes axes) {
    Loads loads;
    AppliedLoad l;
    l.axes = axes;
    l.F = cga::Force(Vector3d(1, -2, 3), alpha);
    l.point_B = Vector3d(0.2, 0.1, -0.4);
    loads.add(l);
    return loads.appliedMoment_B(M, 1.5);
  };
  for (Axes axes : {Axes::kWorld, Axes::kBody}) {
    EXPECT_EQ(moment(0.0, axes).coefficients(), moment(1e3, axes).coefficients());
    EXPECT_EQ(moment(0.0, axes).coefficients(), moment(-7.5, axes).coefficients());
  }
  const Multivector alpha_only =
      referenceMoment(M, Vector3d(0.2, 0.1, -0.4), cga::Force(Vector3d::Zero(), 1e3), 1.5);
  EXPECT_LE(alpha_only.norm2(), 1e-12);
}

// Truth: the definitions of the predicates. Loads accumulate (the moment of two loads is the sum
// of their moments) and clearApplied() empties the list but keeps gravity.
TEST(Loads, PredicatesAndAccumulation) {
  Loads loads;
  EXPECT_TRUE(loads.empty());
  EXPECT_FALSE(loads.hasGravity());
  EXPECT_FALSE(loads.hasTorque());

  AppliedLoad through_com;  // a force at the centre of mass: no torque
  through_com.F = cga::Force(Vector3d(1, 0, 0));
  loads.add(through_com);
  EXPECT_FALSE(loads.empty());
  EXPECT_TRUE(loads.hasApplied());
  EXPECT_FALSE(loads.hasTorque());

  AppliedLoad off_centre = through_com;
  off_centre.point_B = Vector3d(0, 0.5, 0);
  Loads other;
  other.add(off_centre);
  EXPECT_TRUE(other.hasTorque());
  AppliedLoad couple;
  couple.couple = Vector3d(0, 0, 1e-3);
  Loads coupled;
  coupled.add(couple);
  EXPECT_TRUE(coupled.hasTorque());

  const cga::Motor M = cga::Motor::fromPose(Quaterniond(Eigen::AngleAxisd(0.5, Vector3d::UnitZ())),
                                            Vector3d(1, 2, 3), 1.0);
  Loads both;
  both.add(off_centre);
  both.add(couple);
  const cga::Moment sum = other.appliedMoment_B(M, 1.0) + coupled.appliedMoment_B(M, 1.0);
  const cga::Moment T = both.appliedMoment_B(M, 1.0);
  EXPECT_LE((T.rot - sum.rot).norm(), 1e-15);
  EXPECT_LE((T.trans - sum.trans).norm(), 1e-15);

  both.setGravity(Vector3d(0, 0, -9.81));
  both.clearApplied();
  EXPECT_FALSE(both.hasApplied());
  EXPECT_TRUE(both.hasGravity());
  EXPECT_FALSE(both.empty());
  EXPECT_EQ(both.appliedMoment_B(M, 1.0).coefficients(), cga::Moment().coefficients());
}

}  // namespace loads_test
}  // namespace dynamics
}  // namespace cga_rigid_sim
