// The three-axis splitting of the free rigid body, written literally with the general motor
// exponential and Eigen rotations: D(h/2) R1(h/2) R2(h/2) R3(h) R2(h/2) R1(h/2) D(h/2), with
//   D(τ):   M ← M exp(−½ τ u∧n)   (Bivelocity(0, −½ τ u)), u = v_B/λ,
//   R_i(τ): φ = τ L_i/J_i, M ← M exp(−½ φ I3 e_i); L_B and u turn by −φ about e_i.
// cga2 used this splitting until it split off the Casimir |L|²/(2 J2) (integrator_cga2.h);
// curved2 still does, and this is its flat limit (curved_limit_test.cc).
#pragma once

#include <Eigen/Geometry>

#include "cga_rigid_sim/body/body_state.h"
#include "cga_rigid_sim/body/inertia.h"
#include "cga_rigid_sim/cga/motor.h"

namespace cga_rigid_sim {
namespace testing {

inline void axisSplittingStep(const dynamics::Inertia& I, double h, dynamics::BodyState& s) {
  const Eigen::Vector3d& J = I.principalMoments();
  Eigen::Vector3d L = J.cwiseProduct(s.omega_B.rot), u = s.omega_B.trans;
  auto drift = [&](double tau) {
    s.M_WB = s.M_WB * cga::exp(cga::Bivelocity(Eigen::Vector3d::Zero(), -0.5 * tau * u));
  };
  auto rotate = [&](int i, double tau) {
    const double phi = tau * L[i] / J[i];
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(i);
    s.M_WB = s.M_WB * cga::exp(cga::Bivelocity(-0.5 * phi * e, Eigen::Vector3d::Zero()));
    const Eigen::AngleAxisd back(-phi, e);
    L = back * L;
    u = back * u;
  };
  drift(0.5 * h);
  rotate(0, 0.5 * h);
  rotate(1, 0.5 * h);
  rotate(2, h);
  rotate(1, 0.5 * h);
  rotate(0, 0.5 * h);
  drift(0.5 * h);
  s.omega_B = cga::Bivelocity(L.cwiseQuotient(J), u);
}

}  // namespace testing
}  // namespace cga_rigid_sim
