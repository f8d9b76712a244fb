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
//
// With --robots, the real robots of robot_cases.h (driver robot_common.h), each read by
// MuJoCo's own URDF import from the copy robot_common prepares (visuals dropped, meshes as .stl
// symlinks, compiler meshdir, discardvisual, fusestatic="false"; its inertials, joint limits
// and joint damping are the URDF's, as ours). MuJoCo's URDF import fixes the root link to the
// world, so for a floating robot the compiled model is saved as MJCF (mj_saveLastXML) and
// reloaded with a <freejoint/> in the root body; a contact case also gets the floor (a plane
// geom at the case's height) and buffers of nconmax 1000, njmax 4000. Every geom then has
// friction 0.5 (our default μ; condim 3, pyramidal cone, default solref/solimp: critically
// damped, the nearest to our e = 0), timestep = the case's h, integrator Euler, solver Newton
// (defaults). A case without contacts runs with <flag contact="disable"/>
// (mjDSBL_CONTACT). Configs:
//   Euler            MuJoCo's default pairs: every pair of bodies but a body and its parent
//                    (filterparent), which collides more pairs than our `auto` (which also
//                    leaves out the pairs that overlap at the initial configuration);
//   Euler_our_pairs  contact cases only: <contact><exclude> for every pair of bodies with
//                    geoms that our World does not let collide (bench/out/robot_pairs_<case>.txt,
//                    written by `bench_contacts --robots`; skipped when absent), so both
//                    engines test the same pairs.
// --starts K --start-shift DZ: the driver's perturbed starts (robot_common.h), the floor geom
// at the shifted case's height, as ours.
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include <mujoco/mujoco.h>

#include "contact_common.h"
#include "mujoco_model.h"
#include "robot_common.h"

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


// A real robot (robot_cases.h) read from its URDF; see the header comment.
class MujocoRobotSim : public bench::robots::RobotSim {
 public:
  MujocoRobotSim(const bench::robots::RobotCase& c, const bench::robots::PreparedRobot& p,
                 bool our_pairs) {
    char err[1000] = "";
    m_ = mj_loadXML(p.mujoco_urdf.c_str(), nullptr, err, sizeof err);
    if (!m_) throw std::runtime_error("mj_loadXML(" + p.mujoco_urdf + "): " + err);
    if (c.floating || c.contacts) {
      const std::string saved = p.dir + "/" + c.name + "_saved.xml";
      if (!mj_saveLastXML(saved.c_str(), m_, err, sizeof err))
        throw std::runtime_error(std::string("mj_saveLastXML: ") + err);
      std::ifstream in(saved);
      std::stringstream ss;
      ss << in.rdbuf();
      std::string xml = ss.str();
      if (c.floating) insertAfter(&xml, "<body name=\"" + c.root_link + "\"", "<freejoint/>");
      if (c.contacts) {
        insertAfter(&xml, "<worldbody",
                    fmt("<geom name=\"bench_floor\" type=\"plane\" size=\"0 0 1\" pos=\"0 0 "
                        "%.17g\"/>",
                        c.ground_z));
        const size_t size = xml.find("<size ");
        if (size != std::string::npos) xml.erase(size, xml.find('>', size) + 1 - size);
        insertAfter(&xml, "<mujoco", "<size nconmax=\"1000\" njmax=\"4000\"/>");
        if (our_pairs) {
          const std::string excludes = excludeList(c, p);
          xml.insert(xml.rfind("</mujoco>"), "<contact>" + excludes + "</contact>\n");
        }
      }
      const std::string edited = p.dir + "/" + c.name + "_edited.xml";
      std::ofstream(edited) << xml;
      mj_deleteModel(m_);
      m_ = mj_loadXML(edited.c_str(), nullptr, err, sizeof err);
      if (!m_) throw std::runtime_error("mj_loadXML(" + edited + "): " + err);
    }
    m_->opt.timestep = c.h;
    m_->opt.integrator = mjINT_EULER;
    if (!c.contacts) m_->opt.disableflags |= mjDSBL_CONTACT;
    for (int g = 0; g < m_->ngeom; ++g) m_->geom_friction[3 * g] = 0.5;
    floor_ = mj_name2id(m_, mjOBJ_GEOM, "bench_floor");
    root_ = c.floating ? mj_name2id(m_, mjOBJ_BODY, c.root_link.c_str()) : -1;
    d_ = mj_makeData(m_);
    e0_ = energy();
  }
  ~MujocoRobotSim() override {
    mj_deleteData(d_);
    mj_deleteModel(m_);
  }
  void step(long n) override {
    for (long i = 0; i < n; ++i) mj_step(m_, d_);
  }
  bench::robots::RobotObs observe() override {
    bench::robots::RobotObs o;
    mjData* d = mj_makeData(m_);
    const double e = energy(d);
    o.kinetic = d->energy[1];
    o.root_z = root_ >= 0 ? d->xpos[3 * root_ + 2] : 0.0;
    o.contacts = d->ncon;
    int self = 0;
    double depth = 0;
    std::string deepest;
    for (int k = 0; k < d->ncon; ++k) {
      const mjContact& con = d->contact[k];
      if (con.geom1 != floor_ && con.geom2 != floor_) ++self;
      if (-con.dist > depth) {
        depth = -con.dist;
        const auto body = [&](int g) {
          return g == floor_ ? std::string("floor") : mj_id2name(m_, mjOBJ_BODY, m_->geom_bodyid[g]);
        };
        deepest = body(con.geom1) + "/" + body(con.geom2);
      }
    }
    mj_deleteData(d);
    o.max_depth = depth;
    o.energy = e - e0_;  // MuJoCo 2.2 has no sleeping: o.asleep stays -1
    o.note = fmt("self %d; max depth %.3g m (%s); energy change %.4g J", self, depth,
                 deepest.c_str(), o.energy);
    if (d_->warning[mjWARN_CONTACTFULL].number) o.note += "; CONTACTFULL";
    if (d_->warning[mjWARN_CNSTRFULL].number) o.note += "; CNSTRFULL";
    if (d_->warning[mjWARN_BADQACC].number) o.note += "; BADQACC(reset)";
    return o;
  }

