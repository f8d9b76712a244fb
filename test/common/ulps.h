// Distance in ulps between a value and its reference, for tests of our elementary functions
// against the C library's (correctly rounded to within an ulp).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace cga_rigid_sim {
namespace testing {

/// |value − reference| in ulps of the reference (below the smallest normal: in units of it).
inline double ulps(double value, double reference) {
  const double ulp =
      std::max(std::abs(std::nextafter(reference, 2.0 * reference + 1.0) - reference),
               std::numeric_limits<double>::denorm_min());
  return std::abs(value - reference) / ulp;
}

}  // namespace testing
}  // namespace cga_rigid_sim
