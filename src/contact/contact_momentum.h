// The world-axes momentum a body in contact carries from one contact step to the next
// (MovingBodyData::ContactMomentum, doc/contacts.md#world-momentum): its centre's velocity v_W
// and its angular momentum about the centre L_W, each a compensated sum hi + lo. Both are
// constant over the torque-free drift of the splitting, so the kick's gravity and the contact
// impulses are added to them where they act (world axes, where a resting body's weight and
// normal impulse cancel exactly), and Ω_B is only read off them, never carried: the roundings
// of the body-axes conversion stay in the step that made them.
#pragma once

#include <Eigen/Geometry>

#include "cga_rigid_sim/body/derived.h"
#include "cga_rigid_sim/body/inertia.h"
#include "cga_rigid_sim/sim/data.h"

namespace cga_rigid_sim {
namespace sim {

/// hi + lo += x, with the rounding of hi + x kept in lo (Knuth's TwoSum, exact for any
/// magnitudes): the sum of n increments is then off by ~ε (Σ |x|) / 2^53 rather than n ε / 2.
inline void addCompensated(Eigen::Vector3d& hi, Eigen::Vector3d& lo, const Eigen::Vector3d& x) {
  for (int k = 0; k < 3; ++k) {
    const double s = hi[k] + x[k];
    const double b = s - hi[k];
    lo[k] += (hi[k] - (s - b)) + (x[k] - b);
    hi[k] = s;
  }
}

/// Whether b's carried momentum is still its state's: the drift that set it left this Ω_B and
/// this attitude, bit for bit (an input, an edit, sleep or a free step changes one of them).
inline bool carriesMomentum(const MovingBodyData& b) {
  const MovingBodyData::ContactMomentum& m = b.contact_momentum;
  return m.valid && m.key_omega_B.rot == b.state.omega_B.rot &&
         m.key_omega_B.trans == b.state.omega_B.trans &&
         m.key_r == b.state.M_WB.rotation().coeffs();
}

/// The momentum of a state: v_W = R v_B, L_W = R (J ∘ w_B) (body/derived.h); lo = 0.
inline MovingBodyData::ContactMomentum stateMomentum(const dynamics::Inertia& I,
                                                     const dynamics::BodyState& s, double lambda) {
  MovingBodyData::ContactMomentum m;
  m.v_hi = dynamics::comVelocity_W(s, lambda);
  m.L_hi = dynamics::angularMomentumCom_W(I, s);
  return m;
}

/// The momentum b starts a contact step with: the carried one, or its state's.
inline MovingBodyData::ContactMomentum startMomentum(const dynamics::Inertia& I,
                                                     const MovingBodyData& b, double lambda) {
  return carriesMomentum(b) ? b.contact_momentum : stateMomentum(I, b.state, lambda);
}

/// The centre's velocity of a momentum, world axes.
inline Eigen::Vector3d velocity_W(const MovingBodyData::ContactMomentum& m) {
  return m.v_hi + m.v_lo;
}

/// Ω_B of a momentum at attitude R: w_B = J⁻¹ ∘ (R̃ L_W), v_B = R̃ v_W.
inline cga::Bivelocity bodyVelocity(const dynamics::Inertia& I, const Eigen::Quaterniond& R,
                                    const MovingBodyData::ContactMomentum& m, double lambda) {
  const Eigen::Quaterniond Rt = R.conjugate();
  const Eigen::Vector3d L_B = Rt * (m.L_hi + m.L_lo);
  return cga::Bivelocity::fromVelocities(L_B.cwiseQuotient(I.principalMoments()),
                                         Rt * velocity_W(m), lambda);
}

}  // namespace sim
}  // namespace cga_rigid_sim
