// Scenes built in code for the World tests (no URDF, so they do not depend on the loader or
// on the example scenes), and bitwise comparisons of states.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "cga_rigid_sim/body/body_state.h"
#include "cga_rigid_sim/body/inertia.h"
#include "cga_rigid_sim/cga/motor.h"
#include "cga_rigid_sim/scene/scene.h"
#include "cga_rigid_sim/sim/world.h"

namespace cga_rigid_sim {
namespace testing {

/// A moving body named `name` whose root link (same name) sits at the CoM with B's axes,
/// principal moments `J` (kg m²) along B's axes, at pose (R, x) with body velocities (w_B, v_B).
inline scene::BodyModel movingBody(const std::string& name, double mass, const Eigen::Vector3d& J,
                                   const Eigen::Quaterniond& R = Eigen::Quaterniond::Identity(),
                                   const Eigen::Vector3d& x = Eigen::Vector3d::Zero(),
                                   const Eigen::Vector3d& w_B = Eigen::Vector3d::Zero(),
                                   const Eigen::Vector3d& v_B = Eigen::Vector3d::Zero(),
                                   double lambda = 1.0) {
  scene::BodyModel b;
  b.name = name;
  b.is_static = false;
  auto I = dynamics::Inertia::fromPrincipal(name, mass, J);
  EXPECT_TRUE(I.ok()) << I.error();
  b.inertia = *I;
  b.links.push_back({name, cga::Motor::identity()});
  b.M_WB0 = cga::Motor::fromPose(R, x, lambda);
  b.omega_B0 = cga::Bivelocity::fromVelocities(w_B, v_B, lambda);
  return b;
}

/// A static body (fixed to the world) whose root link is at (R, x).
inline scene::BodyModel staticBody(const std::string& name,
                                   const Eigen::Quaterniond& R = Eigen::Quaterniond::Identity(),
                                   const Eigen::Vector3d& x = Eigen::Vector3d::Zero(),
                                   double lambda = 1.0) {
  scene::BodyModel b;
  b.name = name;
  b.is_static = true;
  b.links.push_back({name, cga::Motor::identity()});
  b.M_WB0 = cga::Motor::fromPose(R, x, lambda);
  return b;
}

/// n bodies "b0", "b1", … of the three inertia classes in turn (spherical, symmetric,
/// asymmetric), masses 1–3 kg, at random attitudes and positions, tumbling (|w| up to ~8 rad/s,
/// |v| up to ~1.7 m/s) except every `rest_period`-th one from `rest_phase`, which is at rest.
inline std::vector<scene::BodyModel> tumblingBodies(int n, unsigned seed, int rest_period,
                                                    int rest_phase) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Vector3d classes[3] = {{0.2, 0.2, 0.2}, {0.2, 0.2, 0.3}, {0.1, 0.2, 0.25}};
  std::vector<scene::BodyModel> bodies;
  for (int i = 0; i < n; ++i) {
    const bool resting = i % rest_period == rest_phase;
    bodies.push_back(movingBody(
        "b" + std::to_string(i), 1.0 + i % 3, classes[i % 3],
        Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized(), {u(rng), u(rng), u(rng)},
        resting ? Eigen::Vector3d::Zero()
                : Eigen::Vector3d(Eigen::Vector3d(u(rng), u(rng), u(rng)) * 5.0),
        resting ? Eigen::Vector3d::Zero() : Eigen::Vector3d(u(rng), u(rng), u(rng))));
  }
  return bodies;
}

inline scene::Scene makeScene(std::vector<scene::BodyModel> bodies,
                              const Eigen::Vector3d& g_W = Eigen::Vector3d::Zero(),
                              double lambda = 1.0) {
  scene::Scene s;
  s.source = "test";
  s.robot_name = "test";
  s.lambda = lambda;
  s.gravity_W = g_W;
  s.bodies = std::move(bodies);
  return s;
}

inline std::unique_ptr<sim::World> makeWorld(scene::Scene scene, double dt = 1e-3,
                                             const std::string& integrator = "auto") {
  sim::WorldConfig config;
  config.dt = dt;
  config.integrator = integrator;
  auto w = sim::World::create(std::move(scene), config);
  EXPECT_TRUE(w.ok()) << w.error();
  return w.ok() ? std::move(w.value()) : nullptr;
}

/// Every coefficient of the state, bit for bit (memcmp: tells −0 from +0 and NaN payloads).
inline bool bitwiseEqual(const dynamics::BodyState& a, const dynamics::BodyState& b) {
  const auto ma = a.M_WB.coefficients(), mb = b.M_WB.coefficients();
  const auto wa = a.omega_B.coefficients(), wb = b.omega_B.coefficients();
  return std::memcmp(ma.data(), mb.data(), sizeof(double) * ma.size()) == 0 &&
         std::memcmp(wa.data(), wb.data(), sizeof(double) * wa.size()) == 0;
}

/// All moving bodies of two worlds, bit for bit, and the same step count.
inline ::testing::AssertionResult sameStates(const sim::World& a, const sim::World& b) {
  if (a.stepCount() != b.stepCount())
    return ::testing::AssertionFailure() << "step " << a.stepCount() << " vs " << b.stepCount();
  const auto sa = a.bodyStates(), sb = b.bodyStates();
  if (sa.size() != sb.size()) return ::testing::AssertionFailure() << "body count differs";
  for (std::size_t i = 0; i < sa.size(); ++i)
    if (sa[i].name != sb[i].name || !bitwiseEqual(sa[i].state, sb[i].state))
      return ::testing::AssertionFailure() << "body '" << sa[i].name << "' differs";
  return ::testing::AssertionSuccess();
}

inline dynamics::BodyState stateOf(const sim::World& w, const std::string& body) {
  auto r = w.getBodyState(body);
  EXPECT_TRUE(r.ok()) << r.error();
  return r.ok() ? r->state : dynamics::BodyState();
}

/// Momentum report of one body (or "total").
inline sim::MomentumReport momentumOf(const sim::World& w, const std::string& body) {
  for (const auto& m : w.momentum())
    if (m.body == body) return m;
  ADD_FAILURE() << "no momentum for '" << body << "'";
  return {};
}

constexpr double kEps = 2.220446049250313e-16;

}  // namespace testing
}  // namespace cga_rigid_sim
