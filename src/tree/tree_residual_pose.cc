// MidpointResidual (tree_integrator_residual.h): the constants it keeps per tree (each joint's
// frame change as R0, its Rodrigues terms and offsets, the joint motion's two parts, the link's
// inertia), and from them the pose and the velocities at a step's end.
#include <cmath>

#include "tree/tree_integrator_residual.h"
#include "tree/tree_residual_frames.h"

namespace cga_rigid_sim {
namespace dynamics {

void MidpointResidual::prepare(const ArticulatedBody& tree) {
  if (tree_ == &tree && joints_ == tree.jointCount()) return;
  tree_ = &tree;
  // The arrays a step leaves for the next one (the end pose's frames, the sines and cosines of
  // ½q the next step starts from) are made anew only for a tree of another size. An integrator
  // belongs to one tree, which may move in memory (a spawned robot before it deleted,
  // World::deleteBody): its constants below are then recomputed to the same values, and the
  // next step starts from what the last one left, as it would have.
  if (joints_ != tree.jointCount()) {
    joints_ = tree.jointCount();
    body_.assign(joints_ + 1, Body());
    frame_.assign(joints_ + 1, Frame());
    root_frame_.assign(joints_ + 1, Frame());
    root_screw_.assign(joints_, Screw());
    composite_.assign(joints_ + 1, Composite());
    sin_half_.assign(joints_, 0.0);
    cos_half_.assign(joints_, 1.0);
  }
  const double lambda = tree.lambda();
  floating_ = tree.floating();
  if (floating_) {
    const Inertia& I = tree.inertiaOf(0);
    for (int i = 0; i < 3; ++i) base_J_[i] = I.principalMoments()[i];
    base_m2_ = I.mass() * lambda * lambda;
    base_lm_ = lambda * I.mass();
  }
  joint_.assign(joints_, Joint());
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

}  // namespace dynamics
}  // namespace cga_rigid_sim
