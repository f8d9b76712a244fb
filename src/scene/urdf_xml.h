// Internal to the scene layer: the loader's own reading of the URDF XML (TinyXML2), done before
// urdfdom parses it.
//
// Why a second reading: urdfdom accepts things silently that no simulation should (a link with
// two parent joints, a cycle of joints, an <inertial> whose numbers it cannot read is kept with
// mass 0), and when it refuses a file its reason goes to the console, not to the caller. This
// pass checks what the loader relies on and names the file, the line, the link or joint and the
// rule. It also reads the extension element <cga_rigid_sim:mass_from_geometry> (urdfdom ignores
// unknown elements) and the collision geometry of the links that use it.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <unordered_map>
#include <vector>

#include "cga_rigid_sim/result.h"

namespace cga_rigid_sim {
namespace scene {
namespace detail {

/// The name of the extension element, inside a <link>.
constexpr const char* kMassFromGeometryElement = "cga_rigid_sim:mass_from_geometry";
/// Prefix of every element of the extension.
constexpr const char* kExtensionPrefix = "cga_rigid_sim:";

/// One <collision> of a link that takes its mass from geometry.
struct CollisionGeometry {
  enum class Kind { kBox, kCylinder, kSphere, kMesh };
  Kind kind = Kind::kBox;
  Eigen::Vector3d size = Eigen::Vector3d::Zero();          ///< box edge lengths, m
  double radius = 0.0;                                     ///< cylinder, sphere, m
  double length = 0.0;                                     ///< cylinder (along z), m
  std::string filename;                                    ///< mesh, as written in the URDF
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();         ///< mesh
  Eigen::Isometry3d X_LG = Eigen::Isometry3d::Identity();  ///< collision origin in the link
  int line = 0;
};

/// <cga_rigid_sim:mass_from_geometry density="…"/> or mass="…" (exactly one).
struct MassFromGeometry {
  double density = 0.0;  ///< kg/m³, > 0 when given
  double mass = 0.0;     ///< kg, > 0 when given (then density = mass / volume)
  bool by_mass = false;
  int line = 0;
  std::vector<CollisionGeometry> parts;
};

struct LinkXml {
  int order = 0;  ///< position in the document
  int line = 0;
  bool has_inertial = false;
  double mass = 0.0;  ///< <mass value>, as read (for the cross-check with urdfdom)
  bool has_mass_from_geometry = false;
  MassFromGeometry mass_from_geometry;
};

struct JointXml {
  int order = 0;
  int line = 0;
};

struct UrdfXml {
  std::string robot_name;
  std::unordered_map<std::string, LinkXml> links;
  std::unordered_map<std::string, JointXml> joints;
};

/// Reads and checks the document. Every error starts with "<source>:<line>: ".
Result<UrdfXml> readUrdfXml(const std::string& xml, const std::string& source,
                            const std::string& world_frame);

/// urdfdom's number syntax (a C-locale decimal number filling the whole string, leading white
/// space allowed), and finite.
bool parseUrdfNumber(const char* text, double* out);

}  // namespace detail
}  // namespace scene
}  // namespace cga_rigid_sim
