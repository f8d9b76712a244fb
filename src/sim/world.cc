#include "cga_rigid_sim/sim/world.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>
#include <utility>

#include "cga_rigid_sim/dynamics/derived.h"
#include "cga_rigid_sim/dynamics/impulse.h"
#include "cga_rigid_sim/dynamics/integrator.h"
#include "cga_rigid_sim/dynamics/loads.h"
#include "cga_rigid_sim/scene/scene.h"
#include "cga_rigid_sim/scene/urdf_loader.h"
#include "cga_rigid_sim/sim/input_queue.h"

namespace cga_rigid_sim {
namespace sim {

namespace {

// Stamps and durations within this many steps of a step boundary count as on it: it absorbs
// the round-off of s/dt for stamps that are multiples of dt (a few ulps of s/dt ≤ kMaxSteps,
// i.e. ≤ 1e15 · 2.2e-16 ≈ 0.2 steps at the very end of the range, ~1e-13 for hours at 1 ms).
constexpr double kStepTolerance = 1e-9;

std::string num(double x) {
  std::ostringstream os;
  os.precision(15);
  os << x;
  return os.str();
}

Error fail(const std::string& where, const std::string& rule) { return Error{where + ": " + rule}; }

// "<input>.<field>.x: not finite (nan)" for the first non-finite component, or nothing.
std::optional<Error> checkFinite(const std::string& input, const char* field,
                                 const Eigen::Vector3d& v) {
  static const char* const kAxes[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(v[i]))
      return fail(input + "." + field + "." + kAxes[i], "not finite (" + num(v[i]) + ")");
  return std::nullopt;
}
std::optional<Error> checkFinite(const std::string& input, const char* field, double x) {
  if (!std::isfinite(x)) return fail(input + "." + field, "not finite (" + num(x) + ")");
  return std::nullopt;
}
std::optional<Error> checkMagnitude(const std::string& input, const char* field,
                                    const Eigen::Vector3d& v, double limit, const char* limit_name,
                                    const char* unit) {
  const double m = v.norm();
  if (m > limit)
    return fail(input + "." + field, "|" + std::string(field) + "| = " + num(m) + " " + unit +
                                         " exceeds " + limit_name + " = " + num(limit) + " " +
                                         unit);
  return std::nullopt;
}

// A pose: finite, and its rotation proper (RᵀR = I within kRotationTolerance, det R > 0).
std::optional<Error> checkPose(const std::string& input, const Eigen::Isometry3d& pose) {
  if (auto e = checkFinite(input, "pose.translation", Eigen::Vector3d(pose.translation())))
    return e;
  const Eigen::Matrix3d R = pose.linear();
  if (!R.allFinite()) return fail(input + ".pose.rotation", "not finite");
  const double orth = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  const double det = R.determinant();
  if (!(orth <= kRotationTolerance) || !(det > 0))
    return fail(input + ".pose.rotation", "not a proper rotation (max |R^T R - I| = " + num(orth) +
                                              ", det R = " + num(det) + "; allowed " +
                                              num(kRotationTolerance) + ", det > 0)");
  return std::nullopt;
}

// The state of a body placed with its root link at pose_root and the given CoM and angular
// velocities (world axes): M_WB = M_WL0 M_BL0⁻¹ (the root link's frame sits at M_BL0 in B),
// Ω_B = R̃ w + (1/λ)(R̃ v)∧n.
dynamics::BodyState placedState(const cga::Motor& M_BL0, const Eigen::Isometry3d& pose_root,
                                const Eigen::Vector3d& v_W, const Eigen::Vector3d& w_W,
                                double lambda) {
  const Eigen::Quaterniond R_WL(Eigen::Quaterniond(pose_root.linear()).normalized());
  const cga::Motor M_WL0 = cga::Motor::fromPose(R_WL, pose_root.translation(), lambda);
  dynamics::BodyState s;
  s.M_WB = (M_WL0 * M_BL0.reverse()).normalized();  // a unit motor to round-off
  const Eigen::Quaterniond R_BW = s.M_WB.rotation().conjugate();
  s.omega_B = cga::Bivelocity::fromVelocities(R_BW * w_W, R_BW * v_W, lambda);
  return s;
}

// Makes room for n applied loads without changing the list (Loads has no reserve; step() must
// not allocate when wrenches start).
void reserveApplied(dynamics::Loads& loads, std::size_t n) {
  if (loads.applied().capacity() >= n) return;
  const std::vector<dynamics::AppliedLoad> keep = loads.applied();
  loads.clearApplied();
  for (std::size_t i = 0; i < n; ++i) loads.add(dynamics::AppliedLoad());
  loads.clearApplied();
  for (const auto& l : keep) loads.add(l);
}

bool isZero(const cga::Bivelocity& w) { return w.rot.isZero(0.0) && w.trans.isZero(0.0); }

}  // namespace

// A wrench that has started: its load (point in B) and the first step it no longer acts in.
struct ActiveWrench {
  int body = -1;
  std::uint64_t end_step = kUntilCleared;
  dynamics::AppliedLoad load;
};

struct World::Impl {
  WorldConfig config;
  scene::Scene scene;
  double lambda = 1.0;
  std::uint64_t step_count = 0;
  std::uint64_t topology_version = 0;

