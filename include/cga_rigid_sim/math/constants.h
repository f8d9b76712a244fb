// π, once: the double nearest π and, for argument reductions that must add no error of their
// own, the rest π − fl(π) (so x − k π = (x − k fl(π)) − k (π − fl(π)) to a rounding).
// Every multiple by a power of two (π/2, π/4, 2π and their rests) is exact.
#pragma once

namespace cga_rigid_sim {
namespace math {

constexpr double kPi = 3.141592653589793;         ///< fl(π) (= M_PI = std::acos(-1.0))
constexpr double kPiLo = 1.2246467991473532e-16;  ///< π − fl(π), rounded
constexpr double kHalfPi = 0.5 * kPi;
constexpr double kHalfPiLo = 0.5 * kPiLo;
constexpr double kQuarterPi = 0.25 * kPi;
constexpr double kTwoPi = 2.0 * kPi;
constexpr double kTwoPiLo = 2.0 * kPiLo;

}  // namespace math
}  // namespace cga_rigid_sim
