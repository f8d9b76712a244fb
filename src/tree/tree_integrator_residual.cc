// MidpointResidual (tree_integrator_residual.h): the midpoint's residual passes for a fixed-base
// tree under gravity, written out on scalars (Eigen's 3×3 products do not unroll at -O2).
#include "tree/tree_integrator_residual.h"

#include <cmath>

#include "cga_rigid_sim/math/mat3.h"
#include "cga_rigid_sim/math/sin_cos.h"

namespace cga_rigid_sim {
namespace dynamics {

namespace {

using math::kHalfPi;  // sinCosReduced's range (a joint within ±π)
using math::sinCosReduced;

// 3×3 kernels on row-major nine numbers (math/mat3.h).
using math::cross;
using math::dot;
using math::mul;
using math::mulT;

// R = R0 + sin q R0[u]× + (1 − cos q) R0[u]×² of a joint, from sq = sin q and vq = 1 − cos q.
template <typename Joint>
inline void rodrigues(const Joint& j, double sq, double vq, double* R) {
  for (int i = 0; i < 9; ++i) R[i] = j.A[i];
  for (int l = 0; l < j.term_count; ++l) {
    const auto& t = j.terms[l];
    R[t.index] += sq * t.b + vq * t.c;
  }
}

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

}  // namespace

bool MidpointResidual::applies(const ArticulatedBody& tree, const TreeLoads& loads) {
  if (tree.floating()) return false;
  for (std::size_t b = 1; b < loads.applied.size(); ++b)
    if (loads.applied[b]) return false;
  return true;
}

void MidpointResidual::prepare(const ArticulatedBody& tree) {
  if (tree_ == &tree && joints_ == tree.jointCount()) return;
  tree_ = &tree;
  joints_ = tree.jointCount();
  const double lambda = tree.lambda();
  joint_.assign(joints_, Joint());
  body_.assign(joints_ + 1, Body());
  frame_.assign(joints_ + 1, Frame());
  root_frame_.assign(joints_ + 1, Frame());
  root_screw_.assign(joints_, Screw());
  composite_.assign(joints_ + 1, Composite());
  sin_half_.assign(joints_, 0.0);
  cos_half_.assign(joints_, 1.0);
  for (int k = 0; k < joints_; ++k) {
    Joint& j = joint_[k];
    const TreeJoint& tj = tree.joints()[k];
    j.revolute = tj.kind == JointKind::kRevolute;
    j.parent = tj.parent;
    const cga::Motor& M0 = tree.childAtZero(k);
    const Eigen::Matrix3d R0 = M0.rotation().toRotationMatrix();
    const Eigen::Vector3d t0 = M0.translation(lambda) / lambda;
    const cga::Bivelocity& s = tree.screwInChild(k);
    for (int i = 0; i < 3; ++i) {
      j.s[i] = s.rot[i];
      j.s[i + 3] = s.trans[i];
    }
    Eigen::Matrix3d B = Eigen::Matrix3d::Zero(), C = Eigen::Matrix3d::Zero();
    Eigen::Vector3d c, d;
    if (j.revolute) {
      Eigen::Matrix3d K;  // [u]×
      K << 0, -s.rot.z(), s.rot.y(), s.rot.z(), 0, -s.rot.x(), -s.rot.y(), s.rot.x(), 0;
      B = R0 * K;
      C = B * K;
      // The motion by π about the line, exp(−½π s) = (u, −m) as quaternions, moves the line's
      // nearest point c to the origin: it translates by 2c.
      const cga::Motor half_turn = cga::Motor::fromQuaternions(
          Eigen::Quaterniond(0.0, s.rot.x(), s.rot.y(), s.rot.z()),
          Eigen::Quaterniond(0.0, -s.trans.x(), -s.trans.y(), -s.trans.z()));
      c = half_turn.translation(lambda) / (2.0 * lambda);
      d = t0 + R0 * c;
    } else {
      c = R0 * s.trans;
      d = t0;
    }
    j.term_count = 0;
    for (int r = 0; r < 3; ++r) {
      j.c[r] = c[r];
      j.d[r] = d[r];
      for (int col = 0; col < 3; ++col) {
        j.A[3 * r + col] = R0(r, col);
        if (B(r, col) != 0.0 || C(r, col) != 0.0)
          j.terms[j.term_count++] = {3 * r + col, B(r, col), C(r, col)};
      }
    }
    // The joint motion's two parts (jointMotor in articulated_body.cc): revolute
    // exp(−½q s) = cos ½q + sin ½q (u, −m), prismatic 1 + q (0, −½m), as (rotor, dual).
    const cga::Motor part =
        j.revolute ? cga::Motor::fromQuaternions(
                         Eigen::Quaterniond(0.0, s.rot.x(), s.rot.y(), s.rot.z()),
                         Eigen::Quaterniond(0.0, -s.trans.x(), -s.trans.y(), -s.trans.z()))
                   : cga::Motor::fromQuaternions(
                         Eigen::Quaterniond(0.0, 0.0, 0.0, 0.0),
                         Eigen::Quaterniond(0.0, -0.5 * s.trans.x(), -0.5 * s.trans.y(),
                                            -0.5 * s.trans.z()));
    const cga::Motor P1 = M0 * part;
    const auto store = [](const cga::Motor& M, double* out) {
      const Eigen::Quaterniond &r = M.rotorQuaternion(), &q = M.dualQuaternion();
      const double c[8] = {r.w(), r.x(), r.y(), r.z(), q.w(), q.x(), q.y(), q.z()};
      for (int i = 0; i < 8; ++i) out[i] = c[i];
    };
    store(M0, j.P0);
    store(P1, j.P1);
    const Inertia& I = tj.inertia;
    for (int i = 0; i < 3; ++i) j.J[i] = I.principalMoments()[i];
    j.m2 = I.mass() * lambda * lambda;
    j.lm = lambda * I.mass();
  }
}

namespace {
// sin and cos of a half angle: sinCosReduced within its range (within 1 ulp of std::sin and
// std::cos, at half the cost; math/sin_cos.h), else the library's.
inline void halfSinCos(double half, double& s, double& c) {
  if (std::abs(half) <= kHalfPi) return sinCosReduced(half, s, c);
  s = std::sin(half);
  c = std::cos(half);
}
}  // namespace

void MidpointResidual::startAt(const Eigen::VectorXd& q) {
  for (int k = 0; k < joints_; ++k) halfSinCos(0.5 * q[k], sin_half_[k], cos_half_[k]);
}

void MidpointResidual::endPose(const Eigen::VectorXd& q, TreeKinematics& kin) {
  const int n = joints_;
  kin.resize(n + 1);
  kin.M_W[0] = cga::Motor();
  for (int k = 0; k < n; ++k) {
    const Joint& j = joint_[k];
    const int b = k + 1;
    Frame& f = frame_[b];
    double* const R = f.R;
    double* const t = f.t;
    double a, c;  // M_pb = a P0 + c P1
    if (j.revolute) {
      double sh, ch;
      halfSinCos(0.5 * q[k], sh, ch);
      sin_half_[k] = sh;
      cos_half_[k] = ch;
      const double sq = 2.0 * sh * ch, vq = 2.0 * sh * sh;
      rodrigues(j, sq, vq, R);
      double Rc[3];
      mul(R, j.c, Rc);
      for (int i = 0; i < 3; ++i) t[i] = j.d[i] - Rc[i];
      a = ch;
      c = sh;
    } else {
      for (int i = 0; i < 9; ++i) R[i] = j.A[i];
      for (int i = 0; i < 3; ++i) t[i] = j.d[i] + q[k] * j.c[i];
      a = 1.0;
      c = q[k];
    }
    const double* P0 = j.P0;
    const double* P1 = j.P1;
    const cga::Motor M = cga::Motor::fromQuaternions(
        Eigen::Quaterniond(a * P0[0] + c * P1[0], a * P0[1] + c * P1[1], a * P0[2] + c * P1[2],
                           a * P0[3] + c * P1[3]),
        Eigen::Quaterniond(a * P0[4] + c * P1[4], a * P0[5] + c * P1[5], a * P0[6] + c * P1[6],
                           a * P0[7] + c * P1[7]));
    kin.M_P[b] = M;
    kin.M_W[b] = kin.M_W[j.parent] * M;
    double* RP = kin.R_P[b].data();  // column-major
    RP[0] = R[0], RP[1] = R[3], RP[2] = R[6];
    RP[3] = R[1], RP[4] = R[4], RP[5] = R[7];
    RP[6] = R[2], RP[7] = R[5], RP[8] = R[8];
    double* tP = kin.t_P[b].data();
    tP[0] = t[0], tP[1] = t[1], tP[2] = t[2];
  }
}

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

void MidpointResidual::velocities(const Eigen::VectorXd& v, TreeKinematics& kin) const {
  kin.omega[0] = cga::Bivelocity();
  for (int k = 0; k < joints_; ++k) {
    const Joint& j = joint_[k];
    const Frame& f = frame_[k + 1];
    const cga::Bivelocity& pa = kin.omega[j.parent];
    // Ω_b = (Rᵀ w, Rᵀ (u − t × w)) + q̇ s.
    const double pw[3] = {pa.rot.x(), pa.rot.y(), pa.rot.z()};
    double pu[3] = {pa.trans.x(), pa.trans.y(), pa.trans.z()}, tw[3], w[3], u[3];
    cross(f.t, pw, tw);
    for (int i = 0; i < 3; ++i) pu[i] -= tw[i];
    mulT(f.R, pw, w);
    mulT(f.R, pu, u);
    const double vk = v[k];
    kin.omega[k + 1] = cga::Bivelocity(
        Eigen::Vector3d(w[0] + vk * j.s[0], w[1] + vk * j.s[1], w[2] + vk * j.s[2]),
        Eigen::Vector3d(u[0] + vk * j.s[3], u[1] + vk * j.s[4], u[2] + vk * j.s[5]));
  }
}

double MidpointResidual::gravityPower() const {
  double power = 0.0;
  for (int k = 0; k < joints_; ++k) {
    const Body& b = body_[k + 1];
    power += joint_[k].lm * dot(b.g, b.u);  // ⟨(0, λ m g_b), Ω_b⟩
  }
  return power;
}

void MidpointResidual::evaluate(const Eigen::VectorXd& q, const Eigen::Vector3d& g_W, double h,
                                const Eigen::VectorXd& nu_bar, Eigen::VectorXd& p,
                                Eigen::VectorXd& gradient) {
  const int n = joints_;
  p.resize(n);
  gradient.resize(n);
  Body* const bodies = body_.data();
  {
    Body& base = bodies[0];
    for (int i = 0; i < 3; ++i) {
      base.g[i] = g_W[i];
      base.w[i] = base.u[i] = 0.0;
    }
  }
  // Outward: frames, gravity, bivelocities, momenta and the external moments.
  for (int k = 0; k < n; ++k) {
    const Joint& j = joint_[k];
    Body& b = bodies[k + 1];
    const Body& pa = bodies[j.parent];
    const double v = nu_bar[k];
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
    mulT(R, pg, g);
    for (int i = 0; i < 3; ++i) {
      w[i] += v * j.s[i];
      u[i] += v * j.s[i + 3];
    }
    for (int i = 0; i < 3; ++i) {
      b.w[i] = w[i];
      b.u[i] = u[i];
      b.g[i] = g[i];
      b.t[i] = t[i];
      b.H[i] = j.J[i] * w[i];
      b.H[i + 3] = j.m2 * u[i];
      b.F[i] = 0.0;
      b.F[i + 3] = j.lm * g[i];
    }
    for (int i = 0; i < 9; ++i) b.R[i] = R[i];
  }
  // Inward: p_k = ⟨H_k, s⟩, ∂L/∂q_k + Q_k = ⟨H_k, s × Ω_b⟩ + ⟨F_k, s⟩ (A7), with
  // s × Ω = commutator(s, Ω) = (−u_s × w, −(u_s × u + m_s × w)).
  for (int k = n - 1; k >= 0; --k) {
    const Joint& j = joint_[k];
    const Body& b = bodies[k + 1];
    const double* s = j.s;
    p[k] = dot(b.H, s) + dot(b.H + 3, s + 3);
    double sw[3], su[3], mw[3];
    cross(s, b.w, sw);
    cross(s, b.u, su);
    cross(s + 3, b.w, mw);
    double g = dot(b.F, s) + dot(b.F + 3, s + 3);
    g -= dot(b.H, sw) + b.H[3] * (su[0] + mw[0]) + b.H[4] * (su[1] + mw[1]) +
         b.H[5] * (su[2] + mw[2]);
    gradient[k] = g;
    if (j.parent != 0) {
      Body& pa = bodies[j.parent];
      addToParent(b.R, b.t, b.H, b.F, pa.H, pa.F);
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
