#include "robot_common.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>

#include "sweep_util.h"

#ifndef BENCH_OUT_DIR
#define BENCH_OUT_DIR "bench/out"
#endif

namespace bench {
namespace robots {
namespace {

namespace fs = std::filesystem;
using sweep::runIsolated;
using sweep::selected;
using sweep::splitList;
using sweep::threadCpuSeconds;

void usage(const char* program, const std::string& engine) {
  const char* slash = std::strrchr(program, '/');
  std::printf(
      "usage: %s --robots [options]\n"
      "  --out DIR       output directory (default %s)\n"
      "  --csv PATH      CSV file (default DIR/robots_%s.csv)\n"
      "  --cases a,b     only these cases (atlas_fall, humanoid_fall, kr5_swing, wam_swing)\n"
      "  --configs a,b   only these configs\n"
      "  --reps R        timing repetitions, median reported (default 3)\n"
      "  --list          list configs and exit\n",
      slash ? slash + 1 : program, BENCH_OUT_DIR, engine.c_str());
}

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A mesh filename of the URDF `urdf` as a path: package://pkg/rest through c.packages,
// file://path, absolute, or relative to the URDF's directory.
std::string resolveMesh(const RobotCase& c, const std::string& urdf, const std::string& uri) {
  const std::string pkg = "package://", file = "file://";
  if (uri.rfind(pkg, 0) == 0) {
    const std::string rest = uri.substr(pkg.size());
    const size_t slash = rest.find('/');
    const auto it = c.packages.find(rest.substr(0, slash));
    if (it == c.packages.end() || slash == std::string::npos) return "";
    return it->second + "/" + rest.substr(slash + 1);
  }
  if (uri.rfind(file, 0) == 0) return uri.substr(file.size());
  if (!uri.empty() && uri[0] == '/') return uri;
  return (fs::path(urdf).parent_path() / uri).string();
}

// An ASCII STL ("solid ..." with "facet" lines) as binary STL at `to`; false if `from` is not
// ASCII STL.
bool asciiStlToBinary(const std::string& from, const fs::path& to) {
  std::ifstream in(from);
  std::string word;
  if (!(in >> word) || word != "solid") return false;
  std::vector<float> tris;  // 12 floats a facet: normal, three vertices
  std::string line;
  std::getline(in, line);  // the name
  bool facet_seen = false;
  while (in >> word) {
    if (word == "facet" || word == "vertex") {
      if (word == "facet") {
        facet_seen = true;
        in >> word;  // "normal"
      }
      for (int k = 0; k < 3; ++k) {
        double x = 0;
        in >> x;
        tris.push_back(static_cast<float>(x));
      }
    }
  }
  if (!facet_seen) return false;  // a binary STL whose header starts with "solid"
  std::ofstream out(to, std::ios::binary);
  char header[80] = "binary STL written by bench robot_common";
  out.write(header, sizeof header);
  const std::uint32_t n = static_cast<std::uint32_t>(tris.size() / 12);
  out.write(reinterpret_cast<const char*>(&n), sizeof n);
  const std::uint16_t attribute = 0;
  for (std::uint32_t t = 0; t < n; ++t) {
    out.write(reinterpret_cast<const char*>(&tris[12 * t]), 12 * sizeof(float));
    out.write(reinterpret_cast<const char*>(&attribute), sizeof attribute);
  }
  return true;
}

// The URDF copy for MuJoCo (see PreparedRobot); an error text, or "" on success.
std::string writeMujocoUrdf(const RobotCase& c, PreparedRobot* p) {
  std::string text = readText(p->urdf);
  text = std::regex_replace(text, std::regex("<visual[\\s\\S]*?</visual>"), "");
  if (!c.contacts)
    text = std::regex_replace(text, std::regex("<collision[\\s\\S]*?</collision>"), "");
  const fs::path meshes = fs::path(p->dir) / "meshes";
  fs::create_directories(meshes);
  const std::regex filename("filename\\s*=\\s*[\"']([^\"']*)[\"']");
  std::string out;
  auto last = text.cbegin();
  int k = 0;
  for (std::sregex_iterator it(text.begin(), text.end(), filename), end; it != end; ++it) {
    const std::string target = resolveMesh(c, p->urdf, (*it)[1].str());
    if (target.empty() || !fs::exists(target))
      return "mesh '" + (*it)[1].str() + "' of " + c.urdf + " not found";
    std::string stem = fs::path(target).stem().string();
    const std::string name = "m" + std::to_string(k++) + "_" + stem + ".stl";
    if (!asciiStlToBinary(target, meshes / name)) fs::create_symlink(target, meshes / name);
    out.append(last, (*it)[0].first);
    out += "filename=\"" + name + "\"";
    last = (*it)[0].second;
  }
  out.append(last, text.cend());
  const std::smatch robot = [&] {
    std::smatch m;
    std::regex_search(out, m, std::regex("<robot[^>]*>"));
    return m;
  }();
  if (robot.empty()) return c.urdf + " has no <robot> element";
  const std::string mujoco = "<mujoco><compiler meshdir=\"" + meshes.string() +
                             "/\" discardvisual=\"true\" fusestatic=\"false\"/></mujoco>";
  out.insert(static_cast<size_t>(robot.position(0) + robot.length(0)), mujoco);
  p->mujoco_urdf = (fs::path(p->dir) / (c.name + "_mujoco.urdf")).string();
  std::ofstream(p->mujoco_urdf) << out;
  return "";
}

// The temporary files of a case; an error text (the case is skipped), or "".
std::string prepare(const RobotCase& c, const std::string& out_dir, PreparedRobot* p) {
  if (!c.generate && !fs::exists(c.urdf))
    return c.urdf + " is absent (Debian package dart-doc: apt-get install dart-doc)";
  char tmpl[] = "/tmp/cga_bench_robots_XXXXXX";
  if (!::mkdtemp(tmpl)) return "cannot create a temporary directory";
  p->dir = tmpl;
  p->out_dir = out_dir;
  p->urdf = c.urdf;
  if (c.generate) {
    fs::create_directories(fs::path(p->dir) / "generated");
    p->urdf = (fs::path(p->dir) / (c.name + ".urdf")).string();
    std::ofstream(p->urdf) << c.generate((fs::path(p->dir) / "generated").string());
  }
  if (!c.packages.empty()) {
    const fs::path packages = fs::path(p->dir) / "packages";
    fs::create_directories(packages);
    for (const auto& [name, dir] : c.packages) fs::create_directory_symlink(dir, packages / name);
    const char* old = std::getenv("ROS_PACKAGE_PATH");
    const std::string path = packages.string() + (old && *old ? ":" + std::string(old) : "");
    ::setenv("ROS_PACKAGE_PATH", path.c_str(), 1);
  }
  return writeMujocoUrdf(c, p);
}

double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

std::string g5(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.5g", v);
  return b;
}

}  // namespace

std::string pairsFile(const PreparedRobot& p, const RobotCase& c) {
  return p.out_dir + "/robot_pairs_" + c.name + ".txt";
}

bool robotsRequested(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--robots") == 0) return true;
  return false;
}

int runRobotSweep(const std::string& engine, const std::string& version,
                  const std::vector<RobotConfig>& configs, int argc, char** argv) {
  std::string out_dir = BENCH_OUT_DIR, csv_path;
  std::vector<std::string> case_filter, config_filter;
  int reps = 3;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        usage(argv[0], engine);
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--robots") continue;
    if (a == "--out")
      out_dir = next();
    else if (a == "--csv")
      csv_path = next();
    else if (a == "--cases")
      case_filter = splitList(next());
    else if (a == "--configs")
      config_filter = splitList(next());
    else if (a == "--reps")
      reps = std::max(1, std::atoi(next().c_str()));
    else if (a == "--list") {
      for (const RobotConfig& c : configs) std::printf("%s\n", c.name.c_str());
      return 0;
    } else {
      usage(argv[0], engine);
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  fs::create_directories(out_dir);
  if (csv_path.empty()) csv_path = out_dir + "/robots_" + engine + ".csv";
  FILE* csv = std::fopen(csv_path.c_str(), "w");
  if (!csv) {
    std::fprintf(stderr, "cannot open %s\n", csv_path.c_str());
    return 2;
  }
  std::fprintf(csv,
               "engine,config,case,phase,t_start,t_end,h,cpu_ms_per_step,wall_ms_per_step,"
               "rtf_cpu,root_z,kinetic_J,contacts,notes\n");
  std::fprintf(stderr, "[%s] %s -> %s\n", engine.c_str(), version.c_str(), csv_path.c_str());

  for (const RobotCase& c : allRobotCases()) {
    if (!selected(case_filter, c.name)) continue;
    PreparedRobot prepared;
    const std::string why = prepare(c, out_dir, &prepared);
    if (!why.empty()) {
      std::fprintf(stderr, "[%s] %s skipped: %s\n", engine.c_str(), c.name.c_str(), why.c_str());
      if (!prepared.dir.empty()) fs::remove_all(prepared.dir);
      continue;
    }
    const size_t np = c.phase_ends.size();
    std::vector<long> steps(np);
    for (size_t k = 0; k < np; ++k)
      steps[k] = std::lround((c.phase_ends[k] - (k ? c.phase_ends[k - 1] : 0.0)) / c.h);
    for (const RobotConfig& cfg : configs) {
      if (!selected(config_filter, cfg.name) || !cfg.applies(c)) continue;
      // Per phase: CPU and wall times of every repetition; observations of the first.
      std::vector<std::vector<double>> cpu(np), wall(np);
      std::vector<std::string> obs(np);
      bool crashed = false;
      for (int r = 0; r < reps && !crashed; ++r) {
        std::string text;
        const bool ok = runIsolated(
            [&]() {
              std::unique_ptr<RobotSim> sim = cfg.make(c, prepared);
              std::ostringstream os;
              os.precision(17);
              for (size_t k = 0; k < np; ++k) {
                const double c0 = threadCpuSeconds();
                const auto t0 = std::chrono::steady_clock::now();
                sim->step(steps[k]);
                const auto t1 = std::chrono::steady_clock::now();
                const double c1 = threadCpuSeconds();
                const RobotObs o = sim->observe();
                os << (c1 - c0) * 1e3 / double(steps[k]) << " "
                   << std::chrono::duration<double, std::milli>(t1 - t0).count() / double(steps[k])
                   << " " << o.root_z << " " << o.kinetic << " " << o.contacts << "\t"
                   << sweep::csvSafe(o.note) << "\n";
              }
              return os.str();
            },
            &text);
        if (!ok) {
          crashed = true;
          break;
        }
        std::istringstream is(text);
        for (size_t k = 0; k < np; ++k) {
          std::string line;
          std::getline(is, line);
          double cp = NAN, wl = NAN;
          std::sscanf(line.c_str(), "%lf %lf", &cp, &wl);
          cpu[k].push_back(cp);
          wall[k].push_back(wl);
          if (r == 0) obs[k] = line;
        }
      }
      for (size_t k = 0; k < np; ++k) {
        const double t0 = k ? c.phase_ends[k - 1] : 0.0, t1 = c.phase_ends[k];
        const double cp = median(cpu[k]), wl = median(wall[k]);
        double z = NAN, ke = NAN;
        int ncon = -1;
        std::string note = crashed ? "crashed (run aborted or threw)" : "";
        if (!obs[k].empty()) {
          std::sscanf(obs[k].c_str(), "%*f %*f %lf %lf %d", &z, &ke, &ncon);
          const size_t tab = obs[k].find('\t');
          if (tab != std::string::npos) note += obs[k].substr(tab + 1);
        }
        std::fprintf(csv, "%s,%s,%s,%s,%g,%g,%g,%.6g,%.6g,%.4g,%.6g,%.6g,%d,%s\n", engine.c_str(),
                     cfg.name.c_str(), c.name.c_str(), c.phase_names[k].c_str(), t0, t1, c.h, cp,
                     wl, c.h * 1e3 / cp, z, ke, ncon, sweep::csvSafe(note).c_str());
        std::fflush(csv);
        std::fprintf(stderr,
                     "[%s] %-12s %-10s %-6s [%g, %g) s: %8.4f ms/step cpu (%8.4f wall)  RTF %-7s"
                     "  root z %-9s KE %-9s contacts %d  %s\n",
                     engine.c_str(), cfg.name.c_str(), c.name.c_str(), c.phase_names[k].c_str(), t0,
                     t1, cp, wl, g5(c.h * 1e3 / cp).c_str(), g5(z).c_str(), g5(ke).c_str(), ncon,
                     note.c_str());
      }
    }
    fs::remove_all(prepared.dir);
  }
  std::fclose(csv);
  return 0;
}

}  // namespace robots
}  // namespace bench
