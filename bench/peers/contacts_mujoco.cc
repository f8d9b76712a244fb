// MuJoCo contact peer runner (Debian libmujoco-dev 2.2.2): peer_contacts_mujoco.
//
// Scene (from bench/cases/contact_cases.h): worldbody plane geom (z = 0),
// for pile1000 four static box geoms as bin walls; every dynamic body is a
// <body> with a <freejoint/> and one geom (sphere / box) with its mass given
// (inertia from the solid shape: 2/5 m r^2, m a^2/6). Integrator: Euler
// (MuJoCo's default, semi-implicit), solver Newton (default), default
// iterations/tolerance.
//
// How the case parameters map to MuJoCo (and what it cannot represent):
//  * friction: geom friction = (mu, 0, 0) on every geom, condim = 3 (sliding
//    friction only; MuJoCo combines two geoms by taking the max, all equal
//    here). mu = 0 (bounce): condim = 1 (frictionless contact).
//    Cone: config `pyramidal` (MuJoCo's default cone, 4 edges) and
//    `elliptic` (the exact Coulomb cone, recommended by MuJoCo's docs when
//    friction matters).
//  * restitution: MuJoCo has NO coefficient of restitution. Contacts are soft
//    constraints whose reference acceleration is a mass-spring-damper,
//    a_ref = -b v - k r, set by solref = (timeconst tau, dampratio zeta):
//    b = 2/(dmax tau), k = d/(dmax^2 tau^2 zeta^2), and the constrained
//    acceleration obeys a + d (b v + k r) = (1 - d) a0 (d = impedance,
//    solimp). So the contact is a spring d k with damper d b, whose damping
//    ratio d b / (2 sqrt(d k)) = zeta for any (locally constant) d. A linear damped
//    oscillator that separates when it returns to zero penetration has
//    e = exp(-zeta pi / sqrt(1 - zeta^2)), i.e. the closest honest
//    setting is dampratio = zeta(e) = -ln e / sqrt(pi^2 + ln^2 e):
//    e = 0.8 -> 0.0709, e = 0.2 -> 0.456; e = 0 -> 1 (critical damping,
//    MuJoCo's default). timeconst stays at MuJoCo's default 0.02 s (its
//    docs: at least 2 time steps). The real rebound differs from e because
//    the contact force cannot pull (it is cut when the damper would pull),
//    and the penetration-dependent impedance makes the spring nonlinear.
//  * solimp: default (0.9 0.95 0.001 0.5 2). margin 0 (default).
//  * sizes: nconmax / njmax set explicitly for pile1000 (MuJoCo 2.2.2 has
//    fixed-size contact/constraint buffers; overflow is reported in notes).
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>

#include <mujoco/mujoco.h>

#include "contact_common.h"
#include "mujoco_model.h"

