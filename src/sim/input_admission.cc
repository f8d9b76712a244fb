#include "input_admission.h"

#include <algorithm>
#include <cmath>

#include "input_rules.h"

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

Result<int> movingTarget(const Model& model, const std::string& input, const std::string& name) {
  const int j = model.resolveBody(name);
  if (j < 0) return Error(input, "body", "unknown body '" + name + "'");
  const int i = model.moving_of_body[j];
  if (i < 0)
    return Error(input, "body",
                 "body '" + model.scene.bodies[j].name + "' is static (static bodies never move)");
  return i;
}

Result<QueuedInput> admitWrench(const Model& model, const Data& data, const WrenchInput& in) {
  const std::string what = "apply_wrench";
  const WorldConfig& config = model.config;
  // Numbers: finite, within the limits.
  if (auto e = checkFinite(what, "f", in.F.f)) return *e;
  if (auto e = checkFinite(what, "alpha", in.F.alpha)) return *e;
  if (auto e = checkFinite(what, "point", in.point)) return *e;
  if (auto e = checkFinite(what, "couple", in.couple)) return *e;
  if (auto e = checkFinite(what, "start_time", in.start_time)) return *e;
  if (auto e = checkFinite(what, "duration", in.duration)) return *e;
  if (auto e = checkMagnitude(what, "f", in.F.f, config.max_force, "max_force", "N")) return *e;
  if (auto e = checkMagnitude(what, "couple", in.couple, config.max_force, "max_force", "N m"))
    return *e;
  if (auto e = checkMagnitude(what, "point", in.point, kMaxPointDistance, "the limit", "m"))
    return *e;
  // Body, frame, step, duration.
  auto target = movingTarget(model, what, in.body);
  if (!target) return target.failure();
  const int i = *target;
  auto frame = frameOf(model, what, in.frame, i);
  if (!frame) return frame.failure();
  auto k = stepOf(model, data, what, in.start_time);
  if (!k) return k.failure();
  std::uint64_t steps = 1;
  if (in.duration < 0) {
    steps = 0;  // until cleared
  } else if (in.duration > 0) {
    const double n = std::floor(in.duration / config.dt + 0.5 + kStepTolerance);
    if (n > kMaxSteps)
      return Error(what, "duration",
                   num(in.duration) + " s is more than " + num(kMaxSteps) +
                       " steps (use a negative duration: until cleared)");
    steps = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(n));
  }
  QueuedInput q =
      placed(model, QueuedInput::Kind::kWrench, *k, i, *frame, in.F, in.point, in.couple);
  q.steps = steps;
  return q;
}

Result<QueuedInput> admitImpulse(const Model& model, const Data& data, const ImpulseInput& in) {
  const std::string what = "apply_impulse";
  const WorldConfig& config = model.config;
  if (auto e = checkFinite(what, "J", in.J.f)) return *e;
  if (auto e = checkFinite(what, "alpha", in.J.alpha)) return *e;
  if (auto e = checkFinite(what, "point", in.point)) return *e;
  if (auto e = checkFinite(what, "angular", in.angular)) return *e;
  if (auto e = checkFinite(what, "start_time", in.start_time)) return *e;
  if (auto e = checkMagnitude(what, "J", in.J.f, config.max_impulse, "max_impulse", "N s"))
    return *e;
  if (auto e =
          checkMagnitude(what, "angular", in.angular, config.max_impulse, "max_impulse", "N m s"))
    return *e;
  if (auto e = checkMagnitude(what, "point", in.point, kMaxPointDistance, "the limit", "m"))
    return *e;
  auto target = movingTarget(model, what, in.body);
  if (!target) return target.failure();
  const int i = *target;
  auto frame = frameOf(model, what, in.frame, i);
  if (!frame) return frame.failure();
  auto k = stepOf(model, data, what, in.start_time);
  if (!k) return k.failure();
  return placed(model, QueuedInput::Kind::kImpulse, *k, i, *frame, in.J, in.point, in.angular);
}

void enqueue(Data& data, const QueuedInput& q) {
  if (q.kind == QueuedInput::Kind::kWrench) {
    // Room for this wrench when it starts, so the step does not allocate.
    std::size_t body_active = 0;
    for (const auto& a : data.active) body_active += a.body == q.body;
    data.bodies[q.body].loads.reserveApplied(body_active + data.queue.wrenchCount(q.body) + 1);
    data.active.reserve(data.active.size() + data.queue.size() + 1);
  }
  data.queue.push(q);
}

}  // namespace sim
}  // namespace cga_rigid_sim
