// Collision shapes: the geometry a body offers to contact detection, one per <collision> of
// every link merged into the body, each with its pose in the body frame B and the contact
// parameters of its surface (doc/urdf.md#collision-shapes-and-contact-parameters).
//
// Frames: S is the shape's own frame (the <collision><origin> frame). A box is centred on S's
// origin with its edges along S's axes; a cylinder is centred on S's origin with its axis along
// S's z (as in URDF); a sphere is centred on S's origin; a mesh's vertices are given in S. The
// shape sits at the constant motor M_BS in B, so in the world it is at M_WS = M_WB M_BS, as a
// link is at M_WL = M_WB M_BL (M_BS = M_BL M_LS, M_LS the <collision><origin>).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

#include "cga_rigid_sim/cga/motor.h"
#include "cga_rigid_sim/scene/mesh.h"

namespace cga_rigid_sim {
namespace scene {

/// The contact parameters of one collision surface. Unset means "the node's default"
/// (~contact_mu, ~contact_restitution), which the sim layer applies. Read from
/// <cga_rigid_sim:contact mu restitution> inside the <collision>, else μ from Gazebo's
/// <gazebo reference="link"><mu1>/<mu2> (doc/urdf.md gives the precedence).
struct SurfaceParameters {
  std::optional<double> mu;           ///< Coulomb friction coefficient (isotropic cone), ≥ 0
  std::optional<double> restitution;  ///< Newton's coefficient of restitution, in [0, 1]
};

/// One <collision> of a link, merged into its body.
struct CollisionShape {
  enum class Kind { kBox, kSphere, kCylinder, kMesh };
  Kind kind = Kind::kBox;
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  ///< kBox: full edge lengths along S, m, > 0
  double radius = 0.0;                             ///< kSphere, kCylinder: m, > 0
  double length = 0.0;                             ///< kCylinder: along S's z axis, m, > 0
  std::string mesh_file;  ///< kMesh: the resolved path of the file (STL or OBJ)
  /// kMesh: the triangles with the URDF scale applied, vertices in S, m (a mirroring scale has
  /// its winding restored). At least one triangle; not necessarily closed.
  TriangleMesh mesh;
  cga::Motor M_BS;            ///< the shape frame S in the body frame B
  int link_index = 0;         ///< the link it belongs to: BodyModel::links[link_index]
  std::string name;           ///< <collision name="…">, or "<link>#<k>" (the link's k-th, from 0)
  SurfaceParameters surface;  ///< contact parameters; unset = the node's default
  int line = 0;               ///< line of the <collision> element in the URDF
};

/// "box", "sphere", "cylinder", "mesh" (the URDF element names).
const char* toString(CollisionShape::Kind kind);

}  // namespace scene
}  // namespace cga_rigid_sim
