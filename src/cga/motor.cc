#include "cga_rigid_sim/cga/motor.h"

#include <ostream>

namespace cga_rigid_sim {
namespace cga {

Bivelocity log(const Motor& M) {
  // M and −M are the same rigid motion; take the one with r_w ≥ 0 so the rotation half-angle is
  // at most π/2 (the principal logarithm, rotation angle ≤ π). The other branch would divide by
  // sinc θ → 0 near a full turn and amplify round-off.
  const double sign = M.rotorQuaternion().w() < 0 ? -1.0 : 1.0;
  const Eigen::Quaterniond r(sign * M.rotorQuaternion().coeffs());
  const Eigen::Quaterniond q(sign * M.dualQuaternion().coeffs());
  const double s = r.vec().norm();
  const double theta = std::atan2(s, r.w());
  const double sc = detail::sinc(theta);
  // a = θ â = r_vec / sinc θ.
  const Eigen::Vector3d a = r.vec() / sc;
  // a·b from both parts of q, stable at every θ (no division):
  //   q_w = −(a·b) sinc θ and a·q_vec = (a·b) cos θ  ⇒  a·b = −q_w θ sin θ + (a·q_vec) cos θ.
  const double ab = -q.w() * theta * std::sin(theta) + a.dot(q.vec()) * std::cos(theta);
  // q_vec = (a·b) c(θ) a + sinc θ b  ⇒  b.
  const Eigen::Vector3d b = (q.vec() - (ab * detail::cosMinusSincOverT2(theta)) * a) / sc;
  return Bivelocity(-a, b);
}

std::ostream& operator<<(std::ostream& os, const Motor& M) {
  static const char* const kNames[8] = {"1", "e23", "e31", "e12", "e1n", "e2n", "e3n", "e123n"};
  const auto c = M.coefficients();
  os << "Motor(";
  for (int i = 0; i < 8; ++i) os << (i ? ", " : "") << c[i] << " " << kNames[i];
  return os << ")";
}

}  // namespace cga
}  // namespace cga_rigid_sim
