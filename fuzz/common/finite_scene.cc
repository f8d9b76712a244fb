#include "common/finite_scene.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace cga_rigid_sim {
namespace fuzz {

void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz check failed: %s\n", what.c_str());
  std::abort();
}

void checkSceneFinite(const scene::Scene& scene, const std::string& what) {
  for (const scene::BodyModel& body : scene.bodies) {
    const std::string b = what + ": body '" + body.name + "'";
    if (!body.M_WB0.allFinite()) fail(b + ": initial pose not finite");
    if (!body.omega_B0.allFinite()) fail(b + ": initial bivelocity not finite");
    if (!body.is_static && !body.inertia) fail(b + ": moving body without inertia");
    if (body.inertia) {
      const dynamics::Inertia& I = *body.inertia;
      if (!std::isfinite(I.mass()) || !(I.mass() > 0.0)) fail(b + ": mass not finite and > 0");
      if (!I.principalMoments().allFinite()) fail(b + ": principal moments not finite");
      if (!I.rotationFromPrincipal().coeffs().allFinite()) fail(b + ": principal axes not finite");
    }
    for (const scene::LinkFrame& link : body.links)
      if (!link.M_BL.allFinite()) fail(b + ": link '" + link.link + "' placement not finite");
    for (const scene::CollisionShape& shape : body.shapes) {
      if (!shape.M_BS.allFinite()) fail(b + ": shape '" + shape.name + "' pose not finite");
      if (!shape.size.allFinite() || !std::isfinite(shape.radius) || !std::isfinite(shape.length))
        fail(b + ": shape '" + shape.name + "' size not finite");
      for (const Eigen::Vector3d& v : shape.mesh.vertices)
        if (!v.allFinite()) fail(b + ": shape '" + shape.name + "' mesh vertex not finite");
    }
  }
  for (const scene::JointModel& joint : scene.joints)
    if (!std::isfinite(joint.initial_position) || !std::isfinite(joint.initial_velocity))
      fail(what + ": joint '" + joint.name + "' initial state not finite");
}

}  // namespace fuzz
}  // namespace cga_rigid_sim
