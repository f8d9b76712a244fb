#include "sim/input/input_admission.h"

#include <algorithm>
#include <cmath>

#include "sim/input/input_rules.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// The link index of `frame` in moving body i, or −1 for the world frame, or the refusal.
Result<int> frameOf(const Model& model, const std::string& input, const std::string& frame, int i) {
  if (frame.empty() || frame == model.config.world_frame) return -1;
  const int j = model.moving[i].body;
  const auto l = model.link_owner.find(frame);
  if (l == model.link_owner.end() || l->second.first != j)
    return Error(input, "frame",
                 "frame '" + frame + "' is not the world frame '" + model.config.world_frame +
                     "' nor a link of body '" + model.scene.bodies[j].name + "'");
  return l->second.second;
}

// An input's directions and point, as queued: in world axes (frame < 0), or carried once from
// link L's frame into B with the constant placement M_BL — fixed in the link, it turns with it.
QueuedInput placed(const Model& model, QueuedInput::Kind kind, std::uint64_t step, int i, int frame,
                   const cga::Force& F, const Eigen::Vector3d& point,
                   const Eigen::Vector3d& couple) {
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
    const cga::Motor& M_BL = model.bodyOf(i).links[frame].M_BL;
    q.axes = dynamics::Axes::kBody;
    q.F = M_BL.apply(F, model.lambda);
    q.point = M_BL.transformPoint(point, model.lambda);
    q.couple = M_BL.transformVector(couple);
  }
  return q;
}

}  // namespace

// The step an input stamped s belongs to, k = floor(s/dt + kStepTolerance) (0 = the next
// step), or the refusal.
Result<std::uint64_t> stepOf(const Model& model, const Data& data, const std::string& input,
                             double s) {
  if (s == 0.0) return data.step_count;
  const double q = s / model.config.dt + kStepTolerance;
  if (q > kMaxSteps)
    return Error(input, "start_time",
                 "start stamp " + num(s) + " is too far ahead (more than " + num(kMaxSteps) +
                     " steps of " + num(model.config.dt) + " s)");
  const double k = std::floor(q);
  if (k < 0 || static_cast<std::uint64_t>(k) < data.step_count)
    return Error(input, "start_time",
                 "start stamp " + num(s) + " is already past (sim time " +
                     num(static_cast<double>(data.step_count) * model.config.dt) + ")");
  return static_cast<std::uint64_t>(k);
}

Result<int> movingTarget(const Model& model, const std::string& input, const std::string& name) {
  const int j = model.resolveBody(name);
  if (j < 0) return Error(input, "body", "unknown body '" + name + "'");
  const int i = model.moving_of_body[j];
  if (i < 0)
    return Error(input, "body",
                 "body '" + model.scene.bodies[j].name + "' is static (static bodies never move)");
  return i;
}

namespace {

// What wrenches and impulses share — a CGA force vector at a point plus a couple, on a body,
// in a frame, from a stamp — with the field names, limit and units of each.
struct ForceInput {
  const char* input;         // "apply_wrench", "apply_impulse"
  const char* force_field;   // "f", "J"
  const char* couple_field;  // "couple", "angular"
  double limit;
  const char* limit_name;
  const char* force_unit;
  const char* couple_unit;
  const std::string& body;
  const std::string& frame;
  const cga::Force& F;
  const Eigen::Vector3d& point;
  const Eigen::Vector3d& couple;
  double start_time;
};

std::optional<Error> checkFiniteNumbers(const ForceInput& in) {
  if (auto e = checkFinite(in.input, in.force_field, in.F.f)) return e;
  if (auto e = checkFinite(in.input, "alpha", in.F.alpha)) return e;
  if (auto e = checkFinite(in.input, "point", in.point)) return e;
  if (auto e = checkFinite(in.input, in.couple_field, in.couple)) return e;
  return checkFinite(in.input, "start_time", in.start_time);
}

std::optional<Error> checkLimits(const ForceInput& in) {
  if (auto e =
          checkMagnitude(in.input, in.force_field, in.F.f, in.limit, in.limit_name, in.force_unit))
    return e;
  if (auto e = checkMagnitude(in.input, in.couple_field, in.couple, in.limit, in.limit_name,
                              in.couple_unit))
    return e;
  return checkMagnitude(in.input, "point", in.point, kMaxPointDistance, "the limit", "m");
}

// Body, frame and step resolved, directions and point placed; the numbers are checked.
Result<QueuedInput> resolve(const Model& model, const Data& data, const ForceInput& in,
                            QueuedInput::Kind kind) {
  auto target = movingTarget(model, in.input, in.body);
  if (!target) return target.failure();
  auto frame = frameOf(model, in.input, in.frame, *target);
  if (!frame) return frame.failure();
  auto k = stepOf(model, data, in.input, in.start_time);
  if (!k) return k.failure();
  return placed(model, kind, *k, *target, *frame, in.F, in.point, in.couple);
}

// The number of steps a wrench of duration d lasts (world.h): 0 = until cleared.
Result<std::uint64_t> wrenchSteps(const WorldConfig& config, double d) {
  if (d < 0) return std::uint64_t{0};
  if (d == 0) return std::uint64_t{1};
  const double n = std::floor(d / config.dt + 0.5 + kStepTolerance);
  if (n > kMaxSteps)
    return Error("apply_wrench", "duration",
                 num(d) + " s is more than " + num(kMaxSteps) +
                     " steps (use a negative duration: until cleared)");
  return std::max<std::uint64_t>(1, static_cast<std::uint64_t>(n));
}

}  // namespace

