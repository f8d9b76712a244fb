// MidpointResidual (tree_integrator_residual.h): the midpoint's residual passes for a fixed-base
// tree under gravity, written out on scalars (Eigen's 3×3 products do not unroll at -O2).
#include "tree_integrator_residual.h"

#include <cmath>

namespace cga_rigid_sim {
namespace dynamics {

namespace {

// sin x and cos x for |x| ≤ 1/16 from their Taylor polynomials: the first omitted terms,
// x¹¹/11! and x¹²/12!, are below 2e-20 |x| and 8e-24, far under an ulp (and so is the rounding
// of the coefficients, which multiply terms below 7e-4 |x|). No divisions: they would lengthen
// the pass's dependent chains.
constexpr double kSmallAngle = 1.0 / 16.0;
inline void smallSinCos(double x, double& s, double& c) {
  constexpr double s3 = -1.0 / 6, s5 = 1.0 / 120, s7 = -1.0 / 5040, s9 = 1.0 / 362880;
  constexpr double c2 = -0.5, c4 = 1.0 / 24, c6 = -1.0 / 720, c8 = 1.0 / 40320,
                   c10 = -1.0 / 3628800;
  const double x2 = x * x;
  s = x + x * x2 * (s3 + x2 * (s5 + x2 * (s7 + x2 * s9)));
  c = 1.0 + x2 * (c2 + x2 * (c4 + x2 * (c6 + x2 * (c8 + x2 * c10))));
}

// y = R x and y = Rᵀ x for a row-major 3×3 R.
inline void mul(const double* R, const double* x, double* y) {
  y[0] = R[0] * x[0] + R[1] * x[1] + R[2] * x[2];
  y[1] = R[3] * x[0] + R[4] * x[1] + R[5] * x[2];
  y[2] = R[6] * x[0] + R[7] * x[1] + R[8] * x[2];
}
inline void mulT(const double* R, const double* x, double* y) {
  y[0] = R[0] * x[0] + R[3] * x[1] + R[6] * x[2];
  y[1] = R[1] * x[0] + R[4] * x[1] + R[7] * x[2];
  y[2] = R[2] * x[0] + R[5] * x[1] + R[8] * x[2];
}
inline void cross(const double* a, const double* b, double* y) {
  y[0] = a[1] * b[2] - a[2] * b[1];
  y[1] = a[2] * b[0] - a[0] * b[2];
  y[2] = a[0] * b[1] - a[1] * b[0];
}
// R = R0 + sin q R0[u]× + (1 − cos q) R0[u]×² of a joint, from sq = sin q and vq = 1 − cos q.
template <typename Joint>
inline void rodrigues(const Joint& j, double sq, double vq, double* R) {
  for (int i = 0; i < 9; ++i) R[i] = j.A[i];
  for (int l = 0; l < j.term_count; ++l) {
    const auto& t = j.terms[l];
    R[t.index] += sq * t.b + vq * t.c;
  }
}

inline double dot(const double* a, const double* b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
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

void MidpointResidual::startAt(const Eigen::VectorXd& q) {
  for (int k = 0; k < joints_; ++k) {
    sin_half_[k] = std::sin(0.5 * q[k]);
    cos_half_[k] = std::cos(0.5 * q[k]);
  }
}

void MidpointResidual::endPose(const Eigen::VectorXd& q, TreeKinematics& kin) {
  const int n = joints_;
  kin.resize(n + 1);
  kin.M_W[0] = cga::Motor();
  for (int k = 0; k < n; ++k) {
    const Joint& j = joint_[k];
    const int b = k + 1;
    double R[9], t[3], a, c;  // M_pb = a P0 + c P1
    if (j.revolute) {
      const double half = 0.5 * q[k], sh = std::sin(half), ch = std::cos(half);
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
    double m[8];
    for (int i = 0; i < 8; ++i) m[i] = a * j.P0[i] + c * j.P1[i];
    const cga::Motor M = cga::Motor::fromQuaternions(Eigen::Quaterniond(m[0], m[1], m[2], m[3]),
                                                     Eigen::Quaterniond(m[4], m[5], m[6], m[7]));
    kin.M_P[b] = M;
    kin.M_W[b] = kin.M_W[j.parent] * M;
    Eigen::Matrix3d& RP = kin.R_P[b];
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col) RP(r, col) = R[3 * r + col];
    kin.t_P[b] = Eigen::Vector3d(t[0], t[1], t[2]);
  }
}

double MidpointResidual::evaluate(const Eigen::VectorXd& q, const Eigen::Vector3d& g_W, double h,
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
  double power = 0.0;
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
      if (std::abs(x) <= kSmallAngle) {
        double sx, cx;
        smallSinCos(x, sx, cx);
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
    double pw[3], pu[3], pg[3], tw[3];
    for (int i = 0; i < 3; ++i) {
      pw[i] = pa.w[i];
      pu[i] = pa.u[i];
      pg[i] = pa.g[i];
    }
    cross(t, pw, tw);
    for (int i = 0; i < 3; ++i) pu[i] -= tw[i];
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
    power += j.lm * dot(g, u);  // ⟨(0, λ m g_b), Ω_b⟩
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
  return power;
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
