// Internal to the node's conversions (conversions.h): the error for a message field that is not
// finite, in the text World's own refusals use.
#pragma once

#include <string>

#include "cga_rigid_sim/result.h"

namespace cga_rigid_sim {
namespace node {

inline Error notFinite(const std::string& field) {
  return Error{field + ": not finite (NaN or Inf)"};
}

}  // namespace node
}  // namespace cga_rigid_sim
