// Conversions of the inputs (conversions.h): the wrench, impulse and joint-effort messages to
// the core's inputs, the World's refusals in the messages' own field names, and the pose and
// twist of set_body_state and spawn_urdf.
#include <cmath>

#include "cga_rigid_sim/ros/conversions.h"
#include "finite_fields.h"

namespace cga_rigid_sim {
namespace node {
namespace {

// An empty frame_id means the world frame (convenient with `rostopic pub`).
std::string frameOrWorld(const std::string& frame_id, const std::string& world_frame) {
  return frame_id.empty() ? world_frame : frame_id;
}

// What a CgaWrench and a CgaImpulse both carry, each number checked finite in the order of the
// message's fields: F = f + αn at `point`, and the couple (the message's torque).
struct CgaLoad {
  cga::Force F;
  Eigen::Vector3d point, couple;
};

template <class CgaMsg>
Result<CgaLoad> toCgaLoad(const CgaMsg& msg, const std::string& topic) {
  auto f = toFiniteEigen(msg.f, topic + ".f");
  if (!f) return Error{f.error()};
  if (!std::isfinite(msg.alpha)) return notFinite(topic + ".alpha");
  auto point = toFiniteEigen(msg.point, topic + ".point");
  if (!point) return Error{point.error()};
  auto torque = toFiniteEigen(msg.torque, topic + ".torque");
  if (!torque) return Error{torque.error()};
  return CgaLoad{cga::Force(*f, msg.alpha), *point, *torque};
}

}  // namespace

Result<sim::WrenchInput> toWrenchInput(const cga_rigid_sim::CgaWrench& msg,
                                       const std::string& world_frame, const std::string& topic) {
  auto load = toCgaLoad(msg, topic);
  if (!load) return Error{load.error()};
  if (!std::isfinite(msg.duration)) return notFinite(topic + ".duration");

  sim::WrenchInput in;
  in.body = msg.body;
  in.frame = frameOrWorld(msg.header.frame_id, world_frame);
  in.F = load->F;
  in.point = load->point;
  in.couple = load->couple;
  in.start_time = toSimTime(msg.header.stamp);
  in.duration = msg.duration;
  return in;
}

Result<sim::ImpulseInput> toImpulseInput(const cga_rigid_sim::CgaImpulse& msg,
                                         const std::string& world_frame, const std::string& topic) {
  auto load = toCgaLoad(msg, topic);
  if (!load) return Error{load.error()};

  sim::ImpulseInput in;
  in.body = msg.body;
  in.frame = frameOrWorld(msg.header.frame_id, world_frame);
  in.J = load->F;
  in.point = load->point;
  in.angular = load->couple;
  in.start_time = toSimTime(msg.header.stamp);
  return in;
}

Result<sim::WrenchInput> toWrenchInput(const geometry_msgs::WrenchStamped& msg,
                                       const scene::Scene& scene, const std::string& topic) {
  const std::string& link = msg.header.frame_id;
  const int body = link.empty() ? -1 : scene.findLink(link);
  if (body < 0) {
    return Error{topic + ".header.frame_id: '" + link +
                 "' is not a link of any body (the plain wrench acts at a link's origin; use "
                 "apply_wrench for a wrench in the world frame)"};
  }
  auto force = toFiniteEigen(msg.wrench.force, topic + ".wrench.force");
  if (!force) return Error{force.error()};
  auto torque = toFiniteEigen(msg.wrench.torque, topic + ".wrench.torque");
  if (!torque) return Error{torque.error()};

  sim::WrenchInput in;
  in.body = scene.bodies[static_cast<std::size_t>(body)].name;
  in.frame = link;
  in.F = cga::Force(*force, 0.0);
  in.point = Eigen::Vector3d::Zero();
  in.couple = *torque;
  in.start_time = toSimTime(msg.header.stamp);
  in.duration = 0.0;  // one step
  return in;
}

sim::JointEffortInput toJointEffortInput(const sensor_msgs::JointState& msg) {
  sim::JointEffortInput in;
  in.names = msg.name;
  in.efforts = msg.effort;
  in.stamp = toSimTime(msg.header.stamp);
  return in;
}

sim::TimedJointEffortInput toTimedJointEffortInput(
    const cga_rigid_sim::ApplyJointEffort::Request& req) {
  sim::TimedJointEffortInput in;
  in.joint = req.joint;
  in.effort = req.effort;
  in.start_time = req.start_time;
  in.duration = req.duration;
  return in;
}

std::string refusalText(const Error& core, const std::string& topic) {
  if (core.input.empty()) return core.message();
  // (topic, core field, message field); fields not listed keep their name.
  struct Rename {
    const char* topic;
    const char* field;
    const char* message_field;
  };
  static const Rename kRenames[] = {
      {"apply_wrench", "couple", "torque"},
      {"apply_wrench", "start_time", "header.stamp"},
      {"apply_wrench", "frame", "header.frame_id"},
      {"apply_impulse", "J", "f"},
      {"apply_impulse", "angular", "torque"},
      {"apply_impulse", "start_time", "header.stamp"},
      {"apply_impulse", "frame", "header.frame_id"},
      {"wrench", "f", "wrench.force"},
      {"wrench", "couple", "wrench.torque"},
      {"wrench", "start_time", "header.stamp"},
      {"wrench", "frame", "header.frame_id"},
      {"wrench", "body", "header.frame_id"},
      {"joint_efforts", "stamp", "header.stamp"},
  };
  // The field's first name is renamed; a sub-field (".x") or an index ("name[1]") stays.
  const std::size_t dot = core.field.find('.');
  const std::string head = core.field.substr(0, dot);
  const std::string rest = dot == std::string::npos ? "" : core.field.substr(dot);
  std::string renamed = head;
  for (const Rename& r : kRenames)
    if (topic == r.topic && head == r.field) renamed = r.message_field;
  return topic + "." + renamed + rest + ": " + core.rule;
}

Result<PoseTwist> toPoseTwist(const geometry_msgs::Pose& pose, const geometry_msgs::Twist& twist,
                              const std::string& field) {
  auto T = toIsometry(pose, field + ".pose");
  if (!T) return Error{T.error()};
  auto linear = toFiniteEigen(twist.linear, field + ".twist.linear");
  if (!linear) return Error{linear.error()};
  auto angular = toFiniteEigen(twist.angular, field + ".twist.angular");
  if (!angular) return Error{angular.error()};
  PoseTwist out;
  out.pose_root = *T;
  out.linear_W = *linear;
  out.angular_W = *angular;
  return out;
}

}  // namespace node
}  // namespace cga_rigid_sim
