// MuJoCo runner of measured cube tosses (Debian libmujoco-dev 2.2.2): peer_tosses_mujoco, driven
// by bench/tosses_vs_mujoco.py (doc/fitting.md#speed-against-mujoco).
//
//   peer_tosses_mujoco STARTS.csv OUT.csv --dt S --mu MU --dampratio Z --height H
//                      [--threads N] [--cone elliptic|pyramidal]
//
// STARTS.csv: one toss per line, no header: samples steps_per_sample half_width mass inertia
// x y z qw qx qy qz vx vy vz wx wy wz (the centre and the velocities in world axes). For each
// toss the cube (a <freejoint> body with one box geom and the given inertia) starts in that
// state above the plane z = H and is stepped `samples` × `steps_per_sample` steps of dt with
// mj_step (semi-implicit Euler, the Newton solver, MuJoCo's defaults), its pose recorded every
// steps_per_sample steps. OUT.csv: per sample, toss index, sample, x y z qw qx qy qz.
// Friction: geom friction (μ, 0, 0), condim 3, on the box and the plane (MuJoCo takes the
// larger of two; they are equal). Restitution: MuJoCo has none; its contact is a damped
// spring, solref = (0.02 s, damping ratio Z): Z = −ln e / √(π² + ln² e) is the nearest to a
// coefficient e (bench/peers/contacts_mujoco.cc). Tosses are split over N threads, one mjData
// each; stdout gets the wall time of the stepping alone: "stepping_seconds S".
#include <mujoco/mujoco.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

struct Toss {
  int samples = 0, steps = 0;
  double half = 0, mass = 0, inertia = 0;
  double s[13] = {};  // x y z qw qx qy qz vx vy vz wx wy wz
};

[[noreturn]] void die(const std::string& m) {
  std::fprintf(stderr, "peer_tosses_mujoco: %s\n", m.c_str());
  std::exit(2);
}

std::string modelXml(const Toss& t, double dt, double mu, double damp, double height,
                     const std::string& cone) {
  std::ostringstream x;
  x.precision(17);
  x << "<mujoco model='cube_tosses'><option timestep='" << dt << "' gravity='0 0 -9.81' cone='"
    << cone << "'/><worldbody><geom name='floor' type='plane' size='0 0 1' pos='0 0 " << height
    << "' friction='" << mu << " 0 0' solref='0.02 " << damp
    << "'/><body name='cube' pos='0 0 1'><freejoint/><inertial pos='0 0 0' mass='" << t.mass
    << "' diaginertia='" << t.inertia << " " << t.inertia << " " << t.inertia
    << "'/><geom type='box' size='" << t.half << " " << t.half << " " << t.half
    << "' friction='" << mu << " 0 0' solref='0.02 " << damp
    << "'/></body></worldbody></mujoco>";
  return x.str();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) die("usage: STARTS.csv OUT.csv --dt S --mu MU --dampratio Z --height H");
  double dt = 0.002, mu = 0.2, damp = 1.0, height = 0.0;
  int threads = 1;
  std::string cone = "elliptic";
  for (int i = 3; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    const char* v = argv[i + 1];
    if (k == "--dt") dt = std::atof(v);
    else if (k == "--mu") mu = std::atof(v);
    else if (k == "--dampratio") damp = std::atof(v);
    else if (k == "--height") height = std::atof(v);
    else if (k == "--threads") threads = std::atoi(v);
    else if (k == "--cone") cone = v;
    else die("unknown option " + k);
  }
  std::vector<Toss> tosses;
  std::ifstream in(argv[1]);
  if (!in) die(std::string("cannot read ") + argv[1]);
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    std::istringstream ls(line);
    Toss t;
    ls >> t.samples >> t.steps >> t.half >> t.mass >> t.inertia;
    for (double& v : t.s) ls >> v;
    if (!ls) die("bad line: " + line);
    tosses.push_back(t);
  }
  if (tosses.empty()) die("no toss");
  char err[1000] = "";
  const std::string path = std::string(argv[2]) + ".xml";
  {
    std::ofstream x(path);
    x << modelXml(tosses[0], dt, mu, damp, height, cone);
  }
  mjModel* m = mj_loadXML(path.c_str(), nullptr, err, sizeof err);
  if (!m) die(std::string("MuJoCo refused the model: ") + err);
  std::vector<std::vector<double>> out(tosses.size());
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    mjData* d = mj_makeData(m);
    for (std::size_t k = next++; k < tosses.size(); k = next++) {
      const Toss& t = tosses[k];
      mj_resetData(m, d);
      for (int i = 0; i < 7; ++i) d->qpos[i] = t.s[i];
      // free joint: linear velocity in world axes, angular velocity in the body's axes
      const double* q = t.s + 3;
      const double w[3] = {t.s[10], t.s[11], t.s[12]};
      double R[9];
      mju_quat2Mat(R, q);
      for (int i = 0; i < 3; ++i) {
        d->qvel[i] = t.s[7 + i];
        d->qvel[3 + i] = R[0 * 3 + i] * w[0] + R[1 * 3 + i] * w[1] + R[2 * 3 + i] * w[2];
      }
      std::vector<double>& o = out[k];
      o.reserve(7 * (t.samples + 1));
      o.insert(o.end(), d->qpos, d->qpos + 7);
      for (int s = 0; s < t.samples; ++s) {
        for (int j = 0; j < t.steps; ++j) mj_step(m, d);
        o.insert(o.end(), d->qpos, d->qpos + 7);
      }
    }
    mj_deleteData(d);
  };
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(work);
  work();
  for (auto& th : pool) th.join();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  mj_deleteModel(m);
  FILE* f = std::fopen(argv[2], "w");
  if (!f) die(std::string("cannot write ") + argv[2]);
  for (std::size_t k = 0; k < out.size(); ++k)
    for (std::size_t s = 0; s * 7 < out[k].size(); ++s) {
      std::fprintf(f, "%zu,%zu", k, s);
      for (int i = 0; i < 7; ++i) std::fprintf(f, ",%.17g", out[k][7 * s + i]);
      std::fprintf(f, "\n");
    }
  std::fclose(f);
  std::printf("stepping_seconds %.6f\n", seconds);
  return 0;
}
