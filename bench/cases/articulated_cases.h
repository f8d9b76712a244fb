// Articulated benchmark cases (doc/benchmarks-articulated.md): trees of revolute joints on a
// fixed base (the world) or on a floating base (a free root body), the same description for
// every engine, and the engine-independent pieces of the metrics (kinematics, energy,
// equations of motion for the reference solution).
//
// Header-only so that the peer runners (bench/peers/articulated_<engine>.cc), the reference
// (articulated_reference.cc) and our own runner (bench/articulated.cc) share it without a link
// dependency.
//
// Model. Joint i moves link i. Its joint frame J_i sits in the frame of link parent(i) (or, for
// parent = -1, in the world or the floating base) at (R_i, p_i) = (origin_R, origin_xyz); at
// q_i = 0 the link frame is
// J_i, and the joint turns the link about the unit `axis` (in J_i, = in the link frame) by q_i:
//   R_link(i) = R_link(parent) R_i Rot(axis_i, q_i),   x_link(i) = x_link(parent) + R_link(parent)
//   p_i.
// Each link carries a mass at `com` (link frame) with a diagonal inertia about the CoM in link
// axes. This is exactly the URDF's joint <origin>, <axis> and <inertial> (rpy = 0 everywhere but
// the arm's ceiling mount, which is folded into joint1's origin here). The numbers are the
// URDF's literals (urdf/double_pendulum.urdf, urdf/arm7.urdf), so that a simulator reading the
// URDF gets bit-identical parameters; bench_articulated_reference checks the two agree.
//
// A floating base (BaseSpec) is the root link of the URDF: it starts at the identity pose with
// the velocities of BaseSpec (world axes; the velocity is that of the base frame's origin).
// Its state is (R_b, p_b, w_b, v_b), world frame.
//
// Energy. E = kinetic + V(q) - V(0), V = -sum m g.x_com: the potential is measured from q = 0
// (the hanging configuration of the fixed-base cases; base at the identity), so that |E(0)| is
// the energy of the motion and not an arbitrary offset set by the height of the pivot.
// Relative drift = max_t |E(t) - E(0)| / E(0).
#pragma once

