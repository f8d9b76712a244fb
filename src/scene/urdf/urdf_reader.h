// Internal to the scene layer: the reader behind readUrdfXml (urdf_xml.h), shared by the files
// that implement it — urdf_xml.cc (the document, its bounds, the extension's placement, the number
// syntax), urdf_xml_links.cc (links, the mass extension), urdf_xml_joints.cc (joints, mimic
// chains), urdf_xml_tree.cc (the tree check) and urdf_xml_collision.cc (collision geometry,
// contact parameters, Gazebo's friction and <self_collide>) and urdf_xml_gazebo.cc (Gazebo's
// sensors and model plugins).
#pragma once

#include <tinyxml2.h>

#include <Eigen/Geometry>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cga_rigid_sim/format.h"
#include "cga_rigid_sim/math/rpy.h"
#include "cga_rigid_sim/result.h"
#include "scene/urdf/urdf_xml.h"

namespace cga_rigid_sim {
namespace scene {
namespace detail {

using tinyxml2::XMLAttribute;
using tinyxml2::XMLElement;

// urdfdom's Vector3::init: the text is split at spaces, empty pieces are skipped, and exactly
// three numbers must remain.
inline bool parseTriple(const char* text, Eigen::Vector3d* out) {
  std::istringstream in{std::string(text)};
  std::string piece;
  int n = 0;
  while (std::getline(in, piece, ' ')) {
    if (piece.empty()) continue;
    if (n == 3 || !parseUrdfNumber(piece.c_str(), &(*out)[n])) return false;
    ++n;
  }
  return n == 3;
}

using math::rotationFromRpy;

class Reader {
 public:
  Reader(const std::string& source, const std::string& world_frame,
         const std::string& plugin_namespace)
      : source_(source), world_frame_(world_frame), plugin_namespace_(plugin_namespace) {}

  Result<UrdfXml> read(const std::string& xml);

 private:
  struct JointEdge {
    std::string name, parent, child;
    int line = 0;
  };
  // One <mu1> or <mu2> of a <gazebo reference="…">, as written.
  struct GazeboNumber {
    std::string text;
    int line = 0;
  };
  struct GazeboFriction {
    std::string reference;
    int line = 0;
    std::optional<GazeboNumber> mu1, mu2;
  };

  Error fail(int line, const std::string& what) const {
    return Error{source_ + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + what};
  }
  // "<owner>: <element attr> must be … (got '…')", or nothing when the attribute is fine.
  std::optional<Error> readNumberAttr(const XMLElement* e, const char* attr,
                                      const std::string& owner, bool required, double* out) const;
  std::optional<Error> readOrigin(const XMLElement* parent, const std::string& owner,
                                  Eigen::Isometry3d* X) const;
  std::optional<Error> readGeometry(const XMLElement* holder, const std::string& owner, bool strict,
                                    CollisionGeometry* g) const;
  std::optional<Error> readCollision(const XMLElement* e, const std::string& link, int k,
                                     CollisionGeometry* g) const;
  std::optional<Error> readContact(const XMLElement* e, const std::string& owner,
                                   SurfaceParameters* surface) const;
  void readGazebo(const XMLElement* e);
  std::optional<Error> readSelfCollide(const XMLElement* e);
  std::optional<Error> applyGazeboFriction();
  // Sensors and drives (urdf_xml_gazebo.cc), once every link and joint is known.
  std::optional<Error> readGazeboSensors(const XMLElement* gazebo);
  std::optional<Error> readSensor(const XMLElement* e, const std::string& reference);
  void readBumperCollision(const XMLElement* sensor, const std::string& owner, SensorModel* s);
  std::optional<Error> readModelPlugin(const XMLElement* p);
  std::optional<Error> readDrive(const XMLElement* p, const std::string& file,
                                 const std::string& name);
  std::optional<Error> readNoise(const XMLElement* holder, const std::string& owner,
                                 GaussianNoise* noise);
  std::optional<Error> readSensorPose(const XMLElement* sensor, const std::string& owner,
                                      Eigen::Isometry3d* X_LS) const;
  std::optional<Error> readGazeboNumber(const XMLElement* parent, const char* name,
                                        const std::string& owner, bool non_negative,
                                        double* out) const;
  std::optional<Error> readGazeboTriple(const XMLElement* parent, const char* name,
                                        const std::string& owner, Eigen::Vector3d* out) const;
  std::optional<Error> readGazeboBool(const XMLElement* parent, const char* name,
                                      const std::string& owner, bool* out) const;
  void warn(int line, const std::string& what);
  bool isLink(const std::string& name) const;
  const JointEdge* findEdge(const std::string& joint) const;
  std::optional<Error> readLink(const XMLElement* e, int order);
  std::optional<Error> readJoint(const XMLElement* e, int order);
  // <axis>, <limit> and <dynamics> of a revolute, continuous or prismatic joint.
  std::optional<Error> readJointMotion(const XMLElement* e, const std::string& owner,
                                       JointXml* joint);
  // After the link's collisions are read (it needs at least one).
  std::optional<Error> readMassFromGeometry(const std::string& owner, const XMLElement* ext,
                                            LinkXml* out) const;
  std::optional<Error> checkExtensionPlacement(const XMLElement* robot) const;
  std::optional<Error> checkTree() const;
  // Every <mimic> names another articulated joint, and following them never loops.
  std::optional<Error> checkMimics() const;

  const std::string& source_;
  const std::string& world_frame_;
  const std::string& plugin_namespace_;  ///< replaces every plugin's robotNamespace when set
  /// A plugin's robotNamespace: plugin_namespace_ when set, else as written ("" when absent).
  std::string robotNamespace(const XMLElement* plugin) const;
  UrdfXml out_;
  std::vector<JointEdge> edges_;
  std::vector<std::string> link_names_;                          // document order
  std::vector<GazeboFriction> gazebo_;                           // document order
  std::vector<std::pair<std::string, int>> self_collide_lines_;  // <self_collide> per link, line
};

}  // namespace detail
}  // namespace scene
}  // namespace cga_rigid_sim
