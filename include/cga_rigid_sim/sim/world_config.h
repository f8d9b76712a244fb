// WorldConfig: the settings a World is created with (the node's parameters ~dt, ~integrator,
// ~world_frame, ~max_force, ~max_impulse, ~relax_inertia, ~threads, ~ground_plane,
// ~contact_mu, ~contact_restitution, the bounds ~max_queued_inputs[_per_body] and
// ~max_active_wrenches[_per_body]), and the fixed limits on inputs.
#pragma once

#include <optional>
#include <string>

#include "cga_rigid_sim/body/inertia.h"
#include "cga_rigid_sim/scene/collision_shape.h"
#include "cga_rigid_sim/scene/self_collision.h"

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

/// Extensions of the contact model beyond Coulomb's law with one μ and Newton's restitution
/// (doc/contact_model.md). Each is off at its default, and then the solve is the plain model's
/// bit for bit.
struct ContactModel {
  /// Static against kinetic friction (Stribeck's curve): a contact slipping at speed v (its
  /// tangential relative velocity before the step's impulses) has the friction coefficient
  ///   μ(v) = μ (1 + (r − 1) exp(−(v / v_s)²)),
  /// μ the surfaces' (kinetic) coefficient, r = static_friction_ratio = μ_s/μ_k ≥ 1 (1: off)
  /// and v_s = stribeck_speed > 0 (m/s) the speed at which friction passes from static to
  /// kinetic.
  double static_friction_ratio = 1.0;
  double stribeck_speed = 0.05;
  /// Rolling and torsional resistance of a contact patch: a contact whose surfaces touch over a
  /// patch rather than a point resists turning about the tangents (rolling, as a pressure
  /// centre moving within the patch, up to its half-width) and about the normal (spinning) by a
  /// couple of at most ρ λ_n, ρ the lever of the patch in m (0: off). Solved with the contact's
  /// friction as MuJoCo's condim 6 rows (doc/contact_model.md).
  double rolling_resistance = 0.0;
  double torsional_resistance = 0.0;
  /// Restitution that falls with the impact speed (Johnson's elastic-plastic impact: the
  /// plastic work grows faster than the kinetic energy, e ∝ v^(−1/4) above the yield speed):
  /// an impact at normal speed v bounces with
  ///   e(v) = min(1, e (v_ref / v)^p),
  /// e the surfaces' coefficient (its value at v_ref), p = restitution_speed_exponent ≥ 0
  /// (0: off; 1/4 Johnson's) and v_ref = restitution_reference_speed > 0 (m/s).
  double restitution_speed_exponent = 0.0;
  double restitution_reference_speed = 1.0;
  /// Rounded edges and corners of boxes against the ground plane: a real box's edges are not
  /// sharp, and it touches the plane with the Minkowski sum of a box smaller by this radius r
  /// (m) on every side and a ball of radius r (capped at half the box's smallest edge). A box
  /// on an edge or a corner then sits lower and rolls over it; a face still lies flat
  /// (0: sharp, off).
  double box_edge_radius = 0.0;
  /// Compliant contact (Hunt and Crossley's law): the surfaces give under load, and a contact
  /// whose points overlap by δ > 0, approaching at δ̇, pushes with the force
  ///   f_n = k δ (1 + d δ̇), never pulling (f_n ≥ 0),
  /// k = normal_stiffness (N/m per contact point; 0: rigid, off) and d = normal_dissipation
  /// (s/m; an impact at speed v keeps e ≈ 1 − (2/3) d v for small d v, doc/contact_model.md). Its
  /// impulse h f_n over the step replaces the rigid contact's (no restitution, no position
  /// correction: the overlap is the deformation); friction stays Coulomb's, within μ h f_n.
  double normal_stiffness = 0.0;
  double normal_dissipation = 0.0;
  /// Tangential restitution at impacts (the tangential compliance of the surfaces, as in
  /// Maw, Barber and Fawcett's and Walton's impact laws): a rigid contact that sticks in an
  /// impact leaves with its slip reversed, u_t⁺ = −e_t u_t⁻, as far as the friction cone
  /// allows; e_t = tangential_restitution in [0, 1] (0: the slip is stopped, off).
  double tangential_restitution = 0.0;
  /// Friction that depends on the contact pressure (polymers, Archard's elastic contact: the
  /// real area grows as N^(2/3), so μ falls as the pressure rises): a face lying on a surface
  /// (three or four coplanar corners between the same bodies) spreads its load over the face
  /// and has the coefficient face_friction_ratio · μ, an edge or a corner, whose load sits on
  /// a small rounded patch, keeps μ (1: off).
  double face_friction_ratio = 1.0;
  /// Friction during impacts (pressure-dependent friction again: an impact's peak contact
  /// pressure is many times a resting one's, and a polymer's μ falls as the pressure rises): a
  /// contact in an impact — approaching faster than the resting threshold and touching within
  /// the step — has the coefficient impact_friction_ratio · μ in that step, and μ again once it
  /// rests or slides on (1: off).
  double impact_friction_ratio = 1.0;
  /// Restitution of a face landing flat: a contact of a face block (three or four coplanar
  /// corners between the same bodies) in an impact bounces with face_restitution_ratio · e, a
  /// corner or an edge landing alone keeps e (1: off). A face meeting a surface flat pushes
  /// the air between them out and rings as a plate; a corner does neither.
  double face_restitution_ratio = 1.0;