#include <Eigen/Core>
#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace bench {
namespace articulated {

constexpr double kG = 9.81;

struct JointSpec {
  std::string joint, link;  // URDF names
  int parent = -1;          // index of the parent joint's link; -1: the base (world or floating)
  std::array<double, 3> origin_xyz{0, 0, 0};  // joint frame in the parent link's frame
  std::array<double, 9> origin_R{1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major, parent -> joint frame
  std::array<double, 3> axis{0, 1, 0};                        // unit, in the joint (= link) frame
  double mass = 1;
  std::array<double, 3> com{0, 0, 0};           // link frame
  std::array<double, 3> inertia_diag{1, 1, 1};  // about the CoM, link axes (kg m^2)
  double limit = 0;  // |q| limit of the URDF (rad), 0: continuous; not enforced by the benchmark
};

// A floating base: the URDF's root link as a free body. Absent (floating = false): the base is
// the world.
struct BaseSpec {
  bool floating = false;
  std::string link;
  double mass = 0;
  std::array<double, 3> com{0, 0, 0};           // base frame
  std::array<double, 3> inertia_diag{0, 0, 0};  // about the CoM, base axes
  std::array<double, 3> w0{0, 0, 0};            // initial angular velocity, world (= base axes)
  std::array<double, 3> v0{0, 0, 0};            // initial velocity of the base frame origin, world
};

struct ArticulatedCase {
  std::string name;
  std::string urdf;  // relative to the repository root
  BaseSpec base;
  std::vector<JointSpec> joints;  // parents before children
  std::vector<double> q0, qd0;    // rad, rad/s
  std::array<double, 3> gravity{0, 0, -kG};
  double T = 1;  // end time (s)
  int n() const { return static_cast<int>(joints.size()); }
};

// Two identical rods (1 kg, 1 m, radius 0.02 m, solid cylinders) on axes y, pivot at z = 2.
inline ArticulatedCase doublePendulum() {
  ArticulatedCase c;
  c.name = "double_pendulum";
  c.urdf = "urdf/double_pendulum.urdf";
  JointSpec rod;
  rod.axis = {0, 1, 0};
  rod.mass = 1.0;
  rod.com = {0, 0, -0.5};
  rod.inertia_diag = {0.08343333333333333, 0.08343333333333333, 0.0002};
  JointSpec shoulder = rod, elbow = rod;
  shoulder.joint = "shoulder";
  shoulder.link = "upper";
  shoulder.parent = -1;
  shoulder.origin_xyz = {0, 0, 2};
  elbow.joint = "elbow";
  elbow.link = "lower";
  elbow.parent = 0;
  elbow.origin_xyz = {0, 0, -1};
  c.joints = {shoulder, elbow};
  c.q0 = {1.0, 0.5};
  c.qd0 = {0.0, 0.0};
  c.T = 10.0;
  return c;
}

// The ceiling-mounted 7-DoF arm of urdf/arm7.urdf. world -> base_link: z = 2, rpy (pi, 0, 0)
// with pi written as 3.141592653589793, the double nearest pi, so R = Rot_x(fl(pi)): diag(1, -1,
// -1) but for R_zy = -R_yz = sin(fl(pi)) = 1.2246e-16, which is what a URDF reader computes
// (urdfdom: the quaternion (cos, sin) of the half angle, 2 cos(fl(pi)/2) = sin(fl(pi)) in
// doubles). Writing diag(1, -1, -1) here instead made the truth and the peers solve a problem
// 1.2e-16 rad away from ours: the arm's motion amplifies that tilt of gravity to 1.8e-13 rad in
// 2 s, which was the floor of our errors at small h. joint1 at (0, 0, 0.15) in base_link, so in
// the world at (0, -0.15 sin(fl(pi)), 1.85).
inline ArticulatedCase arm7() {
  ArticulatedCase c;
  c.name = "arm7";
  c.urdf = "urdf/arm7.urdf";
  struct Row {
    double z_origin;  // joint origin along the parent link's z
    std::array<double, 3> axis;
    double mass;
    std::array<double, 3> com;
    double ixx, izz;
    double limit;  // the URDF's literal (rad): 170, 120, 170, 120, 170, 120, 175 deg
  };
  const Row rows[7] = {
      {0.15, {0, 0, 1}, 3.5, {0, 0.01, 0.1}, 0.01595416667, 0.008575, 2.967059728},
      {0.2, {0, 1, 0}, 3.5, {0.005, 0, 0.14}, 0.02656354167, 0.00739375, 2.094395102},
      {0.28, {0, 0, 1}, 3.0, {0, -0.008, 0.14}, 0.0223, 0.0054, 2.967059728},
      {0.28, {0, -1, 0}, 3.0, {-0.005, 0.005, 0.14}, 0.0223, 0.0054, 2.094395102},
      {0.28, {0, 0, 1}, 2.0, {0, 0.006, 0.1}, 0.007916666667, 0.0025, 2.967059728},
      {0.2, {0, 1, 0}, 1.5, {0.004, 0, 0.05}, 0.002009375, 0.00151875, 2.094395102},
      {0.1, {0, 0, 1}, 1.5, {0, 0, 0.03}, 0.00105, 0.0012, 3.054326191},
  };
  for (int i = 0; i < 7; ++i) {
    JointSpec j;
    j.joint = "joint" + std::to_string(i + 1);
    j.link = "link" + std::to_string(i + 1);
    j.parent = i - 1;
    j.origin_xyz = {0, 0, rows[i].z_origin};
    if (i == 0) {  // the ceiling mount folded in
      const double s = std::sin(3.141592653589793);
      j.origin_xyz = {0, -s * rows[i].z_origin, 2.0 - rows[i].z_origin};
      j.origin_R = {1, 0, 0, 0, -1, -s, 0, s, -1};
    }
    j.axis = rows[i].axis;
    j.mass = rows[i].mass;
    j.com = rows[i].com;
    j.inertia_diag = {rows[i].ixx, rows[i].ixx, rows[i].izz};
    j.limit = rows[i].limit;
    c.joints.push_back(j);
  }
  // A posture away from every symmetry (all joints off zero), at rest, E0 = 9.9 J above the
  // hanging posture. Under gravity the arm swings and its roll joints (1, 3, 5, 7: tiny inertia
  // about their axes, nothing holding them) wind up to ~5 rad/s, but every joint stays inside
  // 0.6 of its limit over T = 2 s (bench_articulated_reference prints the ranges). Larger
  // postures make the roll joints whip through many turns (> 50 rad/s) and leave the limits.
  c.q0 = {-0.3, -0.4, 0.4, 0.2, -0.5, -0.2, 0.4};
  c.qd0.assign(7, 0.0);
  c.T = 2.0;
  return c;
}

// urdf/satellite.urdf in free space: a 100 kg cubic bus with two 10 kg panels on hinges about
// the bus's y. The bus spins about z (its axis of largest inertia with the panels out) and
// wobbles a little; the panels start folded by 0.4 and -0.3 rad and at rest relative to the bus.
// The spin's centrifugal pull swings them about their flat position, through +-0.4 rad, inside
// their +-pi/2 limits (bench_articulated_reference prints the ranges).
inline ArticulatedCase satellite() {
  ArticulatedCase c;
  c.name = "satellite";
  c.urdf = "urdf/satellite.urdf";
  c.gravity = {0, 0, 0};
  c.base.floating = true;
  c.base.link = "bus";
  c.base.mass = 100.0;
  c.base.com = {0, 0, 0};
  c.base.inertia_diag = {16.666666666666668, 16.666666666666668, 16.666666666666668};
  c.base.w0 = {0.05, 0.1, 1.0};
  c.base.v0 = {0, 0, 0};
  JointSpec panel;
  panel.axis = {0, 1, 0};
  panel.mass = 10.0;
  panel.inertia_diag = {0.5336666666666667, 3.333666666666667, 3.8666666666666667};
  panel.limit = 1.5707963267948966;
  JointSpec right = panel, left = panel;
  right.joint = "hinge_right";
  right.link = "panel_right";
  right.origin_xyz = {0.52, 0, 0};
  right.com = {1, 0, 0};
  left.joint = "hinge_left";
  left.link = "panel_left";
  left.origin_xyz = {-0.52, 0, 0};
  left.com = {-1, 0, 0};
  c.joints = {right, left};
  c.q0 = {0.4, -0.3};
  c.qd0 = {0.0, 0.0};
  c.T = 10.0;
  return c;
}

inline std::vector<ArticulatedCase> allArticulatedCases() {
  return {doublePendulum(), arm7(), satellite()};
}

// Angle difference wrapped to (-pi, pi] (ODE reports hinge angles wrapped).
template <class S>
S wrapAngle(S a) {
  using std::atan2;
  using std::cos;
  using std::sin;
  return atan2(sin(a), cos(a));
}

// The state of a floating base (world frame); for a fixed base it stays the identity at rest.
template <class S>
struct BaseState {
  Eigen::Matrix<S, 3, 3> R = Eigen::Matrix<S, 3, 3>::Identity();
  Eigen::Matrix<S, 3, 1> p = Eigen::Matrix<S, 3, 1>::Zero();
  Eigen::Matrix<S, 3, 1> w = Eigen::Matrix<S, 3, 1>::Zero();
  Eigen::Matrix<S, 3, 1> v = Eigen::Matrix<S, 3, 1>::Zero();  // of the base frame origin
};

// World poses and velocities of all links (and of the base, when it floats), and the pieces the
// dynamics needs.
template <class S>
struct Kinematics {
  using V3 = Eigen::Matrix<S, 3, 1>;
  using M3 = Eigen::Matrix<S, 3, 3>;
  std::vector<M3> R;                             // link orientation (world)
  std::vector<V3> x;                             // link frame origin = joint position (world)
  std::vector<V3> z;                             // joint axis (world)
  std::vector<V3> c;                             // CoM (world)
  std::vector<V3> w;                             // angular velocity (world)
  std::vector<V3> vc;                            // CoM velocity (world)
  std::vector<M3> Iw;                            // inertia about the CoM, world axes
  BaseState<S> base;                             // the base's state as given
  V3 base_c = V3::Zero(), base_vc = V3::Zero();  // floating base: CoM and its velocity
  M3 base_Iw = M3::Zero();                       // floating base: inertia about its CoM, world
};

template <class S>
Eigen::Matrix<S, 3, 3> axisRotation(const Eigen::Matrix<S, 3, 1>& a, S q) {
  using std::cos;
  using std::sin;
  Eigen::Matrix<S, 3, 3> K;
  K << S(0), -a(2), a(1), a(2), S(0), -a(0), -a(1), a(0), S(0);
  return Eigen::Matrix<S, 3, 3>::Identity() + sin(q) * K + (S(1) - cos(q)) * K * K;
}

template <class S>
Eigen::Matrix<S, 3, 1> vec3(const std::array<double, 3>& a) {
  return Eigen::Matrix<S, 3, 1>(S(a[0]), S(a[1]), S(a[2]));
}

template <class S>
Kinematics<S> kinematics(const ArticulatedCase& cs, const BaseState<S>& base, const S* q,
                         const S* qd) {
  using V3 = Eigen::Matrix<S, 3, 1>;
  using M3 = Eigen::Matrix<S, 3, 3>;
  const int n = cs.n();
  Kinematics<S> k;
  k.R.resize(n);
  k.x.resize(n);
  k.z.resize(n);
  k.c.resize(n);
  k.w.resize(n);
  k.vc.resize(n);
  k.Iw.resize(n);
  k.base = base;
  if (cs.base.floating) {
    const V3 rc = base.R * vec3<S>(cs.base.com);
    k.base_c = base.p + rc;
    k.base_vc = base.v + base.w.cross(rc);
    k.base_Iw = base.R * vec3<S>(cs.base.inertia_diag).asDiagonal() * base.R.transpose();
  }
  std::vector<V3> vo(n);  // velocity of the link frame origin
  for (int i = 0; i < n; ++i) {
    const JointSpec& j = cs.joints[i];
    M3 Ro;
    for (int r = 0; r < 3; ++r)
      for (int s = 0; s < 3; ++s) Ro(r, s) = S(j.origin_R[3 * r + s]);
    const V3 p = vec3<S>(j.origin_xyz), a = vec3<S>(j.axis), com = vec3<S>(j.com);
    M3 Rp = base.R;
    V3 xp = base.p, wp = base.w, vp = base.v;
    if (j.parent >= 0) {
      Rp = k.R[j.parent];
      xp = k.x[j.parent];
      wp = k.w[j.parent];
      vp = vo[j.parent];
    }
    const M3 RJ = Rp * Ro;
    k.R[i] = RJ * axisRotation<S>(a, q[i]);
    k.x[i] = xp + Rp * p;
    k.z[i] = RJ * a;
    k.w[i] = wp + k.z[i] * qd[i];
    vo[i] = vp + wp.cross(k.x[i] - xp);
    const V3 rc = k.R[i] * com;
    k.c[i] = k.x[i] + rc;
    k.vc[i] = vo[i] + k.w[i].cross(rc);
    k.Iw[i] = k.R[i] * vec3<S>(j.inertia_diag).asDiagonal() * k.R[i].transpose();
  }
  return k;
}

template <class S>
Kinematics<S> kinematics(const ArticulatedCase& cs, const S* q, const S* qd) {
  return kinematics<S>(cs, BaseState<S>(), q, qd);
}

// The initial base state of a case (identity pose, BaseSpec velocities; at rest if fixed).
template <class S>
BaseState<S> initialBase(const ArticulatedCase& cs) {
  BaseState<S> b;
  if (cs.base.floating) {
    b.w = vec3<S>(cs.base.w0);
    b.v = vec3<S>(cs.base.v0);
  }
  return b;
}

// Kinetic + potential energy, potential measured from q = 0 and the base at the identity (see
// the header comment). Holds the CoMs of that configuration, so that an evaluation costs one
// kinematics pass.
template <class S>
class EnergyMeter {
 public:
  explicit EnergyMeter(const ArticulatedCase& cs) : cs_(cs) {
    std::vector<S> zero(cs.n(), S(0));
    const Kinematics<S> k0 = kinematics<S>(cs, zero.data(), zero.data());
    c0_ = k0.c;
    base_c0_ = k0.base_c;
  }
  S operator()(const S* q, const S* qd) const { return fromKinematics(kinematics<S>(cs_, q, qd)); }
  S operator()(const BaseState<S>& base, const S* q, const S* qd) const {
    return fromKinematics(kinematics<S>(cs_, base, q, qd));
  }
  S fromKinematics(const Kinematics<S>& k) const {
    const Eigen::Matrix<S, 3, 1> g = vec3<S>(cs_.gravity);
    S e = S(0);
    for (int i = 0; i < cs_.n(); ++i) {
      const S m = S(cs_.joints[i].mass);
      e += S(0.5) * m * k.vc[i].squaredNorm() + S(0.5) * k.w[i].dot(k.Iw[i] * k.w[i]);
      e -= m * g.dot(k.c[i] - c0_[i]);
    }
    if (cs_.base.floating) {
      const S m = S(cs_.base.mass);
      e += S(0.5) * m * k.base_vc.squaredNorm() + S(0.5) * k.base.w.dot(k.base_Iw * k.base.w);
      e -= m * g.dot(k.base_c - base_c0_);
    }
    return e;
  }
  // The same from world body states (maximal coordinates, e.g. ODE), one entry per body: the
  // floating base first (when there is one), then the links in case order. Per body the CoM
  // position and velocity, the orientation and the angular velocity.
  double fromBodies(const std::vector<Eigen::Vector3d>& com,
                    const std::vector<Eigen::Vector3d>& vcom, const std::vector<Eigen::Matrix3d>& R,
                    const std::vector<Eigen::Vector3d>& w) const {
    const Eigen::Vector3d g = vec3<double>(cs_.gravity);
    const int off = cs_.base.floating ? 1 : 0;
    double e = 0;
    for (int b = 0; b < cs_.n() + off; ++b) {
      const bool is_base = b < off;
      const double m = is_base ? cs_.base.mass : cs_.joints[b - off].mass;
      const Eigen::Vector3d d =
          vec3<double>(is_base ? cs_.base.inertia_diag : cs_.joints[b - off].inertia_diag);
      const Eigen::Vector3d c0 = (is_base ? base_c0_ : c0_[b - off]).template cast<double>();
      const Eigen::Vector3d wb = R[b].transpose() * w[b];
      e += 0.5 * m * vcom[b].squaredNorm() + 0.5 * wb.dot(d.asDiagonal() * wb);
      e -= m * g.dot(com[b] - c0);
    }
    return e;
  }

