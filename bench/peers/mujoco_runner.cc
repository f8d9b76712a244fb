// MuJoCo peer runner (Debian libmujoco-dev 2.2.2).
//
// Model: one body with a <freejoint/>, explicit <inertial pos="0 0 0"
// mass=m diaginertia="J1 J2 J3"/> (body frame = principal frame at the CoM),
// no geoms, joint damping/armature 0 (defaults), contact disabled via
// <flag contact="disable"/>, gravity from the case. The world torque is put
// in d->xfrc_applied (world-frame couple at the CoM; MuJoCo keeps it until
// changed, so it acts at every step). qvel of a free joint = (linear velocity
// in world axes, angular velocity in body axes).
//
// Configs: every integrator this MuJoCo version has: Euler (semi-implicit),
// RK4, implicit. "implicitfast" does not exist in 2.2.2 (added in 2.3.x), so
// it is not measured.
//
// Timing: see peer_common.h -- median of 3 fresh runs of min(T/h, 20000)
// steps of mj_step(); errors from a separate full run to T = 100 s.
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>

#include <mujoco/mujoco.h>

#include "peer_common.h"
#include "mujoco_model.h"

namespace {

using bench::BodyState;
using bench::Case;

std::string modelXml(const Case& c, double h) {
  char buf[2048];
  std::snprintf(buf, sizeof buf,
                "<mujoco model=\"free_body\">\n"
                "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
                "  <option timestep=\"%.17g\" gravity=\"%.17g %.17g %.17g\">\n"
                "    <flag contact=\"disable\"/>\n"
                "  </option>\n"
                "  <worldbody>\n"
                "    <body name=\"b\" pos=\"0 0 0\">\n"
                "      <freejoint name=\"free\"/>\n"
                "      <inertial pos=\"0 0 0\" mass=\"%.17g\" diaginertia=\"%.17g %.17g %.17g\"/>\n"
                "    </body>\n"
                "  </worldbody>\n"
                "</mujoco>\n",
                h, c.gravity[0], c.gravity[1], c.gravity[2], c.mass, c.inertia[0], c.inertia[1], c.inertia[2]);
  return buf;
}

class MujocoSim : public bench::peers::PeerSim {
 public:
  MujocoSim(const Case& c, double h, int integrator) {
    const std::string xml = modelXml(c, h);
    m_ = bench::loadMujocoModel(xml);
    m_->opt.integrator = integrator;
    d_ = mj_makeData(m_);
    // Free joint: qpos = (x, y, z, qw, qx, qy, qz), qvel = (v_world, w_body).
    for (int i = 0; i < 3; ++i) {
      d_->qvel[i] = c.v0_world[i];
      d_->qvel[3 + i] = c.w0_body[i];
      d_->xfrc_applied[6 * 1 + 3 + i] = c.torque_world[i];  // body id 1
    }
    mj_forward(m_, d_);
  }
  ~MujocoSim() override {
    mj_deleteData(d_);
    mj_deleteModel(m_);
  }
  void run(long steps) override {
    for (long i = 0; i < steps; ++i) mj_step(m_, d_);
  }
  // MuJoCo resets mjData to the initial pose at rest when it finds a bad
  // qacc (mjWARN_BADQACC); we count that as a blow-up.
  bool engineReportedFailure() override { return d_->warning[mjWARN_BADQACC].number > 0; }
  BodyState state() override {
    BodyState s;
    for (int i = 0; i < 4; ++i) s.q[i] = d_->qpos[3 + i];
    mjtNum wb[3] = {d_->qvel[3], d_->qvel[4], d_->qvel[5]}, ww[3];
    mjtNum quat[4] = {s.q[0], s.q[1], s.q[2], s.q[3]};
    mju_normalize4(quat);
    mju_rotVecQuat(ww, wb, quat);
    for (int i = 0; i < 3; ++i) {
      s.w_world[i] = ww[i];
      s.x[i] = d_->qpos[i];
      s.v[i] = d_->qvel[i];
    }
    return s;
  }

 private:
  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
};

// Silences MuJoCo's "simulation is unstable" console warnings; the
// condition itself is read from d->warning (engineReportedFailure).
void quietWarning(const char*) {}

}  // namespace

int main(int argc, char** argv) {
  using bench::peers::PeerConfig;
  mju_user_warning = quietWarning;
  auto make = [](int integ) {
    return [integ](const Case& c, double h) -> std::unique_ptr<bench::peers::PeerSim> {
      return std::make_unique<MujocoSim>(c, h, integ);
    };
  };
  std::vector<PeerConfig> configs = {
      {"Euler", make(mjINT_EULER)},
      {"RK4", make(mjINT_RK4)},
      {"implicit", make(mjINT_IMPLICIT)},
  };
  const std::string version = std::string("MuJoCo ") + mj_versionString();
  return bench::peers::runSweep("mujoco", version, configs, argc, argv);
}
