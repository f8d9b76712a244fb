// Scene look-ups and the planned integrator path per body.
#include "cga_rigid_sim/scene/scene.h"

#include <algorithm>

#include "cga_rigid_sim/body/at_rest.h"
#include "cga_rigid_sim/body/integrator.h"

namespace cga_rigid_sim {
namespace scene {

int Scene::findBody(const std::string& name) const {
  for (std::size_t k = 0; k < bodies.size(); ++k)
    if (bodies[k].name == name) return static_cast<int>(k);
  return -1;
}

int Scene::findJoint(const std::string& name) const {
  for (std::size_t k = 0; k < joints.size(); ++k)
    if (joints[k].name == name) return static_cast<int>(k);
  return -1;
}

const char* toString(JointType t) {
  switch (t) {
    case JointType::kRevolute:
      return "revolute";
    case JointType::kContinuous:
      return "continuous";
    case JointType::kPrismatic:
      return "prismatic";
  }
  return "?";
}

int Scene::findLink(const std::string& link, int* link_index) const {
  for (std::size_t k = 0; k < bodies.size(); ++k)
    for (std::size_t i = 0; i < bodies[k].links.size(); ++i)
      if (bodies[k].links[i].link == link) {
        if (link_index) *link_index = static_cast<int>(i);
        return static_cast<int>(k);
      }
  return -1;
}

const std::vector<std::string>& summaryIntegratorNames() { return dynamics::integratorNames(); }

std::string plannedIntegratorPath(const Scene& scene, const BodyModel& body,
                                  const std::string& integrator) {
  if (body.is_static) return "static";
  const auto& names = summaryIntegratorNames();
  if (std::find(names.begin(), names.end(), integrator) == names.end()) return "unknown";
  if (integrator != "auto") return integrator;
  // Uniform gravity acts at the centre of mass: it changes no rotation, so it leaves the
  // torque-free paths exact (the centre of mass follows its parabola in closed form).
  if (dynamics::isAtRest(!scene.gravity_W.isZero(0.0), body.omega_B0)) return "at-rest";
  return std::string("exact-") + dynamics::toString(body.inertia->inertiaClass());
}

}  // namespace scene
}  // namespace cga_rigid_sim
