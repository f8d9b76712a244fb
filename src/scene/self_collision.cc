// The self-collision modes' names (self_collision.h).
#include "cga_rigid_sim/scene/self_collision.h"

namespace cga_rigid_sim {
namespace scene {

const char* toString(SelfCollisionMode mode) {
  switch (mode) {
    case SelfCollisionMode::kAuto:
      return "auto";
    case SelfCollisionMode::kAll:
      return "all";
    case SelfCollisionMode::kNone:
      return "none";
  }
  return "auto";
}

std::optional<SelfCollisionMode> parseSelfCollisionMode(const std::string& text) {
  for (SelfCollisionMode m :
       {SelfCollisionMode::kAuto, SelfCollisionMode::kAll, SelfCollisionMode::kNone})
    if (text == toString(m)) return m;
  return std::nullopt;
}

}  // namespace scene
}  // namespace cga_rigid_sim
