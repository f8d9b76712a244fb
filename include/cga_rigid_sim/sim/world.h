// World: owns the bodies of a scene, advances time in fixed steps, applies stamped inputs at
// the step they belong to, and reports momentum and energy. Deterministic: the same scene, the
// same inputs with the same stamps, the same steps give bit-identical states. No ROS.
//
// Time. The world counts steps; t = stepCount·dt (an integer count, so t never drifts). Step k
// advances t_k = k·dt to t_{k+1}. An input stamped s belongs to step k = floor(s/dt + 1e-9)
// (the 1e-9 step absorbs the round-off of stamps that are multiples of dt: 0.3/0.1 is
// 2.9999999999999996); s = 0 means the next step (k = stepCount). A stamp whose step is already
// done (k < stepCount) is refused. Inputs wait in a queue ordered by (step, arrival order), so
// the order they take effect in depends on their stamps and, within one step, on the order
// they arrived — never on wall time.
//
// One step k is a pipeline of stages over the constant Model and the changing Data
// (sim/stages.h, doc/architecture.md): (1) inputs due at k, in (step, arrival) order: impulses
// make Ω_B jump (then the body's integrator is reset), wrenches start; (2) each body's loads
// are gravity plus its active wrenches (summed in the order they started); (3) every moving
// body is integrated over [t_k, t_{k+1}]; (4) wrenches whose last step was k end. Static bodies
// are never stepped. A moving body with no loads and Ω_B = 0 is at rest for every integrator:
// it is skipped (its state is left exactly as it is).
//
// Wrenches (WrenchInput). Given in a link frame (`frame` a link of the body) a wrench is fixed
// in that link and turns with it for its whole duration (a thruster): force, point and couple
// are carried into B once with the link's constant placement M_BL and applied with body axes.
// Given in the world frame (`frame` == config.world_frame, or empty) its force and couple keep
// their world directions, and its point becomes, at the start of its first step, the material
// point of the body that is there; that material point moves with the body. Concurrent
// wrenches on a body add. A wrench lasts n steps: duration d > 0 → n = round(d/dt), halves
// rounding up, with the same 1e-9 step tolerance (n = floor(d/dt + 0.5 + 1e-9); 2.5 steps → 3),
// at least 1; d = 0 → 1 step; d < 0 → until clearWrenches() (or reset()).
//
// Impulses (ImpulseInput) act at the start of the step their stamp falls in, before loads and
// integration: ΔΩ_B = (I∧n)⁻¹ T_imp (doc/conventions.md (E17)). In the world frame the linear
// impulse, its point and the angular impulse are in world axes at that step's pose; in a link
// frame they are in that link's frame (fixed in the body). The pose does not jump.
//
// Validation. Every input is checked completely before anything is queued or changed: on a
// refusal the world is exactly as before. The Error names input, field and rule
// (result.h); its message reads "<input>.<field>: <rule>", e.g.
// "apply_wrench.f.y: not finite (nan)", "apply_wrench.body: body 'table' is static",
// "apply_impulse.frame: frame 'x' is not the world frame 'world' nor a link of body 'b'",
// "apply_wrench.start_time: start stamp 0.5 is already past (sim time 1)". Field names are
// those of inputs.h, with F.f written `f` (wrench) or `J` (impulse) and F.alpha `alpha`.
// Rules: every number finite; |f|, |couple| ≤ max_force; |J|, |angular| ≤ max_impulse;
// |point| ≤ kMaxPointDistance; body known (a body name or any of its links) and moving; frame
// the world frame or a link of that body; stamp not past and at most kMaxSteps steps ahead;
// duration at most kMaxSteps steps.
//
// Performance: moving bodies live in contiguous arrays (Model::moving, Data::bodies: state,
// loads, one integrator object each); step() looks up no string and does not allocate (room
// for loads is reserved when an input arrives).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cga_rigid_sim/body/loads.h"
#include "cga_rigid_sim/contact/contact.h"
#include "cga_rigid_sim/control/joint_trajectory.h"
#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/scene/param_value.h"
#include "cga_rigid_sim/scene/scene.h"
#include "cga_rigid_sim/sim/input/inputs.h"
#include "cga_rigid_sim/sim/reports.h"
#include "cga_rigid_sim/sim/world_config.h"

namespace cga_rigid_sim {
namespace sim {

struct Model;
struct Data;

class World {
 public:
  /// Builds the world; refuses an unknown integrator, dt ≤ 0 or not finite, limits not finite
  /// and > 0, an empty world frame, and a scene that is not consistent (λ ≤ 0, a moving body
  /// without inertia, duplicate body or link names, a link named like the world frame, an
  /// initial state that is not finite). One integrator object is made per moving body.
  static Result<std::unique_ptr<World>> create(scene::Scene scene, const WorldConfig& config);
  ~World();

