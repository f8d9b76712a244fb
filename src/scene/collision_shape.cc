#include "cga_rigid_sim/scene/collision_shape.h"

namespace cga_rigid_sim {
namespace scene {

const char* toString(CollisionShape::Kind kind) {
  switch (kind) {
    case CollisionShape::Kind::kBox:
      return "box";
    case CollisionShape::Kind::kSphere:
      return "sphere";
    case CollisionShape::Kind::kCylinder:
      return "cylinder";
    case CollisionShape::Kind::kMesh:
      return "mesh";
  }
  return "unknown";
}

}  // namespace scene
}  // namespace cga_rigid_sim
