// MuJoCo articulated runner (Debian libmujoco-dev 2.2.2): peer_articulated_mujoco.
//
// Model: MJCF written from the case (bench/cases/articulated_cases.h), not read from the URDF,
// so that nothing of MuJoCo's URDF import (fusing, inertia from geoms, default joint options)
// enters: one <body> per link at its joint origin (pos, quat from the origin rotation), one
// hinge <joint> at the body origin about the case's axis, an explicit <inertial pos=CoM mass
// diaginertia> (body axes = link axes), no geoms; joint damping, armature, frictionloss and
// stiffness 0 (MuJoCo's defaults), no limits (limited="false"), contacts disabled
// (<flag contact="disable"/>), the case's gravity. qpos of a hinge = the joint angle from the
// model pose, qvel its rate, which are set to (q0, qd0) before mj_forward.
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
  for (int k = 0; k < c.n(); ++k)
    if (c.joints[k].parent < 0) bodyXml(c, k, 2, &x);
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
  bool failed() override { return d_->warning[mjWARN_BADQACC].number > 0; }
  std::string events() override { return failed() ? "BADQACC (MuJoCo reset the state)" : ""; }

 private:
  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  std::vector<int> qadr_, vadr_;
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
