// Articulated benchmark cases (doc/benchmarks-articulated.md): serial chains of revolute joints
// on a fixed base, the same description for every engine, and the engine-independent pieces of
// the metrics (kinematics, energy, joint-space dynamics for the reference solution).
//
// Header-only so that the peer runners (bench/peers/articulated_<engine>.cc), the reference
// (articulated_reference.cc) and our own runner (bench/articulated.cc) share it without a link
// dependency.
//
// Model. Joint i moves link i. Its joint frame J_i sits in the frame of link parent(i) (or in
// the world, parent = -1) at (R_i, p_i) = (origin_R, origin_xyz); at q_i = 0 the link frame is
// J_i, and the joint turns the link about the unit `axis` (in J_i, = in the link frame) by q_i:
//   R_link(i) = R_link(parent) R_i Rot(axis_i, q_i),   x_link(i) = x_link(parent) + R_link(parent)
//   p_i.
// Each link carries a mass at `com` (link frame) with a diagonal inertia about the CoM in link
// axes. This is exactly the URDF's joint <origin>, <axis> and <inertial> (rpy = 0 everywhere but
// the arm's ceiling mount, which is folded into joint1's origin here). The numbers are the
// URDF's literals (urdf/double_pendulum.urdf, urdf/arm7.urdf), so that a simulator reading the
// URDF gets bit-identical parameters; bench_articulated_reference checks the two agree.
//
// Energy. E = kinetic + V(q) - V(0), V = -sum m g.x_com: the potential is measured from q = 0
// (the hanging configuration of both cases), so that |E(0)| is the energy of the motion and not
// an arbitrary offset set by the height of the pivot. Relative drift = max_t |E(t) - E(0)| / E(0).
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
  int parent = -1;          // index of the parent joint's link; -1: the world (fixed base)
  std::array<double, 3> origin_xyz{0, 0, 0};  // joint frame in the parent link's frame
  std::array<double, 9> origin_R{1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major, parent -> joint frame
  std::array<double, 3> axis{0, 1, 0};                        // unit, in the joint (= link) frame
  double mass = 1;
  std::array<double, 3> com{0, 0, 0};           // link frame
  std::array<double, 3> inertia_diag{1, 1, 1};  // about the CoM, link axes (kg m^2)
  double limit = 0;  // |q| limit of the URDF (rad), 0: continuous; not enforced by the benchmark
};

struct ArticulatedCase {
  std::string name;
  std::string urdf;               // relative to the repository root
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

// The ceiling-mounted 7-DoF arm of urdf/arm7.urdf. world -> base_link: z = 2, rpy (pi, 0, 0),
// i.e. R = diag(1, -1, -1); joint1 at (0, 0, 0.15) in base_link, so in the world at (0, 0, 1.85).
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
      j.origin_xyz = {0, 0, 2.0 - rows[i].z_origin};
      j.origin_R = {1, 0, 0, 0, -1, 0, 0, 0, -1};
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

inline std::vector<ArticulatedCase> allArticulatedCases() { return {doublePendulum(), arm7()}; }

// Angle difference wrapped to (-pi, pi] (ODE reports hinge angles wrapped).
template <class S>
S wrapAngle(S a) {
  using std::atan2;
  using std::cos;
  using std::sin;
  return atan2(sin(a), cos(a));
}

// World poses and velocities of all links, and the pieces the dynamics needs.
template <class S>
struct Kinematics {
  using V3 = Eigen::Matrix<S, 3, 1>;
  using M3 = Eigen::Matrix<S, 3, 3>;
  std::vector<M3> R;   // link orientation (world)
  std::vector<V3> x;   // link frame origin = joint position (world)
  std::vector<V3> z;   // joint axis (world)
  std::vector<V3> c;   // CoM (world)
  std::vector<V3> w;   // angular velocity (world)
  std::vector<V3> vc;  // CoM velocity (world)
  std::vector<M3> Iw;  // inertia about the CoM, world axes
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
Kinematics<S> kinematics(const ArticulatedCase& cs, const S* q, const S* qd) {
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
  std::vector<V3> vo(n);  // velocity of the link frame origin
  for (int i = 0; i < n; ++i) {
    const JointSpec& j = cs.joints[i];
    M3 Ro;
    for (int r = 0; r < 3; ++r)
      for (int s = 0; s < 3; ++s) Ro(r, s) = S(j.origin_R[3 * r + s]);
    const V3 p(S(j.origin_xyz[0]), S(j.origin_xyz[1]), S(j.origin_xyz[2]));
    const V3 a(S(j.axis[0]), S(j.axis[1]), S(j.axis[2]));
    const V3 com(S(j.com[0]), S(j.com[1]), S(j.com[2]));
    M3 Rp = M3::Identity();
    V3 xp = V3::Zero(), wp = V3::Zero(), vp = V3::Zero();
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
    const V3 d(S(j.inertia_diag[0]), S(j.inertia_diag[1]), S(j.inertia_diag[2]));
    k.Iw[i] = k.R[i] * d.asDiagonal() * k.R[i].transpose();
  }
  return k;
}

// Kinetic + potential energy, potential measured from q = 0 (see the header comment). Holds the
// CoMs at q = 0, so that an evaluation costs one kinematics pass.
template <class S>
class EnergyMeter {
 public:
  explicit EnergyMeter(const ArticulatedCase& cs) : cs_(cs) {
    std::vector<S> zero(cs.n(), S(0));
    c0_ = kinematics<S>(cs, zero.data(), zero.data()).c;
  }
  S operator()(const S* q, const S* qd) const { return fromKinematics(kinematics<S>(cs_, q, qd)); }
  S fromKinematics(const Kinematics<S>& k) const {
    const Eigen::Matrix<S, 3, 1> g(S(cs_.gravity[0]), S(cs_.gravity[1]), S(cs_.gravity[2]));
    S e = S(0);
    for (int i = 0; i < cs_.n(); ++i) {
      const S m = S(cs_.joints[i].mass);
      e += S(0.5) * m * k.vc[i].squaredNorm() + S(0.5) * k.w[i].dot(k.Iw[i] * k.w[i]);
      e -= m * g.dot(k.c[i] - c0_[i]);
    }
    return e;
  }
  // The same from world body states (maximal coordinates, e.g. ODE): per link the CoM position
  // and velocity, the orientation and the angular velocity.
  double fromBodies(const std::vector<Eigen::Vector3d>& com,
                    const std::vector<Eigen::Vector3d>& vcom, const std::vector<Eigen::Matrix3d>& R,
                    const std::vector<Eigen::Vector3d>& w) const {
    const Eigen::Vector3d g(cs_.gravity[0], cs_.gravity[1], cs_.gravity[2]);
    double e = 0;
    for (int i = 0; i < cs_.n(); ++i) {
      const JointSpec& j = cs_.joints[i];
      const Eigen::Vector3d d(j.inertia_diag[0], j.inertia_diag[1], j.inertia_diag[2]);
      const Eigen::Vector3d wb = R[i].transpose() * w[i];
      e += 0.5 * j.mass * vcom[i].squaredNorm() + 0.5 * wb.dot(d.asDiagonal() * wb);
      e -= j.mass * g.dot(com[i] - c0_[i].template cast<double>());
    }
    return e;
  }

