// control_toolbox's integral term (pid_integral.h).
#include "cga_rigid_sim/control/pid_integral.h"

#include <algorithm>
#include <cmath>

namespace cga_rigid_sim {
namespace control {

double PidIntegral::accumulate(double error, double dt, const PidGains& gains) {
  integral_ += dt * error;
  if (gains.antiwindup && gains.i != 0) {
    const double k = std::abs(gains.i);
    integral_ = std::clamp(integral_, gains.i_clamp_min / k, gains.i_clamp_max / k);
  }
  return term(gains);
}

double PidIntegral::term(const PidGains& gains) const {
  return std::clamp(gains.i * integral_, gains.i_clamp_min, gains.i_clamp_max);
}

}  // namespace control
}  // namespace cga_rigid_sim
