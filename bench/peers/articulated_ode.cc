// ODE articulated runner (Debian libode-dev 0.16.2, double precision): peer_articulated_ode.
//
// Model: maximal coordinates, built in code from the case (bench/cases/articulated_cases.h):
// a floating base is a free dBody (at its CoM, identity rotation, the case's velocities), and
// one dBody per link (position = the link's CoM, rotation = the link's axes, dMass with the
// link's mass and diagonal inertia, no geoms), one hinge joint per revolute joint
// (dJointAttach(link, parent link or the static world)). The joints are created with the
// bodies in the q = 0 pose (anchor = the joint's world position, axis = its world axis), so that
// dJointGetHingeAngle measures q from the case's zero; then every body is moved to the pose
// and velocity of (q0, qd0) (case kinematics). World: gravity of the case, damping 0,
// auto-disable off, max angular speed dInfinity, ERP and CFM at ODE's defaults (0.2, 1e-10):
// ODE keeps the joints together by constraint forces plus this position correction.
//
// Readings: q = dJointGetHingeAngle (wrapped to (-pi, pi]; the error metric wraps too),
// qd = dJointGetHingeAngleRate. The energy is the bodies' (ArticulatedSim::bodyEnergy): a
// maximal-coordinates engine can move or spin bodies in ways no joint coordinate shows. The
// notes give the largest joint gap seen (distance between the hinge's two anchors).
//
// Configs: step (dWorldStep, direct solver) and quickstep (dWorldQuickStep, 20 SOR iterations,
// the default), both with the gyroscopic term on (the default).
#include <ode/ode.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "articulated_common.h"

namespace {

using bench::articulated::ArticulatedCase;
using bench::articulated::EnergyMeter;
using bench::articulated::JointSpec;
using bench::articulated::Kinematics;

void setRotation(dBodyID b, const Eigen::Matrix3d& R) {
  dMatrix3 m;
  for (int r = 0; r < 3; ++r) {
    for (int s = 0; s < 3; ++s) m[4 * r + s] = R(r, s);
    m[4 * r + 3] = 0;
  }
  dBodySetRotation(b, m);
}

class OdeArticulated : public bench::articulated::ArticulatedSim {
 public:
  OdeArticulated(const ArticulatedCase& c, double h, bool quick)
      : h_(h), quick_(quick), energy_(c) {
    world_ = dWorldCreate();
    dWorldSetGravity(world_, c.gravity[0], c.gravity[1], c.gravity[2]);
    dWorldSetDamping(world_, 0, 0);
    dWorldSetAutoDisableFlag(world_, 0);
    dWorldSetMaxAngularSpeed(world_, dInfinity);
    const int n = c.n();
    std::vector<double> zero(n, 0.0);
    const Kinematics<double> k0 =
        bench::articulated::kinematics<double>(c, zero.data(), zero.data());
    if (c.base.floating) {  // the base body first, at the identity
      const auto& b = c.base;
      base_ = dBodyCreate(world_);
      dMass m;
      dMassSetParameters(&m, b.mass, 0, 0, 0, b.inertia_diag[0], b.inertia_diag[1],
                         b.inertia_diag[2], 0, 0, 0);
      dBodySetMass(base_, &m);
      dBodySetAutoDisableFlag(base_, 0);
      dBodySetLinearDamping(base_, 0);
      dBodySetAngularDamping(base_, 0);
      dBodySetMaxAngularSpeed(base_, dInfinity);
      dBodySetPosition(base_, b.com[0], b.com[1], b.com[2]);
      base_com_ = Eigen::Vector3d(b.com[0], b.com[1], b.com[2]);
    }
    for (int i = 0; i < n; ++i) {
      const JointSpec& j = c.joints[i];
      dBodyID b = dBodyCreate(world_);
      dMass m;
      dMassSetParameters(&m, j.mass, 0, 0, 0, j.inertia_diag[0], j.inertia_diag[1],
                         j.inertia_diag[2], 0, 0, 0);
      dBodySetMass(b, &m);
      dBodySetAutoDisableFlag(b, 0);
      dBodySetLinearDamping(b, 0);
      dBodySetAngularDamping(b, 0);
      dBodySetMaxAngularSpeed(b, dInfinity);
      dBodySetPosition(b, k0.c[i].x(), k0.c[i].y(), k0.c[i].z());
      setRotation(b, k0.R[i]);
      bodies_.push_back(b);
    }
    for (int i = 0; i < n; ++i) {
      dJointID jt = dJointCreateHinge(world_, nullptr);
      dJointAttach(jt, bodies_[i], c.joints[i].parent >= 0 ? bodies_[c.joints[i].parent] : base_);
      dJointSetHingeAnchor(jt, k0.x[i].x(), k0.x[i].y(), k0.x[i].z());
      dJointSetHingeAxis(jt, k0.z[i].x(), k0.z[i].y(), k0.z[i].z());
      joints_.push_back(jt);
    }
    const Kinematics<double> k = bench::articulated::kinematics<double>(
        c, bench::articulated::initialBase<double>(c), c.q0.data(), c.qd0.data());
    if (base_) {
      dBodySetLinearVel(base_, k.base_vc.x(), k.base_vc.y(), k.base_vc.z());
      dBodySetAngularVel(base_, k.base.w.x(), k.base.w.y(), k.base.w.z());
    }
    for (int i = 0; i < n; ++i) {
      dBodySetPosition(bodies_[i], k.c[i].x(), k.c[i].y(), k.c[i].z());
      setRotation(bodies_[i], k.R[i]);
      dBodySetLinearVel(bodies_[i], k.vc[i].x(), k.vc[i].y(), k.vc[i].z());
      dBodySetAngularVel(bodies_[i], k.w[i].x(), k.w[i].y(), k.w[i].z());
    }
  }
  ~OdeArticulated() override { dWorldDestroy(world_); }

