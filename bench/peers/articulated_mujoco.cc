// MuJoCo articulated runner (Debian libmujoco-dev 2.2.2): peer_articulated_mujoco.
//
// Model: MJCF written from the case (bench/cases/articulated_cases.h), not read from the URDF,
// so that nothing of MuJoCo's URDF import (fusing, inertia from geoms, default joint options)
// enters: one <body> per link at its joint origin (pos, quat from the origin rotation), one
// hinge <joint> at the body origin about the case's axis, an explicit <inertial pos=CoM mass
// diaginertia> (body axes = link axes), no geoms; joint damping, armature, frictionloss and
// stiffness 0 (MuJoCo's defaults), no limits (limited="false"), contacts disabled
// (<flag contact="disable"/>), the case's gravity. qpos of a hinge = the joint angle from the
// model pose, qvel its rate, which are set to (q0, qd0) before mj_forward. A floating base is a
// body with a <freejoint/> at the identity pose holding the root joints' bodies; its qvel is
// (v_b in world axes, w_b in body axes = world axes at t = 0).
//
// Configs: every integrator of 2.2.2: Euler (semi-implicit, the default), RK4, implicit
// (implicit in the velocity-dependent forces; "implicitfast" came with 2.3).
#include <mujoco/mujoco.h>

#include <Eigen/Geometry>
#include <cstdarg>
#include <cstdio>
#include <memory>
#include <string>

#include "articulated_common.h"
#include "mujoco_model.h"

