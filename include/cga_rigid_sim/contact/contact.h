// Contact: one point where two bodies (or a body and the ground plane) touch in a step, and the
// impulse the contact solver gave it (doc/contacts.md).
//
// A contact joins body a (always moving) to body b (moving, static, or the ground plane). Its
// normal is a unit vector in world axes pointing from b towards a: the normal impulse on a acts
// along it, the one on b against it. Depth is the penetration along the normal (> 0: the
// shapes overlap; ≤ 0: a gap that the step may close, a speculative contact).
#pragma once

#include <Eigen/Core>
#include <limits>

namespace cga_rigid_sim {
namespace sim {

/// body_b of a contact with the ground plane (it is no scene body).
constexpr int kGroundPlane = -1;
/// The name the ground plane has in reports (body and link).
constexpr const char* kGroundPlaneName = "ground_plane";

struct Contact {
  int body_a = -1;            ///< body index j (scene.bodies), a moving body
  int shape_a = -1;           ///< index in scene.bodies[body_a].shapes
  int body_b = kGroundPlane;  ///< body index j, or kGroundPlane
  int shape_b = -1;           ///< index in scene.bodies[body_b].shapes; −1 for the plane
  Eigen::Vector3d point_W = Eigen::Vector3d::Zero();    ///< contact point, world, m
  Eigen::Vector3d normal_W = Eigen::Vector3d::UnitZ();  ///< unit, from b towards a
  double depth = 0.0;  ///< penetration along the normal, m (≤ 0: gap)
  int feature = -1;    ///< which point of shape a (a vertex for plane contacts), −1: unknown
  double mu = 0.0;     ///< combined friction coefficient (doc/contacts.md)
  double restitution = 0.0;  ///< combined coefficient of restitution
  /// The impulse of the last step on a (b receives its opposite): along the normal, N s, ≥ 0,
  /// and tangential (world axes, N s, |friction| ≤ mu·normal).
  double normal_impulse = 0.0;
  Eigen::Vector3d friction_impulse_W = Eigen::Vector3d::Zero();
  /// The solver's own, for the next step's warm start: of normal_impulse, the part a tree's
  /// resting solve last put on its friction pyramid's two edges along the first tangent (the
  /// rest on the two along the second; kept through steps the sweeps solve), which the
  /// impulses alone do not tell; NaN when unknown.
  double pyramid_share = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace sim
}  // namespace cga_rigid_sim
