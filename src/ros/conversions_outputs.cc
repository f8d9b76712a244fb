// Conversions of the outputs (conversions.h): the World's reports to momentum, body-state,
// contact, joint-state and tf messages, built anew or written in place into the messages the node
// keeps from tick to tick.
#include <algorithm>
#include <iterator>

#include "cga_rigid_sim/ros/conversions.h"

namespace cga_rigid_sim {
namespace node {

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
