// MidpointResidual (tree_integrator_residual.h): the midpoint's residual passes for a fixed-base
// tree under gravity, written out on scalars (Eigen's 3×3 products do not unroll at -O2). The
// tree's constants and the end pose: tree_residual_pose.cc; the mass matrix and the explicit
// stage: tree_residual_dynamics.cc.
#include "tree/tree_integrator_residual.h"

#include <cmath>

#include "tree/tree_residual_frames.h"

namespace cga_rigid_sim {
namespace dynamics {

namespace {

// Adds M_pb T M̃_pb (a trivector of the child carried to the parent, tree_math::toParent) to
// the parent's, for the two trivectors H and F at once.
inline void addToParent(const double* R, const double* t, const double* H, const double* F,
                        double* Hp, double* Fp) {
  double RHf[3], RH[3], RFf[3], RF[3], tH[3], tF[3];
  mul(R, H + 3, RHf);
  mul(R, H, RH);
  mul(R, F + 3, RFf);
  mul(R, F, RF);
  cross(t, RHf, tH);
  cross(t, RFf, tF);
  for (int i = 0; i < 3; ++i) {
    Hp[i] += RH[i] + tH[i];
    Hp[i + 3] += RHf[i];
    Fp[i] += RF[i] + tF[i];
    Fp[i + 3] += RFf[i];
  }
}

// The same for H alone (no external moments: a floating base's drift).
inline void addToParent(const double* R, const double* t, const double* H, double* Hp) {
  double RHf[3], RH[3], tH[3];
  mul(R, H + 3, RHf);
  mul(R, H, RH);
  cross(t, RHf, tH);
  for (int i = 0; i < 3; ++i) {
    Hp[i] += RH[i] + tH[i];
    Hp[i + 3] += RHf[i];
  }
}

}  // namespace

bool MidpointResidual::applies(const ArticulatedBody& tree, const TreeLoads& loads) {
  // A floating base only without gravity: its world wrench W would need the links' world poses.
  if (tree.floating() && !loads.gravity_W.isZero(0.0)) return false;
  for (std::size_t b = tree.floating() ? 0 : 1; b < loads.applied.size(); ++b)
    if (loads.applied[b]) return false;
  return true;
}

void MidpointResidual::startAt(const Eigen::VectorXd& q) {
  for (int k = 0; k < joints_; ++k) halfSinCos(0.5 * q[k], sin_half_[k], cos_half_[k]);
}

double MidpointResidual::gravityPower() const {
  if (floating_) return 0.0;  // (no gravity: applies())
  double power = 0.0;
  for (int k = 0; k < joints_; ++k) {
    const Body& b = body_[k + 1];
    power += joint_[k].lm * dot(b.g, b.u);  // ⟨(0, λ m g_b), Ω_b⟩
  }
  return power;
}

void MidpointResidual::evaluate(const Eigen::VectorXd& q, const Eigen::Vector3d& g, double h,
                                const Eigen::VectorXd& nu_bar, Eigen::VectorXd& p,
                                Eigen::VectorXd& gradient) {
  if (floating_)
    passes<true>(q, g, h, nu_bar, p, gradient);
  else
    passes<false>(q, g, h, nu_bar, p, gradient);
}

// The passes of evaluate(). Floating: the base's own bivelocity is ν̄'s first six entries, its
// momentum gathers the links' and is the first six of p, and there is no gravity (applies()):
// no external moments are carried.
template <bool Floating>
inline void MidpointResidual::passes(const Eigen::VectorXd& q, const Eigen::Vector3d& g_0, double h,
                                     const Eigen::VectorXd& nu_bar, Eigen::VectorXd& p,
                                     Eigen::VectorXd& gradient) {
  constexpr bool kGravity = !Floating;
  const int n = joints_, off = Floating ? 6 : 0;
  p.resize(n + off);
  gradient.resize(n);
  Body* const bodies = body_.data();
  {
    Body& base = bodies[0];
    for (int i = 0; i < 3; ++i) {
      if (kGravity) base.g[i] = g_0[i];
      base.w[i] = Floating ? nu_bar[i] : 0.0;
      base.u[i] = Floating ? nu_bar[i + 3] : 0.0;
    }
    if (Floating)
      for (int i = 0; i < 3; ++i) {
        base.H[i] = base_J_[i] * base.w[i];
        base.H[i + 3] = base_m2_ * base.u[i];
      }
  }
  // Outward: frames, gravity, bivelocities, momenta and the external moments.
  for (int k = 0; k < n; ++k) {
    const Joint& j = joint_[k];
    Body& b = bodies[k + 1];
    const Body& pa = bodies[j.parent];
    const double v = nu_bar[off + k];
    double R[9], t[3];
    if (j.revolute) {
      // sin, cos of ½q̄ = ½q + ¼h q̄̇; then sin q̄ = 2 sin cos, 1 − cos q̄ = 2 sin².
      const double x = 0.25 * h * v;
      double sh, ch;
      if (std::abs(x) <= math::kSinCosSmallLimit) {
        double sx, cx;
        math::sinCosSmall(x, sx, cx);
        sh = sin_half_[k] * cx + cos_half_[k] * sx;
        ch = cos_half_[k] * cx - sin_half_[k] * sx;
      } else {
        const double half = 0.5 * (q[k] + 0.5 * h * v);
        sh = std::sin(half);
        ch = std::cos(half);
      }
      const double sq = 2.0 * sh * ch, vq = 2.0 * sh * sh;
      rodrigues(j, sq, vq, R);
      double Rc[3];
      mul(R, j.c, Rc);
      for (int i = 0; i < 3; ++i) t[i] = j.d[i] - Rc[i];
    } else {
      const double qm = q[k] + 0.5 * h * v;
      for (int i = 0; i < 9; ++i) R[i] = j.A[i];
      for (int i = 0; i < 3; ++i) t[i] = j.d[i] + qm * j.c[i];
    }
    // Ω_b = M_bp Ω_p M̃_bp + q̄̇ s = (Rᵀ w, Rᵀ (u − t × w)) + q̄̇ s; g_b = Rᵀ g_p.
    const double* pw = pa.w;
    const double* pg = pa.g;
    double pu[3], tw[3];
    cross(t, pw, tw);
    for (int i = 0; i < 3; ++i) pu[i] = pa.u[i] - tw[i];
    double w[3], u[3], g[3];
    mulT(R, pw, w);
    mulT(R, pu, u);
    if (kGravity) mulT(R, pg, g);
    for (int i = 0; i < 3; ++i) {
      w[i] += v * j.s[i];
      u[i] += v * j.s[i + 3];
    }
    for (int i = 0; i < 3; ++i) {
      b.w[i] = w[i];
      b.u[i] = u[i];
      b.t[i] = t[i];
      b.H[i] = j.J[i] * w[i];
      b.H[i + 3] = j.m2 * u[i];
      if (kGravity) {
        b.g[i] = g[i];
        b.F[i] = 0.0;
        b.F[i + 3] = j.lm * g[i];
      }
    }
    for (int i = 0; i < 9; ++i) b.R[i] = R[i];
  }
  // Inward: p_k = ⟨H_k, s⟩, ∂L/∂q_k + Q_k = ⟨H_k, s × Ω_b⟩ + ⟨F_k, s⟩ (A7), with
  // s × Ω = commutator(s, Ω) = (−u_s × w, −(u_s × u + m_s × w)).
  for (int k = n - 1; k >= 0; --k) {
    const Joint& j = joint_[k];
    const Body& b = bodies[k + 1];
    const double* s = j.s;
    p[off + k] = dot(b.H, s) + dot(b.H + 3, s + 3);
    double sw[3], su[3], mw[3];
    cross(s, b.w, sw);
    cross(s, b.u, su);
    cross(s + 3, b.w, mw);
    double g = kGravity ? dot(b.F, s) + dot(b.F + 3, s + 3) : 0.0;
    g -= dot(b.H, sw) + b.H[3] * (su[0] + mw[0]) + b.H[4] * (su[1] + mw[1]) +
         b.H[5] * (su[2] + mw[2]);
    gradient[k] = g;
    if (Floating) {
      addToParent(b.R, b.t, b.H, bodies[j.parent].H);
    } else if (j.parent != 0) {
      Body& pa = bodies[j.parent];
      addToParent(b.R, b.t, b.H, b.F, pa.H, pa.F);
    }
  }
  if (Floating)
    for (int i = 0; i < 6; ++i) p[i] = bodies[0].H[i];
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
