// MidpointResidual (tree_integrator_residual.h): the mass matrix M(q) on the frames of the last
// end pose, and the explicit integrators' stage q̈ = M(q)⁻¹ (τ − b(q, q̇)) on the same constants
// (doc/articulated.md#integrators).
#include <cmath>

#include "tree/tree_integrator_residual.h"
#include "tree/tree_residual_frames.h"

namespace cga_rigid_sim {
namespace dynamics {

void MidpointResidual::massMatrix(Eigen::MatrixXd& M) {
  const int n = joints_;
  M.resize(n, n);
  double* const out = M.data();  // column-major: M(r, c) = out[r + n c]
  // Everything in one frame per subtree hanging from the base: that of its root body (the child
  // of a joint on the base), where entry (j, k) is the pairing ⟨I_c s_k, s_j⟩ of joint k's
  // screw, moved by its subtree's composite inertia, with the screw of joint j, an ancestor —
  // no moment carried joint by joint towards the base (the CRBA's O(n²) frame changes become
  // pairings). The root body's frame (not the world's) keeps every offset within the tree's own
  // size: a tree far from the origin loses no digits.
  Composite* const C = composite_.data();
  for (int k = 0; k < n; ++k) {
    const Joint& j = joint_[k];
    const int b = k + 1;
    Frame& w = root_frame_[b];
    if (j.parent == 0) {
      for (int i = 0; i < 9; ++i) w.R[i] = (i % 4 == 0) ? 1.0 : 0.0;
      w.t[0] = w.t[1] = w.t[2] = 0.0;
    } else {  // x_root = R_p (R x + t) + t_p
      const Frame& wp = root_frame_[j.parent];
      const Frame& f = frame_[b];
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          w.R[3 * r + c] =
              wp.R[3 * r] * f.R[c] + wp.R[3 * r + 1] * f.R[3 + c] + wp.R[3 * r + 2] * f.R[6 + c];
      mul(wp.R, f.t, w.t);
      for (int i = 0; i < 3; ++i) w.t[i] += wp.t[i];
    }
    const double* R = w.R;
    const double* t = w.t;
    // The screw there: (R w, R u + t × R w).
    double* S = root_screw_[k].s;
    mul(R, j.s, S);
    double Ru[3], tw[3];
    mul(R, j.s + 3, Ru);
    cross(t, S, tw);
    for (int i = 0; i < 3; ++i) S[i + 3] = Ru[i] + tw[i];
    // The link's own inertia there, as a composite about the origin: I_o = R diag(J) Rᵀ +
    // m' (t·t 1 − t tᵀ), h = m' t (its centre of mass is its frame's origin).
    double RJR[6];
    math::rotateDiagonal(R, j.J, RJR);
    const double m = j.m2, tt = dot(t, t);
    Composite& cb = C[b];
    cb.I[0] = RJR[0] + m * (tt - t[0] * t[0]);
    cb.I[1] = RJR[1] + m * (tt - t[1] * t[1]);
    cb.I[2] = RJR[2] + m * (tt - t[2] * t[2]);
    cb.I[3] = RJR[3] - m * t[0] * t[1];
    cb.I[4] = RJR[4] - m * t[0] * t[2];
    cb.I[5] = RJR[5] - m * t[1] * t[2];
    for (int i = 0; i < 3; ++i) cb.h[i] = m * t[i];
    cb.m = m;
  }
  // Composites inward: in one frame, a sum.
  for (int b = n; b >= 1; --b) {
    const int p = joint_[b - 1].parent;
    if (p == 0) continue;
    Composite& cp = C[p];
    const Composite& c = C[b];
    for (int i = 0; i < 6; ++i) cp.I[i] += c.I[i];
    for (int i = 0; i < 3; ++i) cp.h[i] += c.h[i];
    cp.m += c.m;
  }
  // Column k: F = I_c s_k = (I_o w + h × u, w × h + m' u), paired with the screws of joint k and
  // its ancestors. Entries off the ancestor chains are zero.
  for (int i = 0; i < n * n; ++i) out[i] = 0.0;
  for (int k = 0; k < n; ++k) {
    const double* s = root_screw_[k].s;
    const Composite& c = C[k + 1];
    const double* I = c.I;
    double F[6], hu[3], wh[3];
    cross(c.h, s + 3, hu);
    cross(s, c.h, wh);
    math::mulSymmetric(I, s, F);
    for (int i = 0; i < 3; ++i) F[i] += hu[i];
    for (int i = 0; i < 3; ++i) F[i + 3] = wh[i] + c.m * s[i + 3];
    out[k + n * k] = dot(F, s) + dot(F + 3, s + 3);
    for (int p = joint_[k].parent; p != 0; p = joint_[p - 1].parent) {
      const double* sp = root_screw_[p - 1].s;
      const double x = dot(F, sp) + dot(F + 3, sp + 3);
      out[k + n * (p - 1)] = x;
      out[(p - 1) + n * k] = x;
    }
  }
}

void MidpointResidual::accelerations(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                     const Eigen::Vector3d& g_W, const Eigen::VectorXd& tau,
                                     Eigen::VectorXd& qdd) {
  const int n = joints_;
  Body* const bodies = body_.data();
  {
    Body& base = bodies[0];
    for (int i = 0; i < 3; ++i) {
      base.w[i] = base.u[i] = base.a[i] = 0.0;
      base.a[i + 3] = -g_W[i] / tree_->lambda();  // (0, −g/λ): gravity as the base's motion
    }
  }
  // Outward: frames, bivelocities Ω_b, the accelerations a_b at q̈ = 0 (A3) and the net moments
  // f_b = I(a_b) − (Ω_b × I(Ω_b)) they need.
  for (int k = 0; k < n; ++k) {
    const Joint& j = joint_[k];
    Body& b = bodies[k + 1];
    const Body& pa = bodies[j.parent];
    Frame& f = frame_[k + 1];
    double* const R = f.R;
    double* const t = f.t;
    if (j.revolute) {
      double sh, ch;
      halfSinCos(0.5 * q[k], sh, ch);
      rodrigues(j, 2.0 * sh * ch, 2.0 * sh * sh, R);
      double Rc[3];
      mul(R, j.c, Rc);
      for (int i = 0; i < 3; ++i) t[i] = j.d[i] - Rc[i];
    } else {
      for (int i = 0; i < 9; ++i) R[i] = j.A[i];
      for (int i = 0; i < 3; ++i) t[i] = j.d[i] + q[k] * j.c[i];
    }
    // X_b = M_bp X_p M̃_bp = (Rᵀ w, Rᵀ (u − t × w)) for Ω and a alike.
    double tw[3], ta[3], pu[3], pau[3];
    cross(t, pa.w, tw);
    cross(t, pa.a, ta);
    for (int i = 0; i < 3; ++i) {
      pu[i] = pa.u[i] - tw[i];
      pau[i] = pa.a[i + 3] - ta[i];
    }
    double w[3], u[3], aw[3], au[3];
    mulT(R, pa.w, w);
    mulT(R, pu, u);
    mulT(R, pa.a, aw);
    mulT(R, pau, au);
    const double vk = v[k];
    const double* s = j.s;
    for (int i = 0; i < 3; ++i) {
      w[i] += vk * s[i];
      u[i] += vk * s[i + 3];
    }
    // + q̇ (s × Ω_b), s × Ω = (−u_s × w, −(u_s × u + m_s × w)) (cga::commutator).
    double sw[3], su[3], mw[3];
    cross(s, w, sw);
    cross(s, u, su);
    cross(s + 3, w, mw);
    for (int i = 0; i < 3; ++i) {
      aw[i] -= vk * sw[i];
      au[i] -= vk * (su[i] + mw[i]);
    }
    // f_b = (J a_w − J w × w, m' a_u − m' u × w) (Inertia::apply, gyroscopic).
    const double Jw[3] = {j.J[0] * w[0], j.J[1] * w[1], j.J[2] * w[2]};
    double Jww[3], uw[3];
    cross(Jw, w, Jww);
    cross(u, w, uw);
    for (int i = 0; i < 3; ++i) {
      b.w[i] = w[i];
      b.u[i] = u[i];
      b.a[i] = aw[i];
      b.a[i + 3] = au[i];
      b.F[i] = j.J[i] * aw[i] - Jww[i];
      b.F[i + 3] = j.m2 * (au[i] - uw[i]);
    }
  }
  // Inward: b_k = ⟨f_k, s⟩ with f_k the subtree's moments in the child's frame; the right-hand
  // side τ − b into qdd.
  qdd.resize(n);
  for (int k = n - 1; k >= 0; --k) {
    const Joint& j = joint_[k];
    Body& b = bodies[k + 1];
    qdd[k] = tau[k] - (dot(b.F, j.s) + dot(b.F + 3, j.s + 3));
    if (j.parent == 0) continue;
    const double* R = frame_[k + 1].R;
    double RF[3], Rt[3], tF[3];
    mul(R, b.F + 3, RF);
    mul(R, b.F, Rt);
    cross(frame_[k + 1].t, RF, tF);
    double* Fp = bodies[j.parent].F;
    for (int i = 0; i < 3; ++i) {
      Fp[i] += Rt[i] + tF[i];
      Fp[i + 3] += RF[i];
    }
  }
  massMatrix(mass_);
  llt_.compute(mass_);
  llt_.solveInPlace(qdd);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