  // Moving bodies, contiguous, in scene order. Index i here is the "moving index".
  std::vector<int> scene_index;  // moving index → index in scene.bodies
  std::vector<dynamics::Inertia> inertia;
  std::vector<dynamics::BodyState> state;
  std::vector<dynamics::BodyState> initial;
  std::vector<std::unique_ptr<dynamics::Integrator>> integrator;
  std::vector<dynamics::Loads> loads;
  std::vector<std::uint8_t> loads_dirty;  // its set of active wrenches changed this step
  std::vector<int> dirty_list;            // the bodies flagged in loads_dirty
  enum LastPath : std::uint8_t { kNotStepped, kStepped, kAtRest };
  std::vector<std::uint8_t> last_path;  // what the last step did with the body (summary)

  // Lookups for inputs (never used in step()). Values are scene indices.
  std::vector<int> moving_of_scene;                       // scene index → moving index or −1
  std::map<std::string, int> body_by_name;                // body name → scene index
  std::map<std::string, std::pair<int, int>> link_owner;  // link → (scene index, link index)

  InputQueue queue;
  std::vector<ActiveWrench> active;  // in the order they started
  std::uint64_t next_expiry = kUntilCleared;

  // --- bodies ---------------------------------------------------------------------------

  Result<bool> addMovingArrays(int j, const dynamics::BodyState& s0) {
    auto integ = dynamics::makeIntegrator(config.integrator);
    if (!integ) return fail("config.integrator", integ.error());
    scene_index.push_back(j);
    inertia.push_back(*scene.bodies[j].inertia);
    state.push_back(s0);
    initial.push_back(s0);
    integrator.push_back(std::move(integ.value()));
    dynamics::Loads l;
    l.setGravity(scene.gravity_W);
    loads.push_back(std::move(l));
    loads_dirty.push_back(0);
    last_path.push_back(kNotStepped);
    dirty_list.reserve(state.size());
    return true;
  }

  void addNames(int j) {
    const scene::BodyModel& b = scene.bodies[j];
    body_by_name[b.name] = j;
    for (int li = 0; li < static_cast<int>(b.links.size()); ++li)
      link_owner[b.links[li].link] = {j, li};
  }

  // The scene index of a body given by its name or, failing that, by any of its links.
  int resolveBody(const std::string& name) const {
    const auto b = body_by_name.find(name);
    if (b != body_by_name.end()) return b->second;
    const auto l = link_owner.find(name);
    return l != link_owner.end() ? l->second.first : -1;
  }

  // Moving index of an input's target, or the refusal.
  Result<int> movingTarget(const std::string& input, const std::string& name,
                           bool allow_links = true) const {
    const int j = allow_links ? resolveBody(name) : [&] {
      const auto b = body_by_name.find(name);
      return b == body_by_name.end() ? -1 : b->second;
    }();
    if (j < 0) return fail(input + ".body", "unknown body '" + name + "'");
    const int i = moving_of_scene[j];
    if (i < 0)
      return fail(input + ".body",
                  "body '" + scene.bodies[j].name + "' is static (static bodies never move)");
    return i;
  }

  // The link index of `frame` in moving body i, or −1 for the world frame, or the refusal.
  Result<int> frameOf(const std::string& input, const std::string& frame, int i) const {
    if (frame.empty() || frame == config.world_frame) return -1;
    const int j = scene_index[i];
    const auto l = link_owner.find(frame);
    if (l == link_owner.end() || l->second.first != j)
      return fail(input + ".frame", "frame '" + frame + "' is not the world frame '" +
                                        config.world_frame + "' nor a link of body '" +
                                        scene.bodies[j].name + "'");
    return l->second.second;
  }