 private:
  const ArticulatedCase& cs_;
  std::vector<Eigen::Matrix<S, 3, 1>> c0_;
};

template <class S>
S energy(const ArticulatedCase& cs, const S* q, const S* qd) {
  return EnergyMeter<S>(cs)(q, qd);
}

inline double energy(const ArticulatedCase& cs, const std::vector<double>& q,
                     const std::vector<double>& qd) {
  return energy<double>(cs, q.data(), qd.data());
}

// Joint-space dynamics M(q) qdd = tau - b(q, qd) (b: Coriolis, centrifugal and gravity), for
// the reference solution: M from the link Jacobians, b from a recursive Newton-Euler pass with
// qdd = 0 and the base accelerating at -g. Returns qdd (tau = 0: the benchmark is unactuated).
template <class S>
Eigen::Matrix<S, Eigen::Dynamic, 1> forwardDynamics(const ArticulatedCase& cs, const S* q,
                                                    const S* qd) {
  using V3 = Eigen::Matrix<S, 3, 1>;
  using VX = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using MX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  const int n = cs.n();
  const Kinematics<S> k = kinematics<S>(cs, q, qd);
  // Ancestors (including itself) of each link.
  std::vector<std::vector<int>> chain(n);
  for (int i = 0; i < n; ++i)
    for (int a = i; a >= 0; a = cs.joints[a].parent) chain[i].push_back(a);
  MX M = MX::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    const S m = S(cs.joints[i].mass);
    Eigen::Matrix<S, 3, Eigen::Dynamic> Jv = Eigen::Matrix<S, 3, Eigen::Dynamic>::Zero(3, n),
                                        Jw = Eigen::Matrix<S, 3, Eigen::Dynamic>::Zero(3, n);
    for (int a : chain[i]) {
      Jw.col(a) = k.z[a];
      Jv.col(a) = k.z[a].cross(k.c[i] - k.x[a]);
    }
    M += m * Jv.transpose() * Jv + Jw.transpose() * k.Iw[i] * Jw;
  }
  // Recursive Newton-Euler, world frame, qdd = 0, base acceleration -g (gravity).
  const V3 g(S(cs.gravity[0]), S(cs.gravity[1]), S(cs.gravity[2]));
  std::vector<V3> alpha(n), ao(n), f(n, V3::Zero()), nn(n, V3::Zero());
  for (int i = 0; i < n; ++i) {
    const int p = cs.joints[i].parent;
    const V3 wp = p >= 0 ? k.w[p] : V3::Zero();
    const V3 alp = p >= 0 ? alpha[p] : V3::Zero();
    const V3 aop = p >= 0 ? ao[p] : V3(-g);
    const V3 xp = p >= 0 ? k.x[p] : V3::Zero();
    const V3 r = k.x[i] - xp;
    alpha[i] = alp + wp.cross(k.z[i] * qd[i]);
    ao[i] = aop + alp.cross(r) + wp.cross(wp.cross(r));
  }
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
    }
  }
  VX b(n);
  for (int i = 0; i < n; ++i) b(i) = k.z[i].dot(nn[i]);
  return M.ldlt().solve(-b);
}

}  // namespace articulated
}  // namespace bench
