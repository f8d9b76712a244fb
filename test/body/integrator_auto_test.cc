// Tests of `auto` (integrator_auto.h): the path it picks for each inertia class and load
// situation, and that each path is the method it names (compared with that method run alone).
#include "cga_rigid_sim/body/integrator_auto.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "cga_rigid_sim/body/derived.h"
#include "cga_rigid_sim/body/integrator_exact.h"
#include "common/dynamics_fixtures.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace integrator_auto_test {

using Eigen::Quaterniond;
using Eigen::Vector3d;
using testing::principal;

BodyState tumbling() {
  BodyState s;
  s.M_WB = cga::Motor::fromPose(Quaterniond(Eigen::AngleAxisd(0.3, Vector3d(1, 2, 2) / 3.0)),
                                Vector3d(1, -1, 2), 1.0);
  s.omega_B = cga::Bivelocity(Vector3d(0.4, -1.0, 2.0), Vector3d(0.5, 0, 1));
  return s;
}

// Truth: the specification of the paths. A body with no loads and Ω_B = 0 is not stepped (its
// state is left bit for bit, even an unnormalised motor); gravity alone makes it fall.
TEST(AutoIntegrator, BodyAtRestIsNotStepped) {
  AutoIntegrator integ;
  EXPECT_STREQ(integ.path(), "auto");
  const Inertia I = principal(Vector3d(1, 2, 3));
  BodyState s;
  s.M_WB = cga::Motor::fromCoefficients({1.0 + 1e-9, 0.1, 0, 0, 0.2, 0, 0, 0});
  const BodyState s0 = s;
  integ.step(I, Loads(), 1.0, 0.01, s);
  EXPECT_STREQ(integ.path(), "at-rest");
  EXPECT_EQ(s.M_WB.coefficients(), s0.M_WB.coefficients());
  EXPECT_EQ(s.omega_B.coefficients(), s0.omega_B.coefficients());

  Loads gravity;
  gravity.setGravity(Vector3d(0, 0, -9.81));
  BodyState still;
  integ.step(I, gravity, 1.0, 0.1, still);
  EXPECT_STREQ(integ.path(), "exact-asymmetric");
  EXPECT_NEAR(comPosition_W(still, 1.0).z(), -0.5 * 9.81 * 0.01, 1e-15);
}

// Truth: without torque, auto is the exact flow with kicks; it must equal `exact` bit for bit
// (same arithmetic), for each inertia class, free or under gravity, and name the class.
TEST(AutoIntegrator, TorqueFreeBodiesTakeTheExactFlow) {
  struct Case {
    Vector3d J;
    const char* path;
  };
  Loads gravity;
  gravity.setGravity(Vector3d(0, 0, -9.81));
  AppliedLoad through_com;  // a force at the centre of mass exerts no torque
  through_com.F = cga::Force(Vector3d(1, 2, 3));
  gravity.add(through_com);
  for (const Case& c :
       {Case{Vector3d(2, 2, 2), "exact-spherical"}, Case{Vector3d(1, 1, 1.5), "exact-symmetric"},
        Case{Vector3d(1, 2, 3), "exact-asymmetric"}}) {
    for (const Loads& loads : {Loads(), gravity}) {
      SCOPED_TRACE(c.path);
      const Inertia I = principal(c.J);
      AutoIntegrator integ;
      ExactIntegrator exact;
      BodyState a = tumbling(), b = tumbling();
      for (int k = 0; k < 100; ++k) {
        integ.step(I, loads, 1.0, 0.01, a);
        exact.step(I, loads, 1.0, 0.01, b);
      }
      EXPECT_STREQ(integ.path(), c.path);
      EXPECT_EQ(a.M_WB.coefficients(), b.M_WB.coefficients());
      EXPECT_EQ(a.omega_B.coefficients(), b.omega_B.coefficients());
    }
  }
}

// Truth: with a torque, auto is the Strang splitting K(h/2) F(h) K(h/2) of `exact` for every
// inertia class (its choice for asymmetric bodies is documented in the .cc): bit for bit the
// same as `exact`, path "exact+kicks". After the torque goes, the path changes back.
TEST(AutoIntegrator, TorquesTakeTheExactFlowWithKicks) {
  Loads torque;
  AppliedLoad couple;
  couple.couple = Vector3d(0.1, -0.2, 0.3);
  torque.add(couple);
  for (const Vector3d& J : {Vector3d(2, 2, 2), Vector3d(1, 1, 1.5), Vector3d(1, 2, 3)}) {
    const Inertia I = principal(J);
    AutoIntegrator integ;
    ExactIntegrator exact;
    BodyState a = tumbling(), b = tumbling();
    for (int k = 0; k < 100; ++k) {
      integ.step(I, torque, 1.0, 0.01, a);
      exact.step(I, torque, 1.0, 0.01, b);
    }
    EXPECT_STREQ(integ.path(), "exact+kicks");
    EXPECT_EQ(a.M_WB.coefficients(), b.M_WB.coefficients());
    EXPECT_EQ(a.omega_B.coefficients(), b.omega_B.coefficients());
    integ.step(I, Loads(), 1.0, 0.01, a);
    EXPECT_STRNE(integ.path(), "exact+kicks");
  }
}

// Truth: the energy of a free tumbling asymmetric body is constant; auto's path is exact, so
// over 1e4 steps the kinetic energy and world L stay within round-off (1e-13 relative: each
// step's closed form is evaluated from the elapsed time, not compounded).
TEST(AutoIntegrator, FreeTumblingIsExact) {
  const Inertia I = principal(Vector3d(1, 2, 3));
  AutoIntegrator integ;
  BodyState s = tumbling();
  const double T0 = kineticEnergy(I, s, 1.0);
  const Vector3d L0 = angularMomentumCom_W(I, s);
  for (int k = 0; k < 10000; ++k) integ.step(I, Loads(), 1.0, 1e-3, s);
  EXPECT_NEAR(kineticEnergy(I, s, 1.0) / T0, 1.0, 1e-13);
  EXPECT_LE((angularMomentumCom_W(I, s) - L0).norm(), 1e-13 * L0.norm());
  EXPECT_STREQ(integ.name(), "auto");
}

}  // namespace integrator_auto_test
}  // namespace dynamics
}  // namespace cga_rigid_sim