namespace {

using bench::articulated::ArticulatedCase;
using bench::articulated::JointSpec;

std::string fmt(const char* f, ...) __attribute__((format(printf, 1, 2)));
std::string fmt(const char* f, ...) {
  char buf[1024];
  va_list ap;
  va_start(ap, f);
  std::vsnprintf(buf, sizeof buf, f, ap);
  va_end(ap);
  return buf;
}

void bodyXml(const ArticulatedCase& c, int i, int depth, std::string* x) {
  const JointSpec& j = c.joints[i];
  Eigen::Matrix3d R;
  for (int r = 0; r < 3; ++r)
    for (int s = 0; s < 3; ++s) R(r, s) = j.origin_R[3 * r + s];
  const Eigen::Quaterniond q(R);
  const std::string pad(2 * depth, ' ');
  *x += pad + fmt("<body name=\"%s\" pos=\"%.17g %.17g %.17g\" quat=\"%.17g %.17g %.17g %.17g\">\n",
                  j.link.c_str(), j.origin_xyz[0], j.origin_xyz[1], j.origin_xyz[2], q.w(), q.x(),
                  q.y(), q.z());
  *x += pad + fmt("  <joint name=\"%s\" type=\"hinge\" pos=\"0 0 0\" axis=\"%.17g %.17g %.17g\" "
                  "limited=\"false\"/>\n",
                  j.joint.c_str(), j.axis[0], j.axis[1], j.axis[2]);
  *x += pad + fmt("  <inertial pos=\"%.17g %.17g %.17g\" mass=\"%.17g\" diaginertia=\"%.17g %.17g "
                  "%.17g\"/>\n",
                  j.com[0], j.com[1], j.com[2], j.mass, j.inertia_diag[0], j.inertia_diag[1],
                  j.inertia_diag[2]);
  for (int k = 0; k < c.n(); ++k)
    if (c.joints[k].parent == i) bodyXml(c, k, depth + 1, x);
  *x += pad + "</body>\n";
}

std::string modelXml(const ArticulatedCase& c, double h) {
  std::string x = "<mujoco model=\"" + c.name + "\">\n";
  x += "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n";
  x += fmt("  <option timestep=\"%.17g\" gravity=\"%.17g %.17g %.17g\">\n", h, c.gravity[0],
           c.gravity[1], c.gravity[2]);
  x += "    <flag contact=\"disable\"/>\n  </option>\n  <worldbody>\n";
  int depth = 2;
  if (c.base.floating) {  // the base: a body with a free joint, at the identity pose
    const auto& b = c.base;
    x += fmt("    <body name=\"%s\" pos=\"0 0 0\">\n      <freejoint name=\"base_free\"/>\n",
             b.link.c_str());
    x +=
        fmt("      <inertial pos=\"%.17g %.17g %.17g\" mass=\"%.17g\" diaginertia=\"%.17g %.17g "
            "%.17g\"/>\n",
            b.com[0], b.com[1], b.com[2], b.mass, b.inertia_diag[0], b.inertia_diag[1],
            b.inertia_diag[2]);
    depth = 3;
  }
  for (int k = 0; k < c.n(); ++k)
    if (c.joints[k].parent < 0) bodyXml(c, k, depth, &x);
  if (c.base.floating) x += "    </body>\n";
  x += "  </worldbody>\n</mujoco>\n";
  return x;
}

class MujocoArticulated : public bench::articulated::ArticulatedSim {
 public:
  MujocoArticulated(const ArticulatedCase& c, double h, int integrator) {
    m_ = bench::loadMujocoModel(modelXml(c, h));
    m_->opt.integrator = integrator;
    d_ = mj_makeData(m_);
    for (int i = 0; i < c.n(); ++i) {
      const int jid = mj_name2id(m_, mjOBJ_JOINT, c.joints[i].joint.c_str());
      qadr_.push_back(m_->jnt_qposadr[jid]);
      vadr_.push_back(m_->jnt_dofadr[jid]);
      d_->qpos[qadr_.back()] = c.q0[i];
      d_->qvel[vadr_.back()] = c.qd0[i];
    }
    if (c.base.floating) {
      // Free joint: qpos = (x, y, z, qw, qx, qy, qz), qvel = (v world, w in body axes); the base
      // starts at the identity, so body axes = world axes.
      const int jid = mj_name2id(m_, mjOBJ_JOINT, "base_free");
      base_q_ = m_->jnt_qposadr[jid];
      base_v_ = m_->jnt_dofadr[jid];
      for (int i = 0; i < 3; ++i) {
        d_->qvel[base_v_ + i] = c.base.v0[i];
        d_->qvel[base_v_ + 3 + i] = c.base.w0[i];
      }
    }
    mj_forward(m_, d_);
  }
  ~MujocoArticulated() override {
    mj_deleteData(d_);
    mj_deleteModel(m_);
  }
  void step(long n) override {
    for (long i = 0; i < n; ++i) mj_step(m_, d_);
  }
  void joints(std::vector<double>* q, std::vector<double>* qd) override {
    q->resize(qadr_.size());
    qd->resize(qadr_.size());
    for (size_t i = 0; i < qadr_.size(); ++i) {
      (*q)[i] = d_->qpos[qadr_[i]];
      (*qd)[i] = d_->qvel[vadr_[i]];
    }
  }
  bool base(bench::articulated::BaseState<double>* b) override {
    if (base_q_ < 0) return false;
    const mjtNum* q = d_->qpos + base_q_;
    const mjtNum* v = d_->qvel + base_v_;
    const Eigen::Quaterniond quat(q[3], q[4], q[5], q[6]);
    b->R = quat.normalized().toRotationMatrix();
    b->p = Eigen::Vector3d(q[0], q[1], q[2]);
    b->v = Eigen::Vector3d(v[0], v[1], v[2]);
    b->w = b->R * Eigen::Vector3d(v[3], v[4], v[5]);
    return true;
  }
  bool failed() override { return d_->warning[mjWARN_BADQACC].number > 0; }
  std::string events() override { return failed() ? "BADQACC (MuJoCo reset the state)" : ""; }

 private:
  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  std::vector<int> qadr_, vadr_;
  int base_q_ = -1, base_v_ = -1;
};

void quietWarning(const char*) {}

}  // namespace

int main(int argc, char** argv) {
  mju_user_warning = quietWarning;
  auto make = [](int integ) {
    return [integ](const ArticulatedCase& c,
                   double h) -> std::unique_ptr<bench::articulated::ArticulatedSim> {
      return std::make_unique<MujocoArticulated>(c, h, integ);
    };
  };
  std::vector<bench::articulated::ArticulatedConfig> configs = {
      {"Euler", make(mjINT_EULER)},
      {"RK4", make(mjINT_RK4)},
      {"implicit", make(mjINT_IMPLICIT)},
  };
  return bench::articulated::runArticulatedSweep(
      "mujoco", std::string("MuJoCo ") + mj_versionString(), configs, argc, argv);
}