  void step(long n) override {
    for (long i = 0; i < n; ++i) {
      if (quick_)
        dWorldQuickStep(world_, h_);
      else
        dWorldStep(world_, h_);
    }
  }
  void joints(std::vector<double>* q, std::vector<double>* qd) override {
    q->resize(joints_.size());
    qd->resize(joints_.size());
    for (size_t i = 0; i < joints_.size(); ++i) {
      (*q)[i] = dJointGetHingeAngle(joints_[i]);
      (*qd)[i] = dJointGetHingeAngleRate(joints_[i]);
      dVector3 a1, a2;
      dJointGetHingeAnchor(joints_[i], a1);
      dJointGetHingeAnchor2(joints_[i], a2);
      const double gap =
          std::sqrt((a1[0] - a2[0]) * (a1[0] - a2[0]) + (a1[1] - a2[1]) * (a1[1] - a2[1]) +
                    (a1[2] - a2[2]) * (a1[2] - a2[2]));
      if (std::isfinite(gap) && gap > max_gap_) max_gap_ = gap;
    }
  }
  bool base(bench::articulated::BaseState<double>* b) override {
    if (!base_) return false;
    const dReal* p = dBodyGetPosition(base_);
    const dReal* v = dBodyGetLinearVel(base_);
    const dReal* av = dBodyGetAngularVel(base_);
    const dReal* m = dBodyGetRotation(base_);
    for (int r = 0; r < 3; ++r)
      for (int s = 0; s < 3; ++s) b->R(r, s) = m[4 * r + s];
    b->w = Eigen::Vector3d(av[0], av[1], av[2]);
    const Eigen::Vector3d rc = b->R * base_com_;
    b->p = Eigen::Vector3d(p[0], p[1], p[2]) - rc;
    b->v = Eigen::Vector3d(v[0], v[1], v[2]) - b->w.cross(rc);
    return true;
  }
  bool bodyEnergy(double* E) override {
    std::vector<dBodyID> all;
    if (base_) all.push_back(base_);
    all.insert(all.end(), bodies_.begin(), bodies_.end());
    const size_t n = all.size();
    std::vector<Eigen::Vector3d> com(n), vcom(n), w(n);
    std::vector<Eigen::Matrix3d> R(n);
    for (size_t i = 0; i < n; ++i) {
      const dReal* p = dBodyGetPosition(all[i]);
      const dReal* v = dBodyGetLinearVel(all[i]);
      const dReal* av = dBodyGetAngularVel(all[i]);
      const dReal* m = dBodyGetRotation(all[i]);
      com[i] = Eigen::Vector3d(p[0], p[1], p[2]);
      vcom[i] = Eigen::Vector3d(v[0], v[1], v[2]);
      w[i] = Eigen::Vector3d(av[0], av[1], av[2]);
      for (int r = 0; r < 3; ++r)
        for (int s = 0; s < 3; ++s) R[i](r, s) = m[4 * r + s];
    }
    *E = energy_.fromBodies(com, vcom, R, w);
    return true;
  }
  std::string events() override {
    char buf[64];
    std::snprintf(buf, sizeof buf, "max joint gap %.2e m", max_gap_);
    return buf;
  }

 private:
  double h_;
  bool quick_;
  EnergyMeter<double> energy_;
  dWorldID world_;
  std::vector<dBodyID> bodies_;
  dBodyID base_ = nullptr;  // floating base
  Eigen::Vector3d base_com_ = Eigen::Vector3d::Zero();
  std::vector<dJointID> joints_;
  double max_gap_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  dInitODE2(0);
  auto make = [](bool quick) {
    return [quick](const ArticulatedCase& c,
                   double h) -> std::unique_ptr<bench::articulated::ArticulatedSim> {
      return std::make_unique<OdeArticulated>(c, h, quick);
    };
  };
  std::vector<bench::articulated::ArticulatedConfig> configs = {
      {"step", make(false)},
      {"quickstep", make(true)},
  };
  const std::string version = std::string("ODE 0.16 (") + dGetConfiguration() + ")";
  const int rc = bench::articulated::runArticulatedSweep("ode", version, configs, argc, argv);
  dCloseODE();
  return rc;
}
