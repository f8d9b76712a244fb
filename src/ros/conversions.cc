// Conversions (conversions.h): time, and geometry between Eigen and geometry_msgs, validated
// where a message can hold what the core cannot.
#include "cga_rigid_sim/ros/conversions.h"

#include <cmath>

#include "cga_rigid_sim/scene/rotation_rule.h"
#include "finite_fields.h"

namespace cga_rigid_sim {
namespace node {
namespace {

// The first non-finite coordinate of (x, y, z), named "<field>.x" etc., or an empty string.
std::string firstNonFinite(double x, double y, double z, const std::string& field) {
  if (!std::isfinite(x)) return field + ".x";
  if (!std::isfinite(y)) return field + ".y";
  if (!std::isfinite(z)) return field + ".z";
  return {};
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

}  // namespace node
}  // namespace cga_rigid_sim
