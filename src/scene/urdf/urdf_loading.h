// Internal to scene/urdf: the Loader behind loadUrdfFile and loadUrdfString (urdf_loader.h),
// shared by the files that implement its steps (doc/urdf.md): urdf_loader.cc (the pipeline, the
// cross-check with urdfdom, the entry points), urdf_link_mass.cc (each link's collision meshes
// and mass properties, the inertia repairs), urdf_bodies.cc (links merged into bodies, joints
// without mass welded), urdf_joints.cc (the joints' models, parent-first order, default
// positions), urdf_mimic.cc (mimic chains resolved and checked) and urdf_tf_frames.cc (link names
// as tf frames).
#pragma once

#include <urdf_model/model.h>

#include <Eigen/Geometry>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/scene/mass_properties.h"
#include "cga_rigid_sim/scene/mesh.h"
#include "cga_rigid_sim/scene/scene.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "scene/urdf/urdf_xml.h"

namespace cga_rigid_sim {
namespace scene {
namespace detail {

// The inertia repairs (doc/urdf.md#inertias-from-cad) are made by default, with a warning; the
// strict option refuses instead, and its messages say how to accept the repair.
const char* const kRelaxHint =
    " (refused because ~relax_inertia is false, SceneOptions::triangle_policy = kRefuse; by "
    "default the loader repairs this with a warning)";
const char* const kRepairedNote = " (~relax_inertia:=false refuses this instead)";

// A link's tf frame name: its name without leading '/' (tf2 refuses frame ids that start with
// one; ROS 1 descriptions written for tf (1) often have them).
inline std::string tfFrame(const std::string& link) {
  const std::size_t start = link.find_first_not_of('/');
  return start == std::string::npos ? std::string() : link.substr(start);
}

// Numbers in messages: 10 significant digits show a triangle inequality broken in the 8th.
constexpr int kDigits = 10;

// urdfdom's pose as an isometry (its quaternion normalised).
inline Eigen::Isometry3d toIsometry(const urdf::Pose& p) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  X.translation() << p.position.x, p.position.y, p.position.z;
  return X;
}

// Everything the loader needs in one place while it runs.
class Loader {
 public:
  Loader(const std::string& source, const std::string& base_dir, const SceneOptions& options)
      : source_(source), base_dir_(base_dir), options_(options) {}

  Result<Scene> load(const std::string& xml);

 private:
  struct LinkMass {
    bool massive = false;
    MassProperties in_link;  // link frame
  };
  // The root link of a body to build. A body started by a revolute, continuous or prismatic
  // joint also knows that joint, its parent body and the joint frame J in the parent's B.
  struct BodyRoot {
    const urdf::Link* link = nullptr;
    /// The root link's pose with every joint above it at 0 (the floating bodies below it start
    /// there).
    Eigen::Isometry3d X_WR = Eigen::Isometry3d::Identity();
    bool is_static = false;
    const urdf::Joint* joint = nullptr;  ///< the articulated joint that starts the body
    int parent = -1;                     ///< the parent's index in the roots (−1: the world)
    Eigen::Isometry3d X_PJ = Eigen::Isometry3d::Identity();  ///< J in B_p (in W for the world)
  };

  Error fail(int line, const std::string& what) const {
    return Error{source_ + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + what};
  }
  int linkLine(const std::string& link) const {
    const auto it = xml_.links.find(link);
    return it == xml_.links.end() ? 0 : it->second.line;
  }
  std::optional<Error> checkOptions() const;
  std::optional<Error> crossCheck(const urdf::ModelInterface& model) const;
  Result<LinkMass> linkMassFromInertial(const urdf::Link& link);
  std::optional<Error> loadCollisionMeshes(const std::string& link,
                                           std::vector<detail::CollisionGeometry>* collisions);
  Result<LinkMass> linkMassFromGeometry(
      const std::string& link, const detail::MassFromGeometry& spec,
      const std::vector<detail::CollisionGeometry>& collisions) const;
  Result<BodyModel> buildBody(const BodyRoot& root, int index, std::vector<BodyRoot>* more_roots);
  JointModel jointModel(const BodyRoot& root, int index, const BodyModel& child) const;
  static void orderParentFirst(Scene* scene, const std::vector<int>& document_order);
  std::optional<Error> resolveMimics(Scene* scene) const;
  std::optional<Error> nameFramesForTf(Scene* scene);
  void setDefaultInitialPositions(Scene* scene);
  std::vector<urdf::JointSharedPtr> childJoints(const urdf::Link& link) const;
  bool weldsMassless(const urdf::Joint& j);
  Eigen::Isometry3d weldedMotion(const urdf::Joint& j) const;

  const std::string& source_;
  const std::string& base_dir_;
  const SceneOptions& options_;
  detail::UrdfXml xml_;
  const urdf::ModelInterface* model_ = nullptr;
  std::unordered_map<std::string, LinkMass> masses_;
  // Per link: the mass (kg) and the largest principal moment (kg m²) of it and every link below
  // it through fixed and moving joints (not floating ones: they start other free bodies).
  struct Carried {
    double mass = 0.0, moment = 0.0;
  };
  std::unordered_map<std::string, Carried> carried_;
  void findCarried();
  bool strict() const { return options_.triangle_policy == dynamics::TrianglePolicy::kRefuse; }
  std::string warnAt(int line) const { return source_ + ":" + std::to_string(line) + ": "; }
  std::map<std::string, TriangleMesh> meshes_;  // by resolved path: each file read once
  std::vector<std::string> warnings_;
};

}  // namespace detail
}  // namespace scene
}  // namespace cga_rigid_sim
