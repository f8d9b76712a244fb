#include "cga_rigid_sim/ros/markers.h"

#include <algorithm>
#include <map>

#include "cga_rigid_sim/ros/conversions.h"

namespace cga_rigid_sim {
namespace node {
namespace {

// Arrows shorter than this are not drawn (rviz draws a zero-length arrow as a stray head).
constexpr double kMinArrowLength = 1e-6;  // m

std_msgs::ColorRGBA rgba(float r, float g, float b, float a = 1.0f) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

visualization_msgs::Marker makeMarker(const std::string& ns, int id, int type,
                                      const ::ros::Time& stamp, const std::string& frame) {
  visualization_msgs::Marker m;
  m.header.stamp = stamp;
  m.header.frame_id = frame;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;  // points are given in `frame` itself
  m.frame_locked = false;
  return m;
}

// An arrow from `from` along `direction` (any length), `length` metres long; false if too short.
bool makeArrow(const std::string& ns, int id, const Eigen::Vector3d& from,
               const Eigen::Vector3d& direction, double length, const std_msgs::ColorRGBA& color,
               double ell, const ::ros::Time& stamp, const std::string& frame,
               visualization_msgs::Marker* out) {
  const double norm = direction.norm();
  if (!(length >= kMinArrowLength) || !(norm > 0.0)) return false;
  *out = makeMarker(ns, id, visualization_msgs::Marker::ARROW, stamp, frame);
  out->points.push_back(toPointMsg(from));
  out->points.push_back(toPointMsg(from + (length / norm) * direction));
  // Shaft and head in proportion to ℓ, not to the arrow: short arrows keep a visible head.
  out->scale.x = 0.04 * ell;  // shaft diameter
  out->scale.y = 0.10 * ell;  // head diameter
  out->scale.z = 0.15 * ell;  // head length
  out->color = color;
  return true;
}

}  // namespace

double arrowLength(double x, double x_ref, double length) {
  if (!(x_ref > 0.0) || !(x >= 0.0)) return 0.0;
  return length * std::min(x / x_ref, kMaxRelativeLength);
}

MarkerReferences updateMarkerReferences(const MarkerInputs& in, const MarkerScale& scale,
                                        const MarkerReferences& previous) {
  double largest_L = 0.0, largest_w = 0.0;
  for (const auto& m : in.momentum)
    if (m.kind == sim::MomentumReport::Kind::kBody)
      largest_L = std::max(largest_L, m.angular.norm());
  for (const auto& b : in.bodies) largest_w = std::max(largest_w, b.angular_velocity.norm());
  MarkerReferences refs;
  refs.angular_momentum =
      scale.angular_momentum_ref > 0.0
          ? scale.angular_momentum_ref
          : std::max({previous.angular_momentum, largest_L, kMinAngularMomentumRef});
  refs.angular_velocity =
      scale.angular_velocity_ref > 0.0
          ? scale.angular_velocity_ref
          : std::max({previous.angular_velocity, largest_w, kMinAngularVelocityRef});
  refs.force = scale.force_ref;
  return refs;
}

visualization_msgs::MarkerArray toMarkerArray(const MarkerInputs& in, double length,
                                              const MarkerReferences& refs,
                                              const ::ros::Time& stamp, const std::string& frame) {
  visualization_msgs::MarkerArray out;
  {
    visualization_msgs::Marker clear;
    clear.header.stamp = stamp;
    clear.header.frame_id = frame;
    clear.action = visualization_msgs::Marker::DELETEALL;
    out.markers.push_back(clear);
  }
  const double ell = length;

  // Per body: L (about the CoM) and ω at the centre of mass.
  std::map<std::string, const sim::MomentumReport*> momentum_of;
  for (const auto& m : in.momentum) momentum_of[m.body] = &m;
  const auto L_color = rgba(1.0f, 0.45f, 0.0f);      // orange
  const auto omega_color = rgba(0.1f, 0.55f, 1.0f);  // blue
  for (const auto& b : in.bodies) {
    const std::string ns = "body/" + b.name;
    visualization_msgs::Marker arrow;
    const auto it = momentum_of.find(b.name);
    if (it != momentum_of.end()) {
      const Eigen::Vector3d& L_W = it->second->angular;
      if (makeArrow(ns, 0, b.com, L_W, arrowLength(L_W.norm(), refs.angular_momentum, ell), L_color,
                    ell, stamp, frame, &arrow))
        out.markers.push_back(arrow);
    }
    const Eigen::Vector3d& w_W = b.angular_velocity;
    if (makeArrow(ns, 1, b.com, w_W, arrowLength(w_W.norm(), refs.angular_velocity, ell),
                  omega_color, ell, stamp, frame, &arrow))
      out.markers.push_back(arrow);
  }

  // Contacts: points, normals, and each impulse as its mean force over the step.
  if (!in.contacts.empty()) {
    auto points = makeMarker("contacts", 0, visualization_msgs::Marker::SPHERE_LIST, stamp, frame);
    points.scale.x = points.scale.y = points.scale.z = 0.08 * ell;  // sphere diameter
    points.color = rgba(1.0f, 0.9f, 0.0f);                          // yellow
    auto normals = makeMarker("contacts", 1, visualization_msgs::Marker::LINE_LIST, stamp, frame);
    normals.scale.x = 0.02 * ell;                       // line width
    normals.color = rgba(0.2f, 0.8f, 0.2f);             // green
    const auto impulse_color = rgba(0.9f, 0.1f, 0.8f);  // magenta
    for (std::size_t k = 0; k < in.contacts.size(); ++k) {
      const sim::ContactReport& c = in.contacts[k];
      points.points.push_back(toPointMsg(c.point));
      normals.points.push_back(toPointMsg(c.point));
      normals.points.push_back(toPointMsg(c.point + 0.5 * ell * c.normal));
      if (in.dt > 0.0) {
        const Eigen::Vector3d force_W = (c.normal_impulse * c.normal + c.friction_impulse) / in.dt;
        visualization_msgs::Marker arrow;
        if (makeArrow("contact_impulses", static_cast<int>(k), c.point, force_W,
                      arrowLength(force_W.norm(), refs.force, ell), impulse_color, ell, stamp,
                      frame, &arrow))
          out.markers.push_back(arrow);
      }
    }
    out.markers.push_back(points);
    out.markers.push_back(normals);
  }
  return out;
}

visualization_msgs::MarkerArray markersOf(const sim::World& world, const MarkerScale& scale,
                                          MarkerReferences* refs, const ::ros::Time& stamp) {
  MarkerInputs in;
  in.bodies = world.bodyStates();
  in.momentum = world.momentum();
  in.contacts = world.contacts();
  in.dt = world.config().dt;
  *refs = updateMarkerReferences(in, scale, *refs);
  return toMarkerArray(in, scale.length, *refs, stamp, world.config().world_frame);
}

}  // namespace node
}  // namespace cga_rigid_sim