namespace {

using bench::contacts::BodyObs;
using bench::contacts::ContactCase;
using bench::contacts::Shape;

double dampRatioFor(double e) {
  if (e <= 0) return 1.0;
  const double l = std::log(e);
  return -l / std::sqrt(M_PI * M_PI + l * l);
}

std::string fmt(const char* f, ...) __attribute__((format(printf, 1, 2)));
std::string fmt(const char* f, ...) {
  char buf[1024];
  va_list ap;
  va_start(ap, f);
  std::vsnprintf(buf, sizeof buf, f, ap);
  va_end(ap);
  return buf;
}

std::string modelXml(const ContactCase& c, double h, bool elliptic) {
  const bool frictionless = c.mu <= 0;
  std::string x = "<mujoco model=\"" + c.name + "\">\n";
  x += fmt("  <option timestep=\"%.17g\" gravity=\"%.17g %.17g %.17g\" cone=\"%s\"/>\n", h, c.gravity[0],
           c.gravity[1], c.gravity[2], elliptic ? "elliptic" : "pyramidal");
  // MuJoCo 2.2.2 allocates njmax x njmax and njmax x nv arrays in one buffer
  // whose size must stay below 2^31 bytes: njmax = 7000 is about the most
  // for nv = 6000 (pile1000). Overflow is reported as CNSTRFULL in notes.
  if (c.bodies.size() > 100) x += "  <size nconmax=\"3000\" njmax=\"7000\"/>\n";
  x += fmt("  <default><geom condim=\"%d\" friction=\"%.17g 0 0\" solref=\"0.02 %.17g\"/></default>\n",
           frictionless ? 1 : 3, c.mu, dampRatioFor(c.e));
  x += "  <worldbody>\n    <geom name=\"ground\" type=\"plane\" size=\"0 0 1\"/>\n";
  if (c.bin.present) {
    const double w = c.bin.half_width, t = c.bin.wall_thickness, hh = 0.5 * c.bin.wall_height;
    const double o = w + 0.5 * t, l = w + t;  // wall centre offset, half length (covers the corners)
    x += fmt("    <geom type=\"box\" pos=\"%g 0 %g\" size=\"%g %g %g\"/>\n", o, hh, 0.5 * t, l, hh);
    x += fmt("    <geom type=\"box\" pos=\"%g 0 %g\" size=\"%g %g %g\"/>\n", -o, hh, 0.5 * t, l, hh);
    x += fmt("    <geom type=\"box\" pos=\"0 %g %g\" size=\"%g %g %g\"/>\n", o, hh, l, 0.5 * t, hh);
    x += fmt("    <geom type=\"box\" pos=\"0 %g %g\" size=\"%g %g %g\"/>\n", -o, hh, l, 0.5 * t, hh);
  }
  for (const auto& b : c.bodies) {
    x += fmt("    <body pos=\"%.17g %.17g %.17g\"><freejoint/>", b.x0[0], b.x0[1], b.x0[2]);
    if (b.shape == Shape::Sphere)
      x += fmt("<geom type=\"sphere\" size=\"%.17g\" mass=\"%.17g\"/>", b.size, b.mass);
    else
      x += fmt("<geom type=\"box\" size=\"%.17g %.17g %.17g\" mass=\"%.17g\"/>", b.size, b.size, b.size, b.mass);
    x += "</body>\n";
  }
  x += "  </worldbody>\n</mujoco>\n";
  return x;
}

class MujocoContactSim : public bench::contacts::ContactSim {
 public:
  MujocoContactSim(const ContactCase& c, double h, bool elliptic) : n_(int(c.bodies.size())) {
    const std::string xml = modelXml(c, h, elliptic);
    m_ = bench::loadMujocoModel(xml);
    d_ = mj_makeData(m_);
    for (int i = 0; i < n_; ++i)
      for (int k = 0; k < 3; ++k) d_->qvel[6 * i + k] = c.bodies[i].v0[k];
    mj_forward(m_, d_);
  }
  ~MujocoContactSim() override {
    mj_deleteData(d_);
    mj_deleteModel(m_);
  }
  void step(long n) override {
    for (long i = 0; i < n; ++i) {
      mj_step(m_, d_);
      if (d_->ncon > max_ncon_) max_ncon_ = d_->ncon;
    }
  }
  void observe(std::vector<BodyObs>* out) override {
    out->resize(n_);
    for (int i = 0; i < n_; ++i) {
      const mjtNum* q = d_->qpos + 7 * i;
      const mjtNum* v = d_->qvel + 6 * i;
      mjtNum quat[4] = {q[3], q[4], q[5], q[6]}, wb[3] = {v[3], v[4], v[5]}, ww[3];
      mju_normalize4(quat);
      mju_rotVecQuat(ww, wb, quat);  // free joint: angular velocity in body axes
      BodyObs& o = (*out)[i];
      for (int k = 0; k < 3; ++k) {
        o.x[k] = q[k];
        o.v[k] = v[k];
        o.w[k] = ww[k];
      }
    }
  }
  std::string events() override {
    std::string s = "max ncon " + std::to_string(max_ncon_);
    if (d_->warning[mjWARN_CONTACTFULL].number) s += " CONTACTFULL";
    if (d_->warning[mjWARN_CNSTRFULL].number) s += " CNSTRFULL";
    if (d_->warning[mjWARN_BADQACC].number) s += " BADQACC(reset)";
    return s;
  }

 private:
  int n_;
  int max_ncon_ = 0;
  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
};

void quietWarning(const char*) {}

// pile1000 runs 1 s instead of 5 s here: MuJoCo 2.2.2 needs ~20 ms of CPU per
// step already at 0.8 s (and more as the pile settles), 5 s would take longer
// than the whole suite's budget; its buffers overflow by then anyway.
constexpr double kPileSeconds = 1.0;

}  // namespace

int main(int argc, char** argv) {
  mju_user_warning = quietWarning;
  auto make = [](bool elliptic) {
    return [elliptic](const ContactCase& c, double h) -> std::unique_ptr<bench::contacts::ContactSim> {
      return std::make_unique<MujocoContactSim>(c, h, elliptic);
    };
  };
  std::vector<bench::contacts::ContactConfig> configs = {
      // pile1000: the pyramidal cone needs 4 constraint rows per contact, so
      // njmax = 7000 holds only 1750 contacts (the elliptic cone 2333), far
      // fewer than the settled pile has; measured with the elliptic cone only.
      {"pyramidal", make(false), {"pile1000"}, "MuJoCo 2.2.2 buffer limit (4 rows per contact); see elliptic"},
      {"elliptic", make(true), {}, ""},
  };
  return bench::contacts::runContactSweep("mujoco", std::string("MuJoCo ") + mj_versionString(), configs, argc,
                                          argv, kPileSeconds);
}