  // An input's directions and point, as queued: in world axes (frame < 0), or carried once from
  // link L's frame into B with the constant placement M_BL — fixed in the link, it turns with it.
  QueuedInput placed(QueuedInput::Kind kind, std::uint64_t step, int i, int frame,
                     const cga::Force& F, const Eigen::Vector3d& point,
                     const Eigen::Vector3d& couple) const {
    QueuedInput q;
    q.kind = kind;
    q.step = step;
    q.body = i;
    if (frame < 0) {
      q.axes = dynamics::Axes::kWorld;
      q.F = F;
      q.point = point;
      q.couple = couple;
    } else {
      const cga::Motor& M_BL = scene.bodies[scene_index[i]].links[frame].M_BL;
      q.axes = dynamics::Axes::kBody;
      q.F = M_BL.apply(F, lambda);
      q.point = M_BL.transformPoint(point, lambda);
      q.couple = M_BL.transformVector(couple);
    }
    return q;
  }

  // The step an input stamped s belongs to, or the refusal.
  Result<std::uint64_t> stepOf(const std::string& input, double s) const {
    if (s == 0.0) return step_count;
    const double q = s / config.dt + kStepTolerance;
    if (q > kMaxSteps)
      return fail(input + ".start_time", "start stamp " + num(s) + " is too far ahead (more than " +
                                             num(kMaxSteps) + " steps of " + num(config.dt) +
                                             " s)");
    const double k = std::floor(q);
    if (k < 0 || static_cast<std::uint64_t>(k) < step_count)
      return fail(input + ".start_time",
                  "start stamp " + num(s) + " is already past (sim time " + num(time()) + ")");
    return static_cast<std::uint64_t>(k);
  }

  double time() const { return static_cast<double>(step_count) * config.dt; }

  // --- step --------------------------------------------------------------------------------

  void markDirty(int i) {
    if (!loads_dirty[i]) {
      loads_dirty[i] = 1;
      dirty_list.push_back(i);  // capacity reserved: one slot per body
    }
  }

  void applyImpulseNow(const QueuedInput& in) {
    dynamics::BodyState& s = state[in.body];
    const cga::Moment T_imp_B =
        in.axes == dynamics::Axes::kWorld
            ? dynamics::impulseMoment_B(s, in.F, in.point, in.couple, lambda)
            : cga::Moment::ofForceAt(in.F.f, in.point, lambda) + cga::Moment::couple(in.couple);
    dynamics::applyImpulse(inertia[in.body], T_imp_B, lambda, s);
    integrator[in.body]->reset();
  }

  void startWrench(const QueuedInput& in, std::uint64_t k) {
    ActiveWrench a;
    a.body = in.body;
    a.end_step = in.steps == 0 ? kUntilCleared : k + in.steps;
    a.load.axes = in.axes;
    a.load.F = in.F;
    a.load.couple = in.couple;
    if (in.axes == dynamics::Axes::kWorld) {
      // The material point at the world point now: x_B = R̃ (p_W − x_c).
      const cga::Motor& M = state[in.body].M_WB;
      a.load.point_B = M.rotation().conjugate() * (in.point - M.translation(lambda));
    } else {
      a.load.point_B = in.point;
    }
    active.push_back(a);  // capacity reserved when the input arrived
    next_expiry = std::min(next_expiry, a.end_step);
    markDirty(in.body);
  }

  // Ends the wrenches whose last step was k − 1 (end_step ≤ k), keeping the others in order.
  void expireWrenches(std::uint64_t k) {
    std::size_t out = 0;
    next_expiry = kUntilCleared;
    for (std::size_t a = 0; a < active.size(); ++a) {
      if (active[a].end_step <= k) {
        markDirty(active[a].body);
        continue;
      }
      next_expiry = std::min(next_expiry, active[a].end_step);
      if (out != a) active[out] = active[a];
      ++out;
    }
    active.resize(out);  // shrinking never allocates
  }

  // Rebuilds the applied loads of the bodies whose wrenches changed, summing in start order.
  void rebuildDirtyLoads() {
    if (dirty_list.empty()) return;
    for (int i : dirty_list) loads[i].clearApplied();
    for (const auto& a : active)
      if (loads_dirty[a.body]) loads[a.body].add(a.load);  // room reserved on arrival
    for (int i : dirty_list) loads_dirty[i] = 0;
    dirty_list.clear();
  }