Result<QueuedInput> admitWrench(const Model& model, const Data& data, const WrenchInput& in) {
  const ForceInput f{"apply_wrench", "f",  "couple", model.config.max_force,
                     "max_force",    "N",  "N m",    in.body,
                     in.frame,       in.F, in.point, in.couple,
                     in.start_time};
  if (auto e = checkFiniteNumbers(f)) return *e;
  if (auto e = checkFinite(f.input, "duration", in.duration)) return *e;
  if (auto e = checkLimits(f)) return *e;
  auto q = resolve(model, data, f, QueuedInput::Kind::kWrench);
  if (!q) return q;
  auto steps = wrenchSteps(model.config, in.duration);
  if (!steps) return steps.failure();
  q->steps = *steps;
  return q;
}

Result<QueuedInput> admitImpulse(const Model& model, const Data& data, const ImpulseInput& in) {
  const ForceInput f{"apply_impulse", "J",   "angular", model.config.max_impulse,
                     "max_impulse",   "N s", "N m s",   in.body,
                     in.frame,        in.J,  in.point,  in.angular,
                     in.start_time};
  if (auto e = checkFiniteNumbers(f)) return *e;
  if (auto e = checkLimits(f)) return *e;
  return resolve(model, data, f, QueuedInput::Kind::kImpulse);
}

std::string targetName(const Model& model, const QueuedInput& q) {
  if (q.kind == QueuedInput::Kind::kWrench || q.kind == QueuedInput::Kind::kImpulse)
    return "body '" + model.bodyOf(q.body).name + "'";
  const TreeModel& t = model.trees[q.tree];
  return "the tree of joint '" + model.scene.joints[t.scene_joint[q.joint]].name + "'";
}

std::optional<Error> checkQueueRoom(const Model& model, const Data& data, const std::string& input,
                                    const std::string& field, const QueuedInput& q, std::size_t n) {
  const bool body = q.kind == QueuedInput::Kind::kWrench || q.kind == QueuedInput::Kind::kImpulse;
  const std::size_t waiting = body ? data.queue.bodyCount(q.body) : data.queue.treeCount(q.tree);
  const int bound = model.config.max_queued_inputs_per_body;
  if (waiting + n > static_cast<std::size_t>(bound))
    return Error(input, field,
                 targetName(model, q) + " already has " + std::to_string(waiting) +
                     " inputs waiting for their step (max_queued_inputs_per_body = " +
                     std::to_string(bound) + ")");
  return checkQueueTotal(model, data, input, n);
}

std::optional<Error> checkQueueTotal(const Model& model, const Data& data, const std::string& input,
                                     std::size_t n) {
  const int bound = model.config.max_queued_inputs;
  if (data.queue.size() + n > static_cast<std::size_t>(bound))
    return Error(input, "start_time",
                 std::to_string(data.queue.size()) +
                     " inputs are already waiting for their step (max_queued_inputs = " +
                     std::to_string(bound) + ")");
  return std::nullopt;
}

std::size_t roomFor(std::size_t needed, int bound) {
  std::size_t n = 1;
  while (n < needed) n *= 2;
  return std::min(n, static_cast<std::size_t>(bound));
}

Result<bool> enqueue(const Model& model, Data& data, const QueuedInput& q,
                     const std::string& input) {
  if (auto e = checkQueueRoom(model, data, input, "body", q)) return *e;
  if (q.kind == QueuedInput::Kind::kWrench) {
    // Room for this wrench when it starts, so the step does not allocate: at most every
    // wrench active or waiting, and never more than a bound lets start.
    const WorldConfig& c = model.config;
    MovingBodyData& b = data.bodies[q.body];
    const std::size_t body_room = roomFor(b.wrenches.size() + data.queue.wrenchCount(q.body) + 1,
                                          c.max_active_wrenches_per_body);
    b.wrenches.reserve(body_room);
    b.loads.reserveApplied(body_room);
    data.expiries.reserve(
        roomFor(data.active_wrenches + data.queue.wrenchCount() + 1, c.max_active_wrenches));
  }
  data.queue.push(q);
  return true;
}

}  // namespace sim
}  // namespace cga_rigid_sim
