// The integral term of control_toolbox's Pid (ROS 1), which ros_control's controllers and
// gazebo_ros_control use: ∫e accumulated by the rectangle rule, its term i·∫e clamped to
// [i_clamp_min, i_clamp_max]. Without antiwindup the integral itself keeps growing past the clamp
// (and must unwind before the term leaves it); with antiwindup the integral is clamped so that
// its term stays inside (doc/control.md#pid).
#pragma once

namespace cga_rigid_sim {
namespace control {

struct PidGains {
  double p = 0;
  double i = 0;
  double d = 0;
  double i_clamp_min = 0;  ///< ≤ 0: lower bound of the term i·∫e (control_toolbox: −|value|)
  double i_clamp_max = 0;  ///< ≥ 0: upper bound of the term i·∫e
  bool antiwindup = false;
};

class PidIntegral {
 public:
  /// Adds e·dt to ∫e (then, with antiwindup, clamps ∫e to the bounds divided by |i|) and returns
  /// the term i·∫e clamped to [i_clamp_min, i_clamp_max].
  double accumulate(double error, double dt, const PidGains& gains);
  /// The term i·∫e clamped, without accumulating.
  double term(const PidGains& gains) const;
  /// ∫e (s times the error's unit).
  double integral() const { return integral_; }
  void reset() { integral_ = 0; }

 private:
  double integral_ = 0;
};

}  // namespace control
}  // namespace cga_rigid_sim