 private:
  static void insertAfter(std::string* xml, const std::string& tag_start, const std::string& what) {
    const size_t at = xml->find(tag_start);
    if (at == std::string::npos) throw std::runtime_error("no " + tag_start + " in the saved MJCF");
    xml->insert(xml->find('>', at) + 1, what);
  }
  // Every pair of bodies with geoms that our World does not let collide.
  std::string excludeList(const bench::robots::RobotCase& c,
                          const bench::robots::PreparedRobot& p) const {
    std::ifstream in(bench::robots::pairsFile(p, c));
    if (!in) throw std::runtime_error(bench::robots::pairsFile(p, c) +
                                      " is absent: run bench_contacts --robots first");
    std::set<std::pair<std::string, std::string>> allowed;
    std::string a, b;
    while (in >> a >> b) allowed.insert(std::minmax(a, b));
    std::string out;
    for (int i = 1; i < m_->nbody; ++i)
      for (int j = i + 1; j < m_->nbody; ++j) {
        if (m_->body_geomnum[i] == 0 || m_->body_geomnum[j] == 0) continue;
        const std::string ni = mj_id2name(m_, mjOBJ_BODY, i), nj = mj_id2name(m_, mjOBJ_BODY, j);
        if (allowed.count(std::minmax(ni, nj)) == 0)
          out += "<exclude body1=\"" + ni + "\" body2=\"" + nj + "\"/>";
      }
    return out;
  }
  // The potential and kinetic energy of the current state, and its contacts (d->ncon,
  // d->contact), from mj_forward with the energy flag on a copy of the data, so that observing
  // leaves the run (its warm start) as it was.
  double energy(mjData* out = nullptr) {
    mjData* d = mj_copyData(out, m_, d_);
    m_->opt.enableflags |= mjENBL_ENERGY;
    mj_forward(m_, d);
    m_->opt.enableflags &= ~mjENBL_ENERGY;
    const double e = d->energy[0] + d->energy[1];
    if (!out) mj_deleteData(d);
    return e;
  }
  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  int floor_ = -1, root_ = -1;
  double e0_ = 0;
};

void quietWarning(const char*) {}

// pile1000 runs 1 s instead of 5 s here: MuJoCo 2.2.2 needs ~20 ms of CPU per
// step already at 0.8 s (and more as the pile settles), 5 s would take longer
// than the whole suite's budget; its buffers overflow by then anyway.
constexpr double kPileSeconds = 1.0;

}  // namespace

int main(int argc, char** argv) {
  mju_user_warning = quietWarning;
  if (bench::robots::robotsRequested(argc, argv)) {
    auto make_robot = [](bool our_pairs) {
      return [our_pairs](const bench::robots::RobotCase& c, const bench::robots::PreparedRobot& p)
                 -> std::unique_ptr<bench::robots::RobotSim> {
        return std::make_unique<MujocoRobotSim>(c, p, our_pairs);
      };
    };
    std::vector<bench::robots::RobotConfig> robot_configs = {
        {"Euler", make_robot(false)},
        {"Euler_our_pairs", make_robot(true),
         [](const bench::robots::RobotCase& c) { return c.contacts; }},
    };
    return bench::robots::runRobotSweep("mujoco", std::string("MuJoCo ") + mj_versionString(),
                                        robot_configs, argc, argv);
  }
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
