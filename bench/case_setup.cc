#include "case_setup.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "cga_rigid_sim/cga/bivelocity.h"
#include "cga_rigid_sim/cga/motor.h"

namespace cga_rigid_sim {
namespace benchmark {
namespace {

Eigen::Vector3d vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }
std::array<double, 3> arr(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

CaseSetup setupCase(const ::bench::Case& c, double lambda) {
  auto inertia = dynamics::Inertia::fromPrincipal(c.name, c.mass, vec(c.inertia));
  if (!inertia) {
    std::fprintf(stderr, "case %s: inertia refused: %s\n", c.name.c_str(), inertia.error().c_str());
    std::exit(2);
  }
  CaseSetup s{*inertia, {}, {}, inertia->rotationFromPrincipal(), lambda};

  // Loads: uniform gravity at the CoM; the constant couple keeps its world direction.
  s.loads.setGravity(vec(c.gravity));
  const Eigen::Vector3d tau_W = vec(c.torque_world);
  if (!tau_W.isZero(0.0)) {
    dynamics::AppliedLoad couple;
    couple.axes = dynamics::Axes::kWorld;
    couple.couple = tau_W;
    s.loads.add(couple);
  }

  // Initial state: F = world at t = 0, so R_WB(0) = R_FB; vectors turned by exact matrices.
  const Eigen::Matrix3d R_FB = s.R_FB.toRotationMatrix();
  const Eigen::Vector3d w_B = R_FB.transpose() * vec(c.w0_body);
  const Eigen::Vector3d v_B = R_FB.transpose() * vec(c.v0_world);
  s.state0.M_WB = cga::Motor::fromPose(s.R_FB, Eigen::Vector3d::Zero(), lambda);
  s.state0.omega_B = cga::Bivelocity::fromVelocities(w_B, v_B, lambda);
  return s;
}

::bench::BodyState toCaseState(const CaseSetup& setup, const dynamics::BodyState& s) {
  const Eigen::Quaterniond q_WF = s.M_WB.rotation() * setup.R_FB.conjugate();
  ::bench::BodyState out;
  out.q = {q_WF.w(), q_WF.x(), q_WF.y(), q_WF.z()};
  out.w_world = arr(s.M_WB.transformVector(s.omega_B.angular()));
  out.x = arr(s.M_WB.translation(setup.lambda));
  out.v = arr(s.M_WB.transformVector(s.omega_B.linear(setup.lambda)));
  return out;
}

bool blownUp(const ::bench::Case& c, const ::bench::BodyState& s) {
  for (double v : s.q)
    if (!std::isfinite(v)) return true;
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(s.w_world[i]) || !std::isfinite(s.x[i]) || !std::isfinite(s.v[i]))
      return true;
  return vec(s.w_world).norm() > 1e6 * vec(c.w0_body).norm();
}

}  // namespace benchmark
}  // namespace cga_rigid_sim
