// Small fixtures shared by the tests of one body, trees and curved space (test/body, test/tree,
// test/curved): an inertia from principal moments, distances between motors, attitudes and states,
// a fixed mix of loads, and a loop of integrator steps. Helpers whose values differ between test
// files (each file's own loads, state builders) stay in those files.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "cga_rigid_sim/body/body_state.h"
#include "cga_rigid_sim/body/derived.h"
#include "cga_rigid_sim/body/inertia.h"
#include "cga_rigid_sim/body/integrator.h"
#include "cga_rigid_sim/body/loads.h"
#include "cga_rigid_sim/cga/force.h"
#include "cga_rigid_sim/cga/motor.h"

namespace cga_rigid_sim {
namespace testing {

/// A body named "body" of mass `mass` (kg) with principal moments `J` (kg m²) along B's axes.
inline dynamics::Inertia principal(const Eigen::Vector3d& J, double mass = 1.0) {
  auto I = dynamics::Inertia::fromPrincipal("body", mass, J);
  EXPECT_TRUE(I.ok()) << I.error();
  return *I;
}

/// The largest difference of the eight motor coefficients.
inline double maxDiff(const cga::Motor& a, const cga::Motor& b) {
  const auto ca = a.coefficients(), cb = b.coefficients();
  double d = 0.0;
  for (int i = 0; i < 8; ++i) d = std::max(d, std::abs(ca[i] - cb[i]));
  return d;
}

/// Rotation angle between two attitudes, up to the double cover (atan2: full precision near 0).
inline double orientationError(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const Eigen::Quaterniond d = a.conjugate() * b;
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

/// A combined state error: attitude angle, and the differences of w, x and v (SI units).
inline double stateError(const dynamics::BodyState& s, const dynamics::BodyState& ref,
                         double lambda = 1.0) {
  return orientationError(s.M_WB.rotation(), ref.M_WB.rotation()) +
         (s.omega_B.rot - ref.omega_B.rot).norm() +
         (dynamics::comPosition_W(s, lambda) - dynamics::comPosition_W(ref, lambda)).norm() +
         (dynamics::comVelocity_W(s, lambda) - dynamics::comVelocity_W(ref, lambda)).norm();
}

/// A force f at the material point p_B (B frame) and a couple, fixed in `axes`.
inline dynamics::AppliedLoad appliedLoad(dynamics::Axes axes, const Eigen::Vector3d& f,
                                         const Eigen::Vector3d& p_B = Eigen::Vector3d::Zero(),
                                         const Eigen::Vector3d& couple = Eigen::Vector3d::Zero()) {
  dynamics::AppliedLoad load;
  load.axes = axes;
  load.F = cga::Force(f);
  load.point_B = p_B;
  load.couple = couple;
  return load;
}

/// Gravity, a world-fixed couple and a body-fixed force off the centre of mass.
inline dynamics::Loads mixedLoads() {
  dynamics::Loads loads;
  loads.setGravity(Eigen::Vector3d(0, 0, -9.81));
  dynamics::AppliedLoad couple;
  couple.axes = dynamics::Axes::kWorld;
  couple.couple = Eigen::Vector3d(0.1, -0.2, 0.3);
  loads.add(couple);
  dynamics::AppliedLoad thruster;
  thruster.axes = dynamics::Axes::kBody;
  thruster.F = cga::Force(Eigen::Vector3d(0.5, 0.2, -0.3));
  thruster.point_B = Eigen::Vector3d(0.1, -0.2, 0.05);
  loads.add(thruster);
  return loads;
}

/// The state after n steps of h from s.
inline dynamics::BodyState run(dynamics::Integrator& it, const dynamics::Inertia& I,
                               const dynamics::Loads& loads, dynamics::BodyState s, double h,
                               long n, double lambda = 1.0) {
  for (long k = 0; k < n; ++k) it.step(I, loads, lambda, h, s);
  return s;
}

/// The benchmark's spinning projectile (bench/cases/cases.h: m = 2 kg, J = (0.02, 0.03, 0.04),
/// w = (3, 20, −5) rad/s, v = (5, 0, 10) m/s, g = 9.81 m/s² down) stepped n times by h: its end
/// state, the centre of mass's distance from the exact parabola x0 + v0 t + ½ g t², and the
/// round-off of a random walk √n u |x(t)| (u = ε/2) the benchmark's T5 measures it against.
struct ParabolaRun {
  dynamics::BodyState end;
  double com_error;
  double random_walk;
};
inline ParabolaRun spinningProjectileOnParabola(dynamics::Integrator& it, double h, long n) {
  const dynamics::Inertia I = principal(Eigen::Vector3d(0.02, 0.03, 0.04), 2.0);
  dynamics::BodyState s;
  s.omega_B = cga::Bivelocity(Eigen::Vector3d(3, 20, -5), Eigen::Vector3d(5, 0, 10));
  const Eigen::Vector3d g(0, 0, -9.81), x0 = dynamics::comPosition_W(s, 1.0),
                                        v0 = dynamics::comVelocity_W(s, 1.0);
  dynamics::Loads loads;
  loads.setGravity(g);
  for (long k = 0; k < n; ++k) it.step(I, loads, 1.0, h, s);
  const double t = n * h;
  const Eigen::Vector3d x = x0 + t * v0 + (0.5 * t * t) * g;
  const double u = 0.5 * std::numeric_limits<double>::epsilon();
  return {s, (dynamics::comPosition_W(s, 1.0) - x).norm(), std::sqrt(double(n)) * u * x.norm()};
}

}  // namespace testing
}  // namespace cga_rigid_sim