  void dropWrenchLoads() {
    for (const auto& a : active) loads[a.body].clearApplied();
    active.clear();
    next_expiry = kUntilCleared;
  }

  // --- reports -----------------------------------------------------------------------------

  BodyStateReport report(int j) const {
    const scene::BodyModel& b = scene.bodies[j];
    const int i = moving_of_scene[j];
    BodyStateReport r;
    r.name = b.name;
    if (i >= 0) {
      r.state = state[i];
    } else {
      r.state.M_WB = b.M_WB0;  // static: fixed pose, no velocity
    }
    r.pose_root = (r.state.M_WB * b.links.front().M_BL).toIsometry(lambda);
    r.com = dynamics::comPosition_W(r.state, lambda);
    r.linear_velocity = dynamics::comVelocity_W(r.state, lambda);
    r.angular_velocity = dynamics::angularVelocity_W(r.state);
    return r;
  }
};

World::World() : impl_(std::make_unique<Impl>()) {}
World::~World() = default;

Result<std::unique_ptr<World>> World::create(scene::Scene scene, const WorldConfig& config) {
  if (!std::isfinite(config.dt) || !(config.dt > 0))
    return fail("config.dt", "must be finite and > 0 (got " + num(config.dt) + ")");
  if (!std::isfinite(config.max_force) || !(config.max_force > 0))
    return fail("config.max_force", "must be finite and > 0 (got " + num(config.max_force) + ")");
  if (!std::isfinite(config.max_impulse) || !(config.max_impulse > 0))
    return fail("config.max_impulse",
                "must be finite and > 0 (got " + num(config.max_impulse) + ")");
  if (config.world_frame.empty()) return fail("config.world_frame", "must not be empty");
  {
    // Refuse an unknown integrator even when there is no moving body.
    auto integ = dynamics::makeIntegrator(config.integrator);
    if (!integ) return fail("config.integrator", integ.error());
  }
  if (!std::isfinite(scene.lambda) || !(scene.lambda > 0))
    return fail("scene.lambda", "must be finite and > 0 (got " + num(scene.lambda) + ")");
  if (auto e = checkFinite("scene", "gravity_W", scene.gravity_W)) return *e;

  std::unique_ptr<World> world(new World());
  Impl& w = *world->impl_;
  w.config = config;
  w.lambda = scene.lambda;
  w.scene = std::move(scene);

  const int n = static_cast<int>(w.scene.bodies.size());
  w.moving_of_scene.assign(n, -1);
  for (int j = 0; j < n; ++j) {
    const scene::BodyModel& b = w.scene.bodies[j];
    const std::string where = "scene.body '" + b.name + "'";
    if (b.name.empty()) return fail("scene.body " + std::to_string(j), "has no name");
    if (w.body_by_name.count(b.name)) return fail(where, "name used twice");
    if (b.links.empty()) return fail(where, "has no link");
    for (const auto& l : b.links) {
      if (l.link == w.config.world_frame)
        return fail(where, "link '" + l.link + "' has the name of the world frame");
      if (w.link_owner.count(l.link)) return fail(where, "link '" + l.link + "' used twice");
      if (!l.M_BL.allFinite()) return fail(where, "link '" + l.link + "': M_BL not finite");
      w.link_owner[l.link] = {j, 0};  // link index set by addNames below
    }
    if (!b.M_WB0.allFinite()) return fail(where, "initial pose not finite");
    w.body_by_name[b.name] = j;
    if (b.is_static) continue;
    if (!b.inertia) return fail(where, "moving body without inertia");
    if (!b.omega_B0.allFinite()) return fail(where, "initial velocity not finite");
    w.moving_of_scene[j] = static_cast<int>(w.state.size());
    auto added = w.addMovingArrays(j, dynamics::BodyState{b.M_WB0, b.omega_B0});
    if (!added) return Error{added.error()};
  }
  for (int j = 0; j < n; ++j) w.addNames(j);
  return world;
}

const WorldConfig& World::config() const { return impl_->config; }
const scene::Scene& World::scene() const { return impl_->scene; }
std::uint64_t World::stepCount() const { return impl_->step_count; }
double World::time() const { return impl_->time(); }
std::uint64_t World::topologyVersion() const { return impl_->topology_version; }
std::size_t World::activeWrenchCount() const { return impl_->active.size(); }
std::size_t World::queuedInputCount() const { return impl_->queue.size(); }

void World::step() {
  Impl& w = *impl_;
  const std::uint64_t k = w.step_count;
  // (1) Inputs due at step k, in (step, arrival) order.
  while (const QueuedInput* in = w.queue.popDue(k)) {
    if (in->kind == QueuedInput::Kind::kImpulse) {
      w.applyImpulseNow(*in);
    } else {
      w.startWrench(*in, k);
    }
  }
  // (2) Loads: gravity (set once) plus the active wrenches of bodies whose set changed.
  w.rebuildDirtyLoads();
  // (3) Integrate every moving body over [t_k, t_k + dt]. With no load and Ω_B = 0 a body is
  // at rest under every integrator (the exact solution is M(t) = M): skip it.
  const double h = w.config.dt, lambda = w.lambda;
  const std::size_t n = w.state.size();
  for (std::size_t i = 0; i < n; ++i) {
    dynamics::BodyState& s = w.state[i];
    const dynamics::Loads& l = w.loads[i];
    const bool rest = l.empty() && isZero(s.omega_B);
    w.last_path[i] = rest ? Impl::kAtRest : Impl::kStepped;
    if (rest) continue;
    w.integrator[i]->step(w.inertia[i], l, lambda, h, s);
  }
  ++w.step_count;
  // (4) Wrenches whose last step was k end (their loads are dropped before the next step).
  if (w.step_count >= w.next_expiry) w.expireWrenches(w.step_count);
}

void World::step(std::uint64_t n) {
  for (std::uint64_t i = 0; i < n; ++i) step();
}

Result<bool> World::applyWrench(const WrenchInput& in) {
  Impl& w = *impl_;
  const std::string what = "apply_wrench";
  // Numbers: finite, within the limits.
  if (auto e = checkFinite(what, "f", in.F.f)) return *e;
  if (auto e = checkFinite(what, "alpha", in.F.alpha)) return *e;
  if (auto e = checkFinite(what, "point", in.point)) return *e;
  if (auto e = checkFinite(what, "couple", in.couple)) return *e;
  if (auto e = checkFinite(what, "start_time", in.start_time)) return *e;
  if (auto e = checkFinite(what, "duration", in.duration)) return *e;
  if (auto e = checkMagnitude(what, "f", in.F.f, w.config.max_force, "max_force", "N")) return *e;
  if (auto e = checkMagnitude(what, "couple", in.couple, w.config.max_force, "max_force", "N m"))
    return *e;
  if (auto e = checkMagnitude(what, "point", in.point, kMaxPointDistance, "the limit", "m"))
    return *e;
  // Body, frame, step, duration.
  auto target = w.movingTarget(what, in.body);
  if (!target) return Error{target.error()};
  const int i = *target;
  auto frame = w.frameOf(what, in.frame, i);
  if (!frame) return Error{frame.error()};
  auto k = w.stepOf(what, in.start_time);
  if (!k) return Error{k.error()};
  std::uint64_t steps = 1;
  if (in.duration < 0) {
    steps = 0;  // until cleared
  } else if (in.duration > 0) {
    const double n = std::floor(in.duration / w.config.dt + 0.5 + kStepTolerance);
    if (n > kMaxSteps)
      return fail(what + ".duration", num(in.duration) + " s is more than " + num(kMaxSteps) +
                                          " steps (use a negative duration: until cleared)");
    steps = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(n));
  }

