// Scenes with collision shapes for the contact tests, built in code.
#pragma once

#include <cmath>
#include <optional>

#include "sim/world_fixtures.h"

namespace cga_rigid_sim {
namespace testing {

/// Adds `shape` at B's origin with B's axes (the body's own link), with μ and e unset unless
/// given.
inline scene::BodyModel withShape(scene::BodyModel b, scene::CollisionShape s,
                                  std::optional<double> mu = std::nullopt,
                                  std::optional<double> e = std::nullopt) {
  s.name = b.name + "#" + std::to_string(b.shapes.size());
  s.surface.mu = mu;
  s.surface.restitution = e;
  b.shapes.push_back(s);
  return b;
}

/// A box of edges `size` centred on its frame.
inline scene::CollisionShape boxShape(const Eigen::Vector3d& size) {
  scene::CollisionShape s;
  s.kind = scene::CollisionShape::Kind::kBox;
  s.size = size;
  return s;
}

/// A sphere of radius `radius` centred on its frame.
inline scene::CollisionShape sphereShape(double radius) {
  scene::CollisionShape s;
  s.kind = scene::CollisionShape::Kind::kSphere;
  s.radius = radius;
  return s;
}

/// A solid sphere of mass m, radius r at x with velocities (v, w) in world axes (B = world
/// axes at the start).
inline scene::BodyModel ball(const std::string& name, double m, double r, const Eigen::Vector3d& x,
                             const Eigen::Vector3d& v = {0, 0, 0},
                             const Eigen::Vector3d& w = {0, 0, 0}) {
  const double J = 0.4 * m * r * r;
  return withShape(movingBody(name, m, {J, J, J}, Eigen::Quaterniond::Identity(), x, w, v),
                   sphereShape(r));
}

/// A solid box of mass m and edges `size` at x, axes along the world's.
inline scene::BodyModel block(const std::string& name, double m, const Eigen::Vector3d& size,
                              const Eigen::Vector3d& x, const Eigen::Vector3d& v = {0, 0, 0},
                              const Eigen::Quaterniond& R = Eigen::Quaterniond::Identity()) {
  const Eigen::Vector3d s2 = size.cwiseProduct(size);
  const Eigen::Vector3d J =
      (m / 12.0) * Eigen::Vector3d(s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y());
  return withShape(movingBody(name, m, J, R, x, Eigen::Vector3d::Zero(), R.conjugate() * v),
                   boxShape(size));
}

/// A world with a ground plane at z = 0 with (μ, e), default surfaces (μ0, e0); `sleeping`
/// off solves every step.
inline std::unique_ptr<sim::World> contactWorld(scene::Scene scene, double mu, double e,
                                                double dt = 1e-3, bool plane = true,
                                                bool sleeping = true) {
  sim::WorldConfig config;
  config.dt = dt;
  config.contact_sleeping = sleeping;
  config.contact_mu = mu;
  config.contact_restitution = e;
  if (plane) config.ground_plane = sim::GroundPlane{};
  auto w = sim::World::create(std::move(scene), config);
  EXPECT_TRUE(w.ok()) << w.error();
  return w.ok() ? std::move(w.value()) : nullptr;
}

/// Gravity of magnitude g tilted by θ about the world y axis: on the ground plane it is a slope
/// of angle θ going down towards +x.
inline Eigen::Vector3d slopeGravity(double g, double theta) {
  return {g * std::sin(theta), 0.0, -g * std::cos(theta)};
}

}  // namespace testing
}  // namespace cga_rigid_sim