  bool compliant() const { return normal_stiffness > 0.0; }
  bool anyOn() const {
    return static_friction_ratio != 1.0 || rolling_resistance != 0.0 ||
           torsional_resistance != 0.0 || restitution_speed_exponent != 0.0 ||
           box_edge_radius != 0.0 || compliant() || tangential_restitution != 0.0 ||
           face_friction_ratio != 1.0 || impact_friction_ratio != 1.0 ||
           face_restitution_ratio != 1.0;
  }
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
  /// Which pairs of one robot's links may collide (the node's ~self_collision;
  /// scene/self_collision.h, doc/contacts.md#self-collision). Links of different robots and
  /// bodies always collide; a link and its parent never do.
  scene::SelfCollisionMode self_collision = scene::SelfCollisionMode::kAuto;
  /// The contact model's extensions (doc/contact_model.md); all off by default.
  ContactModel contact_model;

  /// Bounds on inputs (each ≥ 1), so that no flood of valid inputs grows memory or the cost of
  /// a step without bound (doc/node.md, "Limits and bounds"). Inputs waiting for their step, in all
  /// and per moving body (wrenches and impulses) or per tree (joint efforts): past them an
  /// input is refused when it arrives. 136 bytes each, so the default costs at most 1.4 MB
  /// (twice that reserved, at worst); 1000 per body hold a 1 s trajectory at 1 kHz ahead.
  int max_queued_inputs = 10000;
  int max_queued_inputs_per_body = 1000;
  /// Wrenches and timed joint efforts acting at once, in all and per moving body (per tree for
  /// timed efforts): past them a wrench is refused when it is due to start (so a replay of the
  /// same stamped inputs refuses the same ones). Each active wrench is evaluated at every
  /// (sub)step of its body's integrator, so these bound the cost of a step; the defaults keep it
  /// within a real-time step at dt = 1 ms (what they cost: doc/decisions.md).
  int max_active_wrenches = 1000;
  int max_active_wrenches_per_body = 64;
  /// Curved space (the node's ~curvature; doc/curved_space.md): the radius R, m, of a space of
  /// constant curvature, > 0 the 3-sphere, < 0 hyperbolic space; unset = Euclidean space. The
  /// bodies then move "1 up" (curved/curved_integrator.h) and are reported in the
  /// stereographic chart. Free bodies only, with gravity off; integrators auto, curved2,
  /// curved_exact; wrenches and impulses act 1 up; no contacts, state edits or spawning yet.
  std::optional<double> curvature;
};

}  // namespace sim
}  // namespace cga_rigid_sim
