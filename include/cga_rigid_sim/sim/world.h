// World: owns the bodies of a scene, advances time in fixed steps, applies stamped inputs at
// the step they belong to, and reports momentum and energy. Deterministic: the same scene, the
// same inputs with the same stamps, the same steps give bit-identical states. No ROS.
//
// Time: step k advances t_k = k·dt to t_{k+1}. An input stamped s belongs to the step
// k = floor(s/dt + tiny) (s = 0: the next step); a stamp whose step is already done is refused.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cga_rigid_sim/dynamics/body_state.h"
#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/scene/scene.h"
#include "cga_rigid_sim/sim/inputs.h"

namespace cga_rigid_sim {
namespace sim {

struct WorldConfig {
  double dt = 0.001;               ///< s, > 0
  std::string integrator = "auto";
  std::string world_frame = "world";
  double max_force = 1e6;          ///< N (and N m for couples): larger inputs are refused
  double max_impulse = 1e4;        ///< N s (and N m s)
};

/// Momentum and energy of one body (or of the whole scene, named "total"), world axes.
struct MomentumReport {
  std::string body;
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();          ///< kg m/s
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();         ///< about the CoM, kg m²/s
  Eigen::Vector3d angular_origin = Eigen::Vector3d::Zero();  ///< about the world origin
  double kinetic_energy = 0.0;                               ///< J
  double potential_energy = 0.0;                             ///< J, uniform gravity
};

/// A body's state as users see it (world axes).
struct BodyStateReport {
  std::string name;
  Eigen::Isometry3d pose_root = Eigen::Isometry3d::Identity();  ///< root link frame in world
  Eigen::Vector3d com = Eigen::Vector3d::Zero();                ///< centre of mass, world
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();    ///< of the CoM, world axes
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();   ///< world axes
  dynamics::BodyState state;  ///< motor M_WB and bivelocity Ω_B (blade coefficients)
};

/// A frame to publish: `child` (a link) relative to `parent` (world frame or a root link).
struct FramePose {
  std::string parent;
  std::string child;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

class World {
 public:
  /// Builds the world; refuses an unknown integrator, dt ≤ 0 or not finite, bad limits.
  static Result<std::unique_ptr<World>> create(scene::Scene scene, const WorldConfig& config);
  ~World();

  const WorldConfig& config() const;
  const scene::Scene& scene() const;
  /// Steps done since creation (never goes back, also not on reset).
  std::uint64_t stepCount() const;
  /// Simulation time t = stepCount·dt, s.
  double time() const;

  /// Advances one step: due impulses, then loads (gravity + active wrenches), integrate.
  void step();
  void step(std::uint64_t n);

  /// Validates and queues an input; on refusal nothing is applied and the error names the
  /// field and the rule ("apply_wrench.f.x: not finite", "body 'x': unknown body", …).
  Result<bool> applyWrench(const WrenchInput& in);
  Result<bool> applyImpulse(const ImpulseInput& in);
  /// Ends every active and queued wrench.
  void clearWrenches();
  /// Every body back to its initial state exactly; queued inputs dropped; time runs on.
  void reset();

  Result<BodyStateReport> getBodyState(const std::string& body) const;
  /// Sets pose (root link) and velocities (CoM, world axes) of a moving body.
  Result<bool> setBodyState(const std::string& body, const Eigen::Isometry3d& pose_root,
                            const Eigen::Vector3d& linear_velocity_W,
                            const Eigen::Vector3d& angular_velocity_W);
  /// Adds the bodies of a URDF under `name` (its single free body is renamed `name`), placed
  /// at `pose_root` with the given CoM/angular velocities (world axes).
  Result<bool> spawnUrdf(const std::string& name, const std::string& urdf,
                         const Eigen::Isometry3d& pose_root, const Eigen::Vector3d& linear_W,
                         const Eigen::Vector3d& angular_W);
  Result<bool> deleteBody(const std::string& body);

  /// Per moving body, then the scene total named "total".
  std::vector<MomentumReport> momentum() const;
  /// Every moving body.
  std::vector<BodyStateReport> bodyStates() const;
  /// world_frame → root link of every moving body (changes every step).
  std::vector<FramePose> movingFrames() const;
  /// world_frame → root link of static bodies, and root link → each merged link (constant).
  std::vector<FramePose> staticFrames() const;
  /// Bumped whenever the set of bodies changes (spawn/delete): static frames must be resent.
  std::uint64_t topologyVersion() const;
  /// Integrator path per body, for the summary ("exact-symmetric", …).
  std::string summary() const;

 private:
  World();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sim
}  // namespace cga_rigid_sim