  const WorldConfig& config() const;
  const scene::Scene& scene() const;
  /// The constant model and the changing data (sim/model.h, sim/data.h), read-only. Like every
  /// report, data() first evaluates the states of coasting bodies (doc/architecture.md#coasting),
  /// which changes nothing but the time it takes. The World is not thread-safe: read it from
  /// the thread that steps it.
  const Model& model() const;
  const Data& data() const;
  /// Steps done since creation (never goes back, also not on reset).
  std::uint64_t stepCount() const;
  /// Simulation time t = stepCount·dt, s.
  double time() const;
  /// Moving body i's state (model().moving[i]) at the current step, a coasting body's evaluated
  /// first: what the sensors read (doc/sensors.md). One body, not data()'s every body.
  const dynamics::BodyState& movingState(int i) const;

  /// Advances one step: the pipeline of stages (sim/stages.h). Allocation-free.
  void step();
  /// n steps.
  void step(std::uint64_t n);

  /// Validates and queues an input; on refusal nothing is applied and the error names the
  /// field and the rule ("apply_wrench.f.x: not finite (nan)", "apply_wrench.body: unknown
  /// body 'x'", …; the list in the file comment). Returns true when queued.
  Result<bool> applyWrench(const WrenchInput& in);
  Result<bool> applyImpulse(const ImpulseInput& in);
  /// Ends every active and queued wrench and timed joint effort now (impulses stay queued;
  /// held joint efforts stay: they are commands, replaced by the next one).
  void clearWrenches();
  /// Every moving body back to its initial state exactly (the scene's, or the placement of
  /// spawnUrdf), integrators reset, active wrenches and queued inputs dropped. The step counter
  /// runs on; spawned bodies stay and deleted ones stay deleted.
  void reset();

  /// The state of a body (its name or any of its links). Static bodies report their fixed
  /// pose and zero velocities.
  Result<BodyStateReport> getBodyState(const std::string& body) const;
  /// Sets pose (root link frame, world) and velocities (CoM velocity and angular velocity,
  /// world axes) of a moving body, effective before the next step:
  /// M_WB = M_WL0 M_BL0⁻¹, Ω_B with body-axis coefficients (R̃ w, R̃ v/λ) (doc/conventions.md
  /// (E6)). Refuses non-finite numbers, a rotation that is not proper, a root link origin
  /// farther than kMaxPointDistance (1e9 m) from the world origin, speeds above 1e9 m/s or
  /// 1e9 rad/s (larger ones overflowed the state), unknown and static bodies. The body's
  /// integrator is reset; its world-frame wrenches keep their material points.
  Result<bool> setBodyState(const std::string& body, const Eigen::Isometry3d& pose_root,
                            const Eigen::Vector3d& linear_velocity_W,
                            const Eigen::Vector3d& angular_velocity_W);
  /// Adds the body of a URDF under `name`, placed at `pose_root` (its root link, world) with
  /// the given CoM/angular velocities (world axes); that placement is its initial state for
  /// reset(). The URDF is loaded with the world's λ, gravity and world frame (source
  /// "spawn_urdf '<name>'") and must hold exactly one body, a moving one. The body and its root
  /// link are renamed `name` (body name = root link name, as for loaded scenes). Refuses an
  /// empty or existing name, a link name the world already has, and what setBodyState refuses.
  /// Bumps topologyVersion().
  ///
  /// A URDF with joints, or any URDF with options.robot_namespace set, is spawned as a robot
  /// called `name` (doc/node.md#spawning-robots): its links and joints named
  /// "<robot_namespace>/<URDF name>", compiled as a scene is, appended after everything the
  /// world has (no index of it changes, nothing it simulates is touched), and its controllers
  /// started from options (loadControllers' rules, names prefixed). pose_root places the URDF's
  /// root link — for a robot fixed to the world (its root link is the world frame), that frame,
  /// and the velocities must then be zero; for a free robot its root body, its links following
  /// at rest in their joints. Also refused, world unchanged: a namespace that is not a ROS name,
  /// a link, joint or controller name the world has, the scene rules of compileModel.
  Result<bool> spawnUrdf(const std::string& name, const std::string& urdf,
                         const Eigen::Isometry3d& pose_root, const Eigen::Vector3d& linear_W,
                         const Eigen::Vector3d& angular_W, const SpawnOptions& options = {});
  /// Removes a body (moving or static, by its name) with its active and queued inputs, or a
  /// spawned robot whole (by its name) with its joints, their inputs and its controllers.
  /// Refuses an unknown name and a body of a tree or of a spawned robot. Bumps
  /// topologyVersion().
  Result<bool> deleteBody(const std::string& body);

