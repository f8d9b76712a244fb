// Numbers and names in messages: one way to print them, used by every layer's error and summary
// text.
//
// formatNumber prints like std::ostream with precision `significant_digits` (the default float
// format: fixed or scientific, whichever is shorter, trailing zeros dropped), so 1.1 prints as
// "1.1", 1e-6 as "1e-06" and NaN as "nan". Callers choose the digits their message needs:
// 15 shows any double that was typed in by a user unchanged, 10 shows a rule broken in the 8th
// digit, 6 keeps a summary short.
#pragma once

#include <Eigen/Core>
#include <sstream>
#include <string>

namespace cga_rigid_sim {

/// x with `significant_digits` significant digits.
inline std::string formatNumber(double x, int significant_digits = 15) {
  std::ostringstream os;
  os.precision(significant_digits);
  os << x;
  return os.str();
}

/// 'name': a name as messages quote it.
inline std::string inQuotes(const std::string& s) { return "'" + s + "'"; }

/// "(x, y, z)", each coordinate as formatNumber prints it.
inline std::string formatVector(const Eigen::Vector3d& v, int significant_digits = 15) {
  return "(" + formatNumber(v.x(), significant_digits) + ", " +
         formatNumber(v.y(), significant_digits) + ", " + formatNumber(v.z(), significant_digits) +
         ")";
}

}  // namespace cga_rigid_sim
