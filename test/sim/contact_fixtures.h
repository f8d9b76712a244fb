// Scenes with collision shapes for the contact tests, built in code.
#pragma once

#include <cmath>
#include <optional>

#include "world_fixtures.h"

namespace cga_rigid_sim {
namespace testing {

/// Adds `shape` at B's origin with B's axes (the body's own link), with μ and e unset unless
/// given.
inline scene::BodyModel withShape(scene::BodyModel b, scene::CollisionShape s,
                                  std::optional<double> mu, std::optional<double> e) {
  s.name = b.name + "#" + std::to_string(b.shapes.size());
  s.surface.mu = mu;
  s.surface.restitution = e;
  b.shapes.push_back(s);
  return b;
}

inline scene::BodyModel withBox(scene::BodyModel b, const Eigen::Vector3d& size,
                                std::optional<double> mu = std::nullopt,
                                std::optional<double> e = std::nullopt) {
  scene::CollisionShape s;
  s.kind = scene::CollisionShape::Kind::kBox;
  s.size = size;
  return withShape(std::move(b), s, mu, e);
}

inline scene::BodyModel withSphere(scene::BodyModel b, double radius,
                                   std::optional<double> mu = std::nullopt,
                                   std::optional<double> e = std::nullopt) {
  scene::CollisionShape s;
  s.kind = scene::CollisionShape::Kind::kSphere;
  s.radius = radius;
  return withShape(std::move(b), s, mu, e);
}

/// A solid sphere of mass m, radius r at x with velocities (v, w) in world axes (B = world
/// axes at the start).
inline scene::BodyModel ball(const std::string& name, double m, double r, const Eigen::Vector3d& x,
                             const Eigen::Vector3d& v = {0, 0, 0},
                             const Eigen::Vector3d& w = {0, 0, 0}) {
  const double J = 0.4 * m * r * r;
  return withSphere(movingBody(name, m, {J, J, J}, Eigen::Quaterniond::Identity(), x, w, v), r);
}

/// A solid box of mass m and edges `size` at x, axes along the world's.
inline scene::BodyModel block(const std::string& name, double m, const Eigen::Vector3d& size,
                              const Eigen::Vector3d& x, const Eigen::Vector3d& v = {0, 0, 0},
                              const Eigen::Quaterniond& R = Eigen::Quaterniond::Identity()) {
  const Eigen::Vector3d s2 = size.cwiseProduct(size);
  const Eigen::Vector3d J =
      (m / 12.0) * Eigen::Vector3d(s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y());
  return withBox(movingBody(name, m, J, R, x, Eigen::Vector3d::Zero(), R.conjugate() * v), size);
}

/// A world with a ground plane at z = 0 with (μ, e), default surfaces (μ0, e0).
inline std::unique_ptr<sim::World> contactWorld(scene::Scene scene, double mu, double e,
                                                double dt = 1e-3, bool plane = true) {
  sim::WorldConfig config;
  config.dt = dt;
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
