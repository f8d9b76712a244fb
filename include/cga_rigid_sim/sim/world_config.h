// WorldConfig: the settings a World is created with (the node's parameters ~dt, ~integrator,
// ~world_frame, ~max_force, ~max_impulse, ~relax_inertia, ~threads, ~ground_plane,
// ~contact_mu, ~contact_restitution, the bounds ~max_queued_inputs[_per_body] and
// ~max_active_wrenches[_per_body]), and the fixed limits on inputs.
#pragma once

#include <optional>
#include <string>

#include "cga_rigid_sim/dynamics/inertia.h"
#include "cga_rigid_sim/scene/collision_shape.h"

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

/// The plane z = height of the world frame, normal +z, an obstacle under every body (the node's
/// ~ground_plane). Its surface parameters, when unset, are the defaults below.
struct GroundPlane {
  double height = 0.0;  ///< m, finite
  scene::SurfaceParameters surface;
};

struct WorldConfig {
  double dt = 0.001;  ///< s, > 0
  std::string integrator = "auto";
  std::string world_frame = "world";
  double max_force = 1e6;    ///< N (and N m for couples): larger inputs are refused
  double max_impulse = 1e4;  ///< N s (and N m s)
  /// Threads that integrate the bodies (≥ 1; the node's ~threads). States do not depend on it:
  /// they are bit-identical for any count (sim/worker_pool.h).
  int threads = 1;
  /// For URDFs loaded by spawnUrdf (the node's ~relax_inertia; scene::SceneOptions).
  dynamics::TrianglePolicy triangle_policy = dynamics::TrianglePolicy::kNearestPhysical;
  /// The ground plane; none when unset.
  std::optional<GroundPlane> ground_plane;
  /// μ and e of every surface that does not set its own (the node's ~contact_mu,
  /// ~contact_restitution): μ finite and ≥ 0, e in [0, 1].
  double contact_mu = 0.5;
  double contact_restitution = 0.0;
  /// Sleeping (doc/contacts.md#sleeping): a group of bodies in contact whose contact points
  /// all stay slower than 1e-6 m/s for 0.2 s is frozen (Ω = 0, not stepped, its contacts kept)
  /// until a state set, an impulse, a wrench, a change of gravity or an awake body touching
  /// it wakes it. false: every body in contact is solved every step.
  bool contact_sleeping = true;

  /// Bounds on inputs (each ≥ 1), so that no flood of valid inputs grows memory or the cost of
  /// a step without bound (README "Limits and bounds"). Inputs waiting for their step, in all
  /// and per moving body (wrenches and impulses) or per tree (joint efforts): past them an
  /// input is refused when it arrives. 136 bytes each, so the default costs at most 1.4 MB
  /// (twice that reserved, at worst); 1000 per body hold a 1 s trajectory at 1 kHz ahead.
  int max_queued_inputs = 10000;
  int max_queued_inputs_per_body = 1000;
  /// Wrenches and timed joint efforts acting at once, in all and per moving body (per tree for
  /// timed efforts): past them a wrench is refused when it is due to start (so a replay of the
  /// same stamped inputs refuses the same ones). Each active wrench is evaluated at every
  /// (sub)step of its body's integrator, ~0.15 µs each: 64 on a body cost ~10 µs a step, 1000
  /// in all ~0.2 ms, a fifth of a real-time step at dt = 1 ms (README "Limits and bounds").
  int max_active_wrenches = 1000;
  int max_active_wrenches_per_body = 64;
  /// Curved space (the node's ~curvature; doc/curved_space.md): the radius R, m, of a space of
  /// constant curvature, > 0 the 3-sphere, < 0 hyperbolic space; unset = Euclidean space. The
  /// bodies then move "1 up" (dynamics/curved_integrator.h) and are reported in the
  /// stereographic chart. Free bodies only, with gravity off; integrators auto, curved2,
  /// curved_exact; no contacts, wrenches, impulses, state edits or spawning yet.
  std::optional<double> curvature;
};

}  // namespace sim
}  // namespace cga_rigid_sim