  /// Articulated trees (doc/articulated.md). Joint names are the URDF's.
  /// Validates and queues held efforts (JointEffortInput: the rules there).
  Result<bool> setJointEfforts(const JointEffortInput& in);
  /// Validates and queues joint positions and rates set by name (JointStateInput: the rules).
  Result<bool> setJointState(const JointStateInput& in);
  /// Validates and queues a timed effort on one joint.
  Result<bool> applyJointEffort(const TimedJointEffortInput& in);
  /// Every joint of every tree, in scene order (parent first).
  std::vector<JointStateReport> jointStates() const;

  /// Joint controllers in ros_control's vocabulary (doc/control.md). Loads the controllers
  /// `names` (empty: every one) of `controllers` (the YAML's dictionary: controller name → its
  /// type, joints, gains, constraints, …) with gazebo_ros_control's `pid_gains` (joint → p, i,
  /// d, i_clamp; none: stiff defaults, each in a warning). All or nothing; returns the
  /// warnings (keys not read, defaults chosen). Running controllers: data().controllers.
  Result<std::vector<std::string>> loadControllers(const scene::ParamValue& controllers,
                                                   const std::vector<std::string>& names,
                                                   const scene::ParamValue& pid_gains);
  /// A trajectory for a trajectory controller, taking effect at the step of its start_time
  /// (0 or past: the next step), with joint_trajectory_controller's semantics (doc/control.md).
  /// Refused, nothing queued, naming "<controller>/command.<field>" and the rule.
  Result<bool> commandTrajectory(const std::string& controller,
                                 const control::JointTrajectory& trajectory);
  /// A group controller's command (positions, velocities or efforts, one per joint in its
  /// `joints` order), from the next step on.
  Result<bool> commandGroup(const std::string& controller, const std::vector<double>& values);

  /// Per moving body (scene order), then the scene total named "total" (see MomentumReport).
  std::vector<MomentumReport> momentum() const;
  /// Every moving body.
  std::vector<BodyStateReport> bodyStates() const;
  /// Curved space (config.curvature): per moving body (scene order), then the total "total",
  /// the 4-d world momentum and the kinetic energy (conserved); empty in Euclidean space. There
  /// momentum() and bodyStates() read the chart pose and true velocities
  /// (doc/curved_space.md#the-chart), whose Euclidean momenta are not conserved.
  std::vector<CurvedMomentumReport> curvedMomentum() const;
  /// The contacts of the last step (doc/contacts.md).
  std::vector<ContactReport> contacts() const;
  /// The same contacts as the solver keeps them: bodies and shapes by index (contact/contact.h),
  /// no names built. What the sensors read.
  const std::vector<Contact>& lastContacts() const;
  /// The loads that acted on moving body i in the last step: gravity and its applied wrenches
  /// (until clearWrenches(), which drops them at once). What the force-torque sensor subtracts.
  const dynamics::Loads& lastLoads(int i) const;
  /// world_frame → root link of every moving body (changes every step).
  std::vector<FramePose> movingFrames() const;
  /// world_frame → root link of static bodies, and root link → each merged link (constant).
  std::vector<FramePose> staticFrames() const;
  /// Bumped whenever the set of bodies changes (spawn/delete): static frames must be resent.
  std::uint64_t topologyVersion() const;
  /// The self-collision table (doc/contacts.md#self-collision), for the start-up summary: per
  /// robot, how many pairs of its links collide, which, and which are left out and why.
  std::vector<std::string> selfCollisionSummary() const;
  /// Every pair of one robot's bodies that collides, by body name (scene order).
  std::vector<std::pair<std::string, std::string>> selfCollisionPairs() const;
  /// Integrator path per body, for the summary ("exact-symmetric", …; "at-rest" for a body
  /// skipped in the last step).
  std::string summary() const;

  /// Wrenches acting in the next step (already started) and inputs waiting for their step.
  std::size_t activeWrenchCount() const;
  std::size_t queuedInputCount() const;

  /// Wrenches and timed joint efforts refused when they were due to start, because their body
  /// (tree) or the world had as many active as ~max_active_wrenches[_per_body] allow (counted
  /// since creation, reset included), and the reason of the last one: "apply_wrench.body: body
  /// 'box' already has 64 active wrenches at step 12 (max_active_wrenches_per_body = 64)",
  /// or for a timed effort "apply_joint_effort.joint: …".
  std::uint64_t startRefusalCount() const;
  std::optional<Error> lastStartRefusal() const;

  /// Tree steps that left a non-finite state and were undone, the tree set at rest at its pose
  /// before the step (counted since creation, reset included; doc/articulated.md#faults), and
  /// the last one: "step.tree: tree 'base_link': step 1 left a non-finite state; it was undone
  /// and the tree is at rest at its pose before the step (…)".
  std::uint64_t treeFaultCount() const;
  std::optional<Error> lastTreeFault() const;

 private:
  World();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sim
}  // namespace cga_rigid_sim
