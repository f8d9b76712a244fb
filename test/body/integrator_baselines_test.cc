// Tests of the baselines euler and rk4 (integrator_euler.h, integrator_rk4.h): they are there
// for comparison, so the tests check that they are the methods they claim to be (their order,
// their known failure modes), not that they are good.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "cga_rigid_sim/body/derived.h"
#include "cga_rigid_sim/body/integrator_cga4.h"
#include "cga_rigid_sim/body/integrator_euler.h"
#include "cga_rigid_sim/body/integrator_rk4.h"
#include "common/dynamics_fixtures.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace integrator_baselines_test {

using Eigen::Quaterniond;
using Eigen::Vector3d;
using testing::mixedLoads;
using testing::principal;
using testing::run;
using testing::stateError;

// Truth: cga4 at a step 16× finer than the finest tested (error ≥ 1e4× below the tested ones).
// The error ratio e(h)/e(h/2) of an order-p method tends to 2^p; ±15% at these h (the next term
// is O(h) relative for euler, O(h²)·small for rk4: both below 10% here).
void expectOrder(Integrator& it, const std::vector<double>& hs, double order) {
  const Inertia I = principal(Vector3d(1, 2, 3), 2.0);
  const Loads loads = mixedLoads();
  BodyState s0;
  s0.omega_B = cga::Bivelocity(Vector3d(0.5, 1, 1.5), Vector3d(1, 0, 2));
  const double T = 1.0, h_ref = hs.back() / 16;
  Cga4Integrator reference;
  const BodyState ref = run(reference, I, loads, s0, h_ref, std::lround(T / h_ref));
  std::vector<double> e;
  for (double h : hs) e.push_back(stateError(run(it, I, loads, s0, h, std::lround(T / h)), ref));
  for (size_t i = 0; i + 1 < e.size(); ++i)
    EXPECT_NEAR(e[i] / e[i + 1] / std::pow(2.0, order), 1.0, 0.15)
        << it.name() << " h = " << hs[i] << ": " << e[i] << " / " << e[i + 1];
}

TEST(Baselines, EulerIsFirstOrder) {
  EulerIntegrator euler;
  expectOrder(euler, {4e-3, 2e-3, 1e-3}, 1);
}

TEST(Baselines, Rk4IsFourthOrder) {
  Rk4Integrator rk4;
  expectOrder(rk4, {0.04, 0.02, 0.01}, 4);
}

// Truth: explicit Euler on J ẇ = Jw × w gains energy every step: with a = J⁻¹(Jw × w),
// T(w + h a) = T(w) + h a·Jw + ½ h² a·Ja and a·Jw = (Jw × w)·w = 0, so T grows by ½h² a·Ja > 0
// (the known failure of game engines' explicit integration). Asserted: strictly increasing over
// 1000 steps of a tumbling body.
TEST(Baselines, EulerGainsEnergyEveryStep) {
  const Inertia I = principal(Vector3d(1, 2, 3));
  BodyState s;
  s.omega_B = cga::Bivelocity(Vector3d(0.5, 1, 1.5), Vector3d::Zero());
  EulerIntegrator euler;
  double T = kineticEnergy(I, s, 1.0);
  for (int k = 0; k < 1000; ++k) {
    euler.step(I, Loads(), 1.0, 1e-2, s);
    const double T_next = kineticEnergy(I, s, 1.0);
    ASSERT_GT(T_next, T) << "step " << k;
    T = T_next;
  }
}

// Truth: the parabola x0 + v0 t + g t²/2. RK4 integrates the cubic-free ODE ẍ = g exactly
// (round-off: 1e3 steps, |x| ≈ 10 → bound 1e-12 relative); explicit Euler lags it by exactly
// g h t/2 (x_n = x0 + v0 t + g h² n(n−1)/2), checked to 1e-12 relative.
TEST(Baselines, CentreOfMassUnderGravity) {
  const Inertia I = principal(Vector3d(0.02, 0.03, 0.04), 2.0);
  const Vector3d g(0, 0, -9.81), v0(5, 0, 10);
  Loads loads;
  loads.setGravity(g);
  const double h = 1e-3;
  const long n = 1000;
  const double t = n * h;
  BodyState s0;
  s0.omega_B = cga::Bivelocity(Vector3d(3, 20, -5), v0);  // body = world axes at t = 0
  Rk4Integrator rk4;
  EulerIntegrator euler;
  const Vector3d parabola = v0 * t + 0.5 * t * t * g;
  const BodyState a = run(rk4, I, loads, s0, h, n);
  EXPECT_LE((comPosition_W(a, 1.0) - parabola).norm(), 1e-12 * parabola.norm());
  const BodyState b = run(euler, I, loads, s0, h, n);
  const Vector3d lagging = v0 * t + 0.5 * h * h * n * (n - 1) * g;
  EXPECT_LE((comPosition_W(b, 1.0) - lagging).norm(), 1e-12 * parabola.norm());
  EXPECT_STREQ(rk4.name(), "rk4");
  EXPECT_STREQ(euler.name(), "euler");
}

}  // namespace integrator_baselines_test
}  // namespace dynamics
}  // namespace cga_rigid_sim
