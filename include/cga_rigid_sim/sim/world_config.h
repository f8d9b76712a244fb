// WorldConfig: the settings a World is created with (the node's parameters ~dt, ~integrator,
// ~world_frame, ~max_force, ~max_impulse, ~relax_inertia), and the fixed limits on inputs.
#pragma once

#include <string>

#include "cga_rigid_sim/dynamics/inertia.h"

namespace cga_rigid_sim {
namespace sim {

/// Stamps and durations farther than this many steps are refused (at dt = 1 ms, 31 000 years);
/// it keeps step numbers well inside the integers a double holds exactly (2^53 ≈ 9e15).
constexpr double kMaxSteps = 1e15;
/// Points of application farther than this from their frame's origin are refused, m: their
/// moments would be round-off.
constexpr double kMaxPointDistance = 1e9;
/// At most this many threads (a sanity bound on ~threads).
constexpr int kMaxThreads = 256;
/// The name of the scene total in momentum().
constexpr const char* kTotalName = "total";

struct WorldConfig {
  double dt = 0.001;  ///< s, > 0
  std::string integrator = "auto";
  std::string world_frame = "world";
  double max_force = 1e6;    ///< N (and N m for couples): larger inputs are refused
  double max_impulse = 1e4;  ///< N s (and N m s)
  /// Threads that integrate the bodies (≥ 1; the node's ~threads). States do not depend on it:
  /// they are bit-identical for any count (sim/worker_pool.h).
  int threads = 1;
  /// For URDFs loaded by spawnUrdf (the node's ~relax_inertia).
  dynamics::TrianglePolicy triangle_policy = dynamics::TrianglePolicy::kRefuse;
};

}  // namespace sim
}  // namespace cga_rigid_sim
