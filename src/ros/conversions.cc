#include "cga_rigid_sim/ros/conversions.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "cga_rigid_sim/scene/rotation_rule.h"

namespace cga_rigid_sim {
namespace node {
namespace {

Error notFinite(const std::string& field) { return Error{field + ": not finite (NaN or Inf)"}; }

// The first non-finite coordinate of (x, y, z), named "<field>.x" etc., or an empty string.
std::string firstNonFinite(double x, double y, double z, const std::string& field) {
  if (!std::isfinite(x)) return field + ".x";
  if (!std::isfinite(y)) return field + ".y";
  if (!std::isfinite(z)) return field + ".z";
  return {};
}

// An empty frame_id means the world frame (convenient with `rostopic pub`).
std::string frameOrWorld(const std::string& frame_id, const std::string& world_frame) {
  return frame_id.empty() ? world_frame : frame_id;
}

}  // namespace

// ---- time ----

::ros::Time toRosTime(double t) { return ::ros::Time().fromSec(t); }
double toSimTime(const ::ros::Time& stamp) { return stamp.toSec(); }

// ---- geometry ----

Eigen::Vector3d toEigen(const geometry_msgs::Vector3& v) { return {v.x, v.y, v.z}; }
Eigen::Vector3d toEigen(const geometry_msgs::Point& p) { return {p.x, p.y, p.z}; }

geometry_msgs::Vector3 toVector3Msg(const Eigen::Vector3d& v) {
  geometry_msgs::Vector3 m;
  m.x = v.x();
  m.y = v.y();
  m.z = v.z();
  return m;
}

geometry_msgs::Point toPointMsg(const Eigen::Vector3d& p) {
  geometry_msgs::Point m;
  m.x = p.x();
  m.y = p.y();
  m.z = p.z();
  return m;
}

geometry_msgs::Pose toPoseMsg(const Eigen::Isometry3d& T) {
  geometry_msgs::Pose m;
  m.position = toPointMsg(T.translation());
  const Eigen::Quaterniond q(T.rotation());
  m.orientation.w = q.w();
  m.orientation.x = q.x();
  m.orientation.y = q.y();
  m.orientation.z = q.z();
  return m;
}

geometry_msgs::Transform toTransformMsg(const Eigen::Isometry3d& T) {
  const geometry_msgs::Pose p = toPoseMsg(T);
  geometry_msgs::Transform m;
  m.translation.x = p.position.x;
  m.translation.y = p.position.y;
  m.translation.z = p.position.z;
  m.rotation = p.orientation;
  return m;
}

Result<Eigen::Isometry3d> toIsometry(const geometry_msgs::Pose& pose, const std::string& field) {
  const std::string bad_position =
      firstNonFinite(pose.position.x, pose.position.y, pose.position.z, field + ".position");
  if (!bad_position.empty()) return notFinite(bad_position);
  const auto& o = pose.orientation;
  if (auto rule = scene::quaternionRule(o.w, o.x, o.y, o.z))
    return Error{field + ".orientation: " + *rule +
                 (o.w == 0.0 ? "; use w: 1 for no rotation" : "")};
  const double norm = std::sqrt(o.w * o.w + o.x * o.x + o.y * o.y + o.z * o.z);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() =
      Eigen::Quaterniond(o.w / norm, o.x / norm, o.y / norm, o.z / norm).toRotationMatrix();
  T.translation() = toEigen(pose.position);
  return T;
}

Result<Eigen::Vector3d> toFiniteEigen(const geometry_msgs::Vector3& v, const std::string& field) {
  const std::string bad = firstNonFinite(v.x, v.y, v.z, field);
  if (!bad.empty()) return notFinite(bad);
  return toEigen(v);
}

Result<Eigen::Vector3d> toFiniteEigen(const geometry_msgs::Point& p, const std::string& field) {
  const std::string bad = firstNonFinite(p.x, p.y, p.z, field);
  if (!bad.empty()) return notFinite(bad);
  return toEigen(p);
}

// ---- inputs ----

Result<sim::WrenchInput> toWrenchInput(const cga_rigid_sim::CgaWrench& msg,
                                       const std::string& world_frame, const std::string& topic) {
  auto f = toFiniteEigen(msg.f, topic + ".f");
  if (!f) return Error{f.error()};
  if (!std::isfinite(msg.alpha)) return notFinite(topic + ".alpha");
  auto point = toFiniteEigen(msg.point, topic + ".point");
  if (!point) return Error{point.error()};
  auto torque = toFiniteEigen(msg.torque, topic + ".torque");
  if (!torque) return Error{torque.error()};
  if (!std::isfinite(msg.duration)) return notFinite(topic + ".duration");

  sim::WrenchInput in;
  in.body = msg.body;
  in.frame = frameOrWorld(msg.header.frame_id, world_frame);
  in.F = cga::Force(*f, msg.alpha);
  in.point = *point;
  in.couple = *torque;
  in.start_time = toSimTime(msg.header.stamp);
  in.duration = msg.duration;
  return in;
}

Result<sim::ImpulseInput> toImpulseInput(const cga_rigid_sim::CgaImpulse& msg,
                                         const std::string& world_frame, const std::string& topic) {
  auto f = toFiniteEigen(msg.f, topic + ".f");
  if (!f) return Error{f.error()};
  if (!std::isfinite(msg.alpha)) return notFinite(topic + ".alpha");
  auto point = toFiniteEigen(msg.point, topic + ".point");
  if (!point) return Error{point.error()};
  auto torque = toFiniteEigen(msg.torque, topic + ".torque");
  if (!torque) return Error{torque.error()};

  sim::ImpulseInput in;
  in.body = msg.body;
  in.frame = frameOrWorld(msg.header.frame_id, world_frame);
  in.J = cga::Force(*f, msg.alpha);
  in.point = *point;
  in.angular = *torque;
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

// ---- outputs ----

namespace {
// The numbers of one entry (everything but its names), shared by the to…Msg conversions and the
// in-place fills so that both always write the same fields.
void setMomentumNumbers(const sim::MomentumReport& r, cga_rigid_sim::Momentum* m) {
  m->linear = toVector3Msg(r.linear);
  m->angular = toVector3Msg(r.angular);
  m->angular_origin = toVector3Msg(r.angular_origin);
  m->kinetic_energy = r.kinetic_energy;
  m->potential_energy = r.potential_energy;
  m->dissipated_energy = r.dissipated_energy;
}

void setBodyStateNumbers(const sim::BodyStateReport& r, cga_rigid_sim::BodyState* m) {
  m->pose = toPoseMsg(r.pose_root);
  m->com = toPointMsg(r.com);
  m->twist.linear = toVector3Msg(r.linear_velocity);
  m->twist.angular = toVector3Msg(r.angular_velocity);
  const auto motor = r.state.M_WB.coefficients();          // 1, e23, e31, e12, e1n, e2n, e3n, e123n
  const auto bivelocity = r.state.omega_B.coefficients();  // e23, e31, e12, e1n, e2n, e3n
  std::copy(motor.begin(), motor.end(), m->motor.begin());
  std::copy(bivelocity.begin(), bivelocity.end(), m->bivelocity.begin());
}

// Overwrites `items` with one entry per report: the names (set_names) only when asked or when
// the count changed (then every entry is renamed), the numbers (set_numbers) always.
template <class Items, class Report, class SetNames, class SetNumbers>
void fillItems(const std::vector<Report>& reports, bool names, Items* items, SetNames set_names,
               SetNumbers set_numbers) {
  if (items->size() != reports.size()) {
    items->resize(reports.size());
    names = true;
  }
  for (std::size_t i = 0; i < reports.size(); ++i) {
    if (names) set_names(reports[i], &(*items)[i]);
    set_numbers(reports[i], &(*items)[i]);
  }
}
}  // namespace

cga_rigid_sim::Momentum toMomentumMsg(const sim::MomentumReport& r) {
  cga_rigid_sim::Momentum m;
  m.body = r.body;
  setMomentumNumbers(r, &m);
  return m;
}

namespace {
// An array message: a header in the world frame and one entry per report in its field `items`
// (bodies, contacts).
template <class ArrayMsg, class Items, class Report, class Convert>
ArrayMsg toArrayMsg(const std::vector<Report>& reports, const ::ros::Time& stamp,
                    const std::string& world_frame, Items ArrayMsg::*items, Convert convert) {
  ArrayMsg m;
  m.header.stamp = stamp;
  m.header.frame_id = world_frame;
  (m.*items).reserve(reports.size());
  for (const auto& r : reports) (m.*items).push_back(convert(r));
  return m;
}
}  // namespace

cga_rigid_sim::MomentumArray toMomentumArrayMsg(const std::vector<sim::MomentumReport>& reports,
                                                const ::ros::Time& stamp,
                                                const std::string& world_frame) {
  return toArrayMsg(reports, stamp, world_frame, &cga_rigid_sim::MomentumArray::bodies,
                    toMomentumMsg);
}

cga_rigid_sim::CurvedMomentumArray toCurvedMomentumArrayMsg(
    const std::vector<sim::CurvedMomentumReport>& reports, double curvature_radius,
    const ::ros::Time& stamp, const std::string& world_frame) {
  cga_rigid_sim::CurvedMomentumArray msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = world_frame;
  msg.curvature_radius = curvature_radius;
  msg.bodies.reserve(reports.size());
  for (const sim::CurvedMomentumReport& r : reports) {
    cga_rigid_sim::CurvedMomentum m;
    m.body = r.body;
    const auto c = r.L_W.coefficients();  // e23, e31, e12, e14, e24, e34
    std::copy(c.begin(), c.end(), m.world_momentum.begin());
    m.kinetic_energy = r.kinetic_energy;
    msg.bodies.push_back(std::move(m));
  }
  return msg;
}

cga_rigid_sim::BodyState toBodyStateMsg(const sim::BodyStateReport& r) {
  cga_rigid_sim::BodyState m;
  m.name = r.name;
  setBodyStateNumbers(r, &m);
  return m;
}

cga_rigid_sim::BodyStateArray toBodyStateArrayMsg(const std::vector<sim::BodyStateReport>& reports,
                                                  const ::ros::Time& stamp,
                                                  const std::string& world_frame) {
  return toArrayMsg(reports, stamp, world_frame, &cga_rigid_sim::BodyStateArray::bodies,
                    toBodyStateMsg);
}

cga_rigid_sim::Contact toContactMsg(const sim::ContactReport& r) {
  cga_rigid_sim::Contact m;
  m.body_a = r.body_a;
  m.link_a = r.link_a;
  m.body_b = r.body_b;
  m.link_b = r.link_b;
  m.position = toPointMsg(r.point);
  m.normal = toVector3Msg(r.normal);
  m.depth = r.depth;
  m.normal_impulse = r.normal_impulse;
  m.friction_impulse = toVector3Msg(r.friction_impulse);
  return m;
}

cga_rigid_sim::ContactArray toContactArrayMsg(const std::vector<sim::ContactReport>& reports,
                                              const ::ros::Time& stamp,
                                              const std::string& world_frame) {
  return toArrayMsg(reports, stamp, world_frame, &cga_rigid_sim::ContactArray::contacts,
                    toContactMsg);
}

sensor_msgs::JointState toJointStateMsg(const std::vector<sim::JointStateReport>& reports,
                                        const ::ros::Time& stamp) {
  sensor_msgs::JointState msg;
  msg.header.stamp = stamp;
  msg.name.reserve(reports.size());
  msg.position.reserve(reports.size());
  msg.velocity.reserve(reports.size());
  msg.effort.reserve(reports.size());
  for (const auto& r : reports) {
    msg.name.push_back(r.name);
    msg.position.push_back(r.position);
    msg.velocity.push_back(r.velocity);
    msg.effort.push_back(r.effort);
  }
  return msg;
}

geometry_msgs::TransformStamped toTransformStampedMsg(const sim::FramePose& frame,
                                                      const ::ros::Time& stamp) {
  geometry_msgs::TransformStamped m;
  m.header.stamp = stamp;
  m.header.frame_id = frame.parent;
  m.child_frame_id = frame.child;
  m.transform = toTransformMsg(frame.pose);
  return m;
}

tf2_msgs::TFMessage toTfMessage(const std::vector<sim::FramePose>& frames,
                                const ::ros::Time& stamp) {
  tf2_msgs::TFMessage m;
  m.transforms.reserve(frames.size());
  for (const auto& f : frames) m.transforms.push_back(toTransformStampedMsg(f, stamp));
  return m;
}

// ---- outputs in place ----

void fillTfMessage(const std::vector<sim::FramePose>& frames, const ::ros::Time& stamp, bool names,
                   tf2_msgs::TFMessage* msg) {
  fillItems(
      frames, names, &msg->transforms,
      [](const sim::FramePose& f, geometry_msgs::TransformStamped* m) {
        m->header.frame_id = f.parent;
        m->child_frame_id = f.child;
      },
      [&stamp](const sim::FramePose& f, geometry_msgs::TransformStamped* m) {
        m->header.stamp = stamp;
        m->transform = toTransformMsg(f.pose);
      });
}

void fillTfMessage(const std::vector<sim::BodyStateReport>& states, const std::string& world_frame,
                   const ::ros::Time& stamp, bool names, tf2_msgs::TFMessage* msg) {
  fillItems(
      states, names, &msg->transforms,
      [&world_frame](const sim::BodyStateReport& r, geometry_msgs::TransformStamped* m) {
        m->header.frame_id = world_frame;
        m->child_frame_id = r.name;
      },
      [&stamp](const sim::BodyStateReport& r, geometry_msgs::TransformStamped* m) {
        m->header.stamp = stamp;
        m->transform = toTransformMsg(r.pose_root);
      });
}

void fillMomentumArrayMsg(const std::vector<sim::MomentumReport>& reports, const ::ros::Time& stamp,
                          const std::string& world_frame, bool names,
                          cga_rigid_sim::MomentumArray* msg) {
  msg->header.stamp = stamp;
  msg->header.frame_id = world_frame;
  fillItems(
      reports, names, &msg->bodies,
      [](const sim::MomentumReport& r, cga_rigid_sim::Momentum* m) { m->body = r.body; },
      setMomentumNumbers);
}

void fillBodyStateArrayMsg(const std::vector<sim::BodyStateReport>& reports,
                           const ::ros::Time& stamp, const std::string& world_frame, bool names,
                           cga_rigid_sim::BodyStateArray* msg) {
  msg->header.stamp = stamp;
  msg->header.frame_id = world_frame;
  fillItems(
      reports, names, &msg->bodies,
      [](const sim::BodyStateReport& r, cga_rigid_sim::BodyState* m) { m->name = r.name; },
      setBodyStateNumbers);
}

}  // namespace node
}  // namespace cga_rigid_sim