 private:
  const ArticulatedCase& cs_;
  std::vector<Eigen::Matrix<S, 3, 1>> c0_;
  Eigen::Matrix<S, 3, 1> base_c0_ = Eigen::Matrix<S, 3, 1>::Zero();
};

template <class S>
S energy(const ArticulatedCase& cs, const S* q, const S* qd) {
  const BaseState<S> b = initialBase<S>(cs);
  return EnergyMeter<S>(cs)(b, q, qd);
}

// The energy of a case's initial state.
inline double energy(const ArticulatedCase& cs, const std::vector<double>& q,
                     const std::vector<double>& qd) {
  return energy<double>(cs, q.data(), qd.data());
}

// Equations of motion M(x) a = -b(x, nu) (b: Coriolis, centrifugal and gravity; no actuation),
// for the reference solution. Generalised velocities nu = (qd) for a fixed base and
// nu = (v_b, w_b, qd) (world axes) for a floating one; a = d(nu)/dt. M from the body Jacobians,
// b from a recursive Newton-Euler pass with a = 0 and the base origin accelerating at -g (the
// floating base's rows: the total force, and moment about the base origin, of all bodies).
template <class S>
Eigen::Matrix<S, Eigen::Dynamic, 1> forwardDynamics(const ArticulatedCase& cs,
                                                    const BaseState<S>& base, const S* q,
                                                    const S* qd) {
  using V3 = Eigen::Matrix<S, 3, 1>;
  using M3 = Eigen::Matrix<S, 3, 3>;
  using VX = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using MX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using JX = Eigen::Matrix<S, 3, Eigen::Dynamic>;
  const int n = cs.n();
  const int off = cs.base.floating ? 6 : 0;  // columns of (v_b, w_b)
  const int dof = n + off;
  const Kinematics<S> k = kinematics<S>(cs, base, q, qd);
  auto skew = [](const V3& r) {
    M3 K;
    K << S(0), -r(2), r(1), r(2), S(0), -r(0), -r(1), r(0), S(0);
    return K;
  };
  // Ancestors (including itself) of each link.
  std::vector<std::vector<int>> chain(n);
  for (int i = 0; i < n; ++i)
    for (int a = i; a >= 0; a = cs.joints[a].parent) chain[i].push_back(a);
  MX M = MX::Zero(dof, dof);
  for (int i = 0; i < n; ++i) {
    const S m = S(cs.joints[i].mass);
    JX Jv = JX::Zero(3, dof), Jw = JX::Zero(3, dof);
    if (off) {
      Jv.block(0, 0, 3, 3) = M3::Identity();
      Jv.block(0, 3, 3, 3) = -skew(k.c[i] - base.p);
      Jw.block(0, 3, 3, 3) = M3::Identity();
    }
    for (int a : chain[i]) {
      Jw.col(off + a) = k.z[a];
      Jv.col(off + a) = k.z[a].cross(k.c[i] - k.x[a]);
    }
    M += m * Jv.transpose() * Jv + Jw.transpose() * k.Iw[i] * Jw;
  }
  if (off) {
    const S m = S(cs.base.mass);
    JX Jv = JX::Zero(3, dof), Jw = JX::Zero(3, dof);
    Jv.block(0, 0, 3, 3) = M3::Identity();
    Jv.block(0, 3, 3, 3) = -skew(k.base_c - base.p);
    Jw.block(0, 3, 3, 3) = M3::Identity();
    M += m * Jv.transpose() * Jv + Jw.transpose() * k.base_Iw * Jw;
  }
  // Recursive Newton-Euler, world frame, a = 0, base origin acceleration -g.
  const V3 g = vec3<S>(cs.gravity);
  std::vector<V3> alpha(n), ao(n), f(n, V3::Zero()), nn(n, V3::Zero());
  for (int i = 0; i < n; ++i) {
    const int p = cs.joints[i].parent;
    const V3 wp = p >= 0 ? k.w[p] : base.w;
    const V3 alp = p >= 0 ? alpha[p] : V3::Zero();
    const V3 aop = p >= 0 ? ao[p] : V3(-g);
    const V3 xp = p >= 0 ? k.x[p] : base.p;
    const V3 r = k.x[i] - xp;
    alpha[i] = alp + wp.cross(k.z[i] * qd[i]);
    ao[i] = aop + alp.cross(r) + wp.cross(wp.cross(r));
  }
  V3 fb = V3::Zero(), nb = V3::Zero();  // on the floating base's rows, about its origin
  for (int i = n - 1; i >= 0; --i) {
    const S m = S(cs.joints[i].mass);
    const V3 rc = k.c[i] - k.x[i];
    const V3 ac = ao[i] + alpha[i].cross(rc) + k.w[i].cross(k.w[i].cross(rc));
    f[i] += m * ac;
    nn[i] += k.Iw[i] * alpha[i] + k.w[i].cross(k.Iw[i] * k.w[i]) + rc.cross(m * ac);
    const int p = cs.joints[i].parent;
    if (p >= 0) {
      f[p] += f[i];
      nn[p] += nn[i] + (k.x[i] - k.x[p]).cross(f[i]);
    } else {
      fb += f[i];
      nb += nn[i] + (k.x[i] - base.p).cross(f[i]);
    }
  }
  VX b(dof);
  if (off) {
    const S m = S(cs.base.mass);
    const V3 rc = k.base_c - base.p;
    const V3 ac = V3(-g) + base.w.cross(base.w.cross(rc));
    fb += m * ac;
    nb += k.base.w.cross(k.base_Iw * base.w) + rc.cross(m * ac);
    b.head(3) = fb;
    b.segment(3, 3) = nb;
  }
  for (int i = 0; i < n; ++i) b(off + i) = k.z[i].dot(nn[i]);
  return M.ldlt().solve(-b);
}

template <class S>
Eigen::Matrix<S, Eigen::Dynamic, 1> forwardDynamics(const ArticulatedCase& cs, const S* q,
                                                    const S* qd) {
  return forwardDynamics<S>(cs, BaseState<S>(), q, qd);
}

}  // namespace articulated
}  // namespace bench
