// Internal to the scene layer: the loader's own reading of the URDF XML (TinyXML2), done before
// urdfdom parses it.
//
// Why a second reading: urdfdom accepts things silently that no simulation should (a link with
// two parent joints, a cycle of joints, an <inertial> whose numbers it cannot read is kept with
// mass 0), and when it refuses a file its reason goes to the console, not to the caller. This
// pass checks what the loader relies on and names the file, the line, the link or joint and the
// rule. It also reads every <collision> (the links' collision shapes, collision_shape.h), the
// extension elements <cga_rigid_sim:mass_from_geometry> and <cga_rigid_sim:contact> (urdfdom
// ignores unknown elements), the friction of Gazebo's <gazebo reference="link"><mu1>/<mu2>, and
// Gazebo's sensors and model plugins (scene/sensors.h).
#pragma once

#include <Eigen/Geometry>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/scene/collision_shape.h"
#include "cga_rigid_sim/scene/joint.h"
#include "cga_rigid_sim/scene/sensors.h"

namespace cga_rigid_sim {
namespace scene {
namespace detail {

/// The name of the extension element for mass from geometry, inside a <link>.
constexpr const char* kMassFromGeometryElement = "cga_rigid_sim:mass_from_geometry";
/// The name of the extension element for contact parameters, inside a link's <collision>.
constexpr const char* kContactElement = "cga_rigid_sim:contact";
/// Prefix of every element of the extension.
constexpr const char* kExtensionPrefix = "cga_rigid_sim:";

/// One <collision> of a link, as read: its shape (kind, sizes checked > 0, name, line, surface
/// parameters; the mesh not loaded yet, M_BS and link_index not known yet) and what loading and
/// placing it needs.
struct CollisionGeometry {
  CollisionShape shape;
  std::string filename;                                    ///< mesh, as written in the URDF
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();         ///< mesh
  Eigen::Isometry3d X_LS = Eigen::Isometry3d::Identity();  ///< the <origin>: S in the link frame
  int geometry_line = 0;  ///< line of the shape element (<box>, <mesh>, …)
};

/// <cga_rigid_sim:mass_from_geometry density="…"/> or mass="…" (exactly one).
struct MassFromGeometry {
  double density = 0.0;  ///< kg/m³, > 0 when given
  double mass = 0.0;     ///< kg, > 0 when given (then density = mass / volume)
  bool by_mass = false;
  int line = 0;
};

struct LinkXml {
  int order = 0;  ///< position in the document
  int line = 0;
  bool has_inertial = false;
  double mass = 0.0;  ///< <mass value>, as read (for the cross-check with urdfdom)
  bool has_mass_from_geometry = false;
  MassFromGeometry mass_from_geometry;
  std::vector<CollisionGeometry> collisions;  ///< every <collision>, in document order
};

/// <mimic joint="…" multiplier="…" offset="…"/> of a joint, as written (multiplier default 1,
/// offset default 0, as URDF says).
struct MimicXml {
  std::string joint;
  double multiplier = 1.0;
  double offset = 0.0;
  int line = 0;
};

struct JointXml {
  int order = 0;
  int line = 0;
  std::optional<MimicXml> mimic;
  /// Set for a revolute, continuous or prismatic joint (then the fields below are read and
  /// checked); unset for fixed and floating joints, whose <axis>, <limit> and <dynamics> the
  /// loader does not use.
  std::optional<JointType> type;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  ///< unit; URDF's default (1, 0, 0)
  JointLimits limits;     ///< has_position for revolute and prismatic only
  double damping = 0.0;   ///< <dynamics damping>, >= 0
  double friction = 0.0;  ///< <dynamics friction>, >= 0
};

struct UrdfXml {
  std::string robot_name;
  std::unordered_map<std::string, LinkXml> links;
  std::unordered_map<std::string, JointXml> joints;
  /// Gazebo's <self_collide>: the model's (<gazebo> without reference) and each link's.
  std::optional<bool> self_collide_model;
  std::map<std::string, bool> self_collide_links;
  /// Gazebo's sensors and drives (<gazebo><sensor>, model <plugin>s), document order.
  SensorSet sensors;
  std::vector<std::string> warnings;  ///< e.g. Gazebo's mu1 and mu2 differ
};

/// Reads and checks the document. Every error starts with "<source>:<line>: ".
/// `plugin_namespace`, when not empty, replaces every gazebo_ros plugin's robotNamespace.
Result<UrdfXml> readUrdfXml(const std::string& xml, const std::string& source,
                            const std::string& world_frame, const std::string& plugin_namespace);

/// urdfdom's number syntax (a C-locale decimal number filling the whole string, leading white
/// space allowed), and finite.
bool parseUrdfNumber(const char* text, double* out);

}  // namespace detail
}  // namespace scene
}  // namespace cga_rigid_sim