  QueuedInput q = w.placed(QueuedInput::Kind::kWrench, *k, i, *frame, in.F, in.point, in.couple);
  q.steps = steps;
  // Room for this wrench when it starts, so step() does not allocate.
  std::size_t body_active = 0;
  for (const auto& a : w.active) body_active += a.body == i;
  reserveApplied(w.loads[i], body_active + w.queue.wrenchCount(i) + 1);
  w.active.reserve(w.active.size() + w.queue.size() + 1);
  w.queue.push(q);
  return true;
}

Result<bool> World::applyImpulse(const ImpulseInput& in) {
  Impl& w = *impl_;
  const std::string what = "apply_impulse";
  if (auto e = checkFinite(what, "J", in.J.f)) return *e;
  if (auto e = checkFinite(what, "alpha", in.J.alpha)) return *e;
  if (auto e = checkFinite(what, "point", in.point)) return *e;
  if (auto e = checkFinite(what, "angular", in.angular)) return *e;
  if (auto e = checkFinite(what, "start_time", in.start_time)) return *e;
  if (auto e = checkMagnitude(what, "J", in.J.f, w.config.max_impulse, "max_impulse", "N s"))
    return *e;
  if (auto e =
          checkMagnitude(what, "angular", in.angular, w.config.max_impulse, "max_impulse", "N m s"))
    return *e;
  if (auto e = checkMagnitude(what, "point", in.point, kMaxPointDistance, "the limit", "m"))
    return *e;
  auto target = w.movingTarget(what, in.body);
  if (!target) return Error{target.error()};
  const int i = *target;
  auto frame = w.frameOf(what, in.frame, i);
  if (!frame) return Error{frame.error()};
  auto k = w.stepOf(what, in.start_time);
  if (!k) return Error{k.error()};

  const QueuedInput q =
      w.placed(QueuedInput::Kind::kImpulse, *k, i, *frame, in.J, in.point, in.angular);
  w.queue.push(q);
  return true;
}

void World::clearWrenches() {
  impl_->dropWrenchLoads();
  impl_->queue.clearWrenches();
}

void World::reset() {
  Impl& w = *impl_;
  w.dropWrenchLoads();
  w.queue.clear();
  for (std::size_t i = 0; i < w.state.size(); ++i) {
    w.state[i] = w.initial[i];
    w.integrator[i]->reset();
    w.last_path[i] = Impl::kNotStepped;
  }
}

Result<BodyStateReport> World::getBodyState(const std::string& body) const {
  const int j = impl_->resolveBody(body);
  if (j < 0) return fail("get_body_state.body", "unknown body '" + body + "'");
  return impl_->report(j);
}

Result<bool> World::setBodyState(const std::string& body, const Eigen::Isometry3d& pose_root,
                                 const Eigen::Vector3d& linear_velocity_W,
                                 const Eigen::Vector3d& angular_velocity_W) {
  Impl& w = *impl_;
  const std::string what = "set_body_state";
  if (auto e = checkPose(what, pose_root)) return *e;
  if (auto e = checkFinite(what, "linear_velocity", linear_velocity_W)) return *e;
  if (auto e = checkFinite(what, "angular_velocity", angular_velocity_W)) return *e;
  auto target = w.movingTarget(what, body);
  if (!target) return Error{target.error()};
  const int i = *target;
  const scene::BodyModel& b = w.scene.bodies[w.scene_index[i]];
  w.state[i] =
      placedState(b.links.front().M_BL, pose_root, linear_velocity_W, angular_velocity_W, w.lambda);
  w.integrator[i]->reset();
  return true;
}

Result<bool> World::spawnUrdf(const std::string& name, const std::string& urdf,
                              const Eigen::Isometry3d& pose_root, const Eigen::Vector3d& linear_W,
                              const Eigen::Vector3d& angular_W) {
  Impl& w = *impl_;
  const std::string what = "spawn_urdf";
  if (name.empty()) return fail(what + ".name", "must not be empty");
  if (name == w.config.world_frame)
    return fail(what + ".name", "'" + name + "' is the name of the world frame");
  if (w.body_by_name.count(name)) return fail(what + ".name", "body '" + name + "' already exists");
  if (auto e = checkPose(what, pose_root)) return *e;
  if (auto e = checkFinite(what, "linear_velocity", linear_W)) return *e;
  if (auto e = checkFinite(what, "angular_velocity", angular_W)) return *e;

  scene::SceneOptions options;
  options.lambda = w.lambda;
  options.gravity_W = w.scene.gravity_W;
  options.world_frame = w.config.world_frame;
  options.triangle_policy = w.config.triangle_policy;
  const std::string source = "spawn_urdf '" + name + "'";
  auto loaded = scene::loadUrdfString(urdf, source, options);
  if (!loaded) return Error{loaded.error()};
  int moving = 0, fixed = 0;
  for (const auto& b : loaded->bodies) (b.is_static ? fixed : moving) += 1;
  if (moving != 1 || fixed != 0)
    return fail(source, "the URDF must hold exactly one body, a moving one (it has " +
                            std::to_string(moving) + " moving and " + std::to_string(fixed) +
                            " static)");
  scene::BodyModel body = loaded->bodies.front();
  if (!body.inertia) return fail(source, "the body has no inertia");
  // The body and its root link take the new name (body name = root link name).
  body.name = name;
  body.links.front().link = name;
  for (std::size_t li = 0; li < body.links.size(); ++li) {
    const std::string& link = body.links[li].link;
    const auto owner = w.link_owner.find(link);
    if (owner != w.link_owner.end())
      return fail(source, "link '" + link + "' already exists in the world (body '" +
                              w.scene.bodies[owner->second.first].name + "')");
    for (std::size_t lj = 0; lj < li; ++lj)
      if (body.links[lj].link == link)
        return fail(source, "link '" + link + "' would appear twice (the root link is renamed '" +
                                name + "')");
    if (link == w.config.world_frame)
      return fail(source, "link '" + link + "' has the name of the world frame");
  }
  const dynamics::BodyState s0 =
      placedState(body.links.front().M_BL, pose_root, linear_W, angular_W, w.lambda);
  body.M_WB0 = s0.M_WB;
  body.omega_B0 = s0.omega_B;

  const int j = static_cast<int>(w.scene.bodies.size());
  w.scene.bodies.push_back(std::move(body));
  w.moving_of_scene.push_back(static_cast<int>(w.state.size()));
  auto added = w.addMovingArrays(j, s0);
  if (!added) {  // cannot happen (the integrator name was checked by create); undo anyway
    w.scene.bodies.pop_back();
    w.moving_of_scene.pop_back();
    return Error{added.error()};
  }
  w.addNames(j);
  for (const auto& warning : loaded->warnings) w.scene.warnings.push_back(warning);
  ++w.topology_version;
  return true;
}

Result<bool> World::deleteBody(const std::string& body) {
  Impl& w = *impl_;
  const auto found = w.body_by_name.find(body);
  if (found == w.body_by_name.end()) return fail("delete_body.body", "unknown body '" + body + "'");
  const int j = found->second;
  const int i = w.moving_of_scene[j];
  if (i >= 0) {
    // Its inputs go with it; moving indices after it shift down by one.
    w.queue.removeBody(i);
    std::size_t out = 0;
    w.next_expiry = kUntilCleared;
    for (std::size_t a = 0; a < w.active.size(); ++a) {
      if (w.active[a].body == i) continue;
      ActiveWrench aw = w.active[a];
      if (aw.body > i) --aw.body;
      w.next_expiry = std::min(w.next_expiry, aw.end_step);
      w.active[out++] = aw;
    }
    w.active.resize(out);
    w.scene_index.erase(w.scene_index.begin() + i);
    w.inertia.erase(w.inertia.begin() + i);
    w.state.erase(w.state.begin() + i);
    w.initial.erase(w.initial.begin() + i);
    w.integrator.erase(w.integrator.begin() + i);
    w.loads.erase(w.loads.begin() + i);
    w.loads_dirty.erase(w.loads_dirty.begin() + i);
    w.last_path.erase(w.last_path.begin() + i);
  }
  // Names out, scene indices after j shift down by one.
  const scene::BodyModel& b = w.scene.bodies[j];
  for (const auto& l : b.links) w.link_owner.erase(l.link);
  w.body_by_name.erase(found);
  w.scene.bodies.erase(w.scene.bodies.begin() + j);
  w.moving_of_scene.erase(w.moving_of_scene.begin() + j);
  for (auto& m : w.moving_of_scene)
    if (i >= 0 && m > i) --m;
  for (auto& s : w.scene_index)
    if (s > j) --s;
  for (auto& kv : w.body_by_name)
    if (kv.second > j) --kv.second;
  for (auto& kv : w.link_owner)
    if (kv.second.first > j) --kv.second.first;
  ++w.topology_version;
  return true;
}

std::vector<MomentumReport> World::momentum() const {
  const Impl& w = *impl_;
  std::vector<MomentumReport> out;
  out.reserve(w.state.size() + 1);
  MomentumReport total;
  total.body = kTotalName;
  double mass = 0.0;
  Eigen::Vector3d mass_x = Eigen::Vector3d::Zero();  // Σ m x_c
  for (std::size_t i = 0; i < w.state.size(); ++i) {
    const dynamics::Inertia& I = w.inertia[i];
    const dynamics::BodyState& s = w.state[i];
    MomentumReport r;
    r.body = w.scene.bodies[w.scene_index[i]].name;
    r.linear = dynamics::linearMomentum_W(I, s, w.lambda);
    r.angular = dynamics::angularMomentumCom_W(I, s);
    r.angular_origin = dynamics::angularMomentumOrigin_W(I, s, w.lambda);
    r.kinetic_energy = dynamics::kineticEnergy(I, s, w.lambda);
    r.potential_energy = dynamics::potentialEnergy(I, s, w.scene.gravity_W, w.lambda);
    total.linear += r.linear;
    total.angular_origin += r.angular_origin;
    total.kinetic_energy += r.kinetic_energy;
    total.potential_energy += r.potential_energy;
    mass += I.mass();
    mass_x += I.mass() * dynamics::comPosition_W(s, w.lambda);
    out.push_back(std::move(r));
  }
  // About the system's centre of mass x_cm = Σ m x_c / Σ m: L_cm = L_origin − x_cm × P.
  if (mass > 0) total.angular = total.angular_origin - (mass_x / mass).cross(total.linear);
  out.push_back(std::move(total));
  return out;
}

std::vector<BodyStateReport> World::bodyStates() const {
  const Impl& w = *impl_;
  std::vector<BodyStateReport> out;
  out.reserve(w.state.size());
  for (int j : w.scene_index) out.push_back(w.report(j));
  return out;
}

std::vector<FramePose> World::movingFrames() const {
  const Impl& w = *impl_;
  std::vector<FramePose> out;
  out.reserve(w.state.size());
  for (std::size_t i = 0; i < w.state.size(); ++i) {
    const scene::LinkFrame& root = w.scene.bodies[w.scene_index[i]].links.front();
    out.push_back(
        {w.config.world_frame, root.link, (w.state[i].M_WB * root.M_BL).toIsometry(w.lambda)});
  }
  return out;
}

std::vector<FramePose> World::staticFrames() const {
  const Impl& w = *impl_;
  std::vector<FramePose> out;
  for (const auto& b : w.scene.bodies) {
    const scene::LinkFrame& root = b.links.front();
    if (b.is_static)
      out.push_back({w.config.world_frame, root.link, (b.M_WB0 * root.M_BL).toIsometry(w.lambda)});
    // Link L relative to the root link R: M_RL = M_BR⁻¹ M_BL.
    const cga::Motor M_RB = root.M_BL.reverse();
    for (std::size_t li = 1; li < b.links.size(); ++li)
      out.push_back({root.link, b.links[li].link, (M_RB * b.links[li].M_BL).toIsometry(w.lambda)});
  }
  return out;
}

std::string World::summary() const {
  constexpr std::size_t kMaxListed = 20;  // one screen, as the scene summary
  const Impl& w = *impl_;
  // The path of each body: the one its integrator took in the last step, "at-rest" if it was
  // skipped, or before its first step the planned one (scene.h).
  auto pathOf = [&](std::size_t j) -> std::string {
    const scene::BodyModel& b = w.scene.bodies[j];
    const int i = w.moving_of_scene[j];
    if (i < 0) return "static";
    switch (w.last_path[i]) {
      case Impl::kAtRest:
        return "at-rest";
      case Impl::kStepped:
        return w.integrator[i]->path();
      default:
        return scene::plannedIntegratorPath(w.scene, b, w.config.integrator);
    }
  };
  std::ostringstream os;
  os.precision(6);
  const auto& g = w.scene.gravity_W;
  os << "world: " << w.state.size() << " moving, " << w.scene.bodies.size() - w.state.size()
     << " static bodies; dt " << w.config.dt << " s, integrator '" << w.config.integrator
     << "', lambda " << w.lambda << " m, gravity (" << g.x() << ", " << g.y() << ", " << g.z()
     << ") m/s^2; step " << w.step_count << ", t " << w.time() << " s\n";
  std::map<std::string, std::size_t> count;  // ordered: deterministic output
  for (std::size_t j = 0; j < w.scene.bodies.size(); ++j) {
    const std::string path = pathOf(j);
    ++count[path];
    if (j >= kMaxListed) continue;
    const scene::BodyModel& b = w.scene.bodies[j];
    const int i = w.moving_of_scene[j];
    os << "  " << b.name << ": ";
    if (i >= 0) {
      const dynamics::Inertia& I = w.inertia[i];
      const Eigen::Vector3d& J = I.principalMoments();
      os << dynamics::toString(I.inertiaClass()) << ", mass " << I.mass() << " kg, J (" << J.x()
         << ", " << J.y() << ", " << J.z() << ") kg m^2, ";
    }
    os << "path " << path << ", links";
    for (const auto& l : b.links) os << " " << l.link;
    os << "\n";
  }
  if (w.scene.bodies.size() > kMaxListed)
    os << "  ... and " << w.scene.bodies.size() - kMaxListed << " more\n";
  os << "paths:";
  for (const auto& kv : count) os << " " << kv.first << " x" << kv.second;
  os << "\n";
  return os.str();
}

}  // namespace sim
}  // namespace cga_rigid_sim
