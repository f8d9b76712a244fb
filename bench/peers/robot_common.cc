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
      "  --starts K      perturbed starts of a contact case: start k lowers the ground plane by\n"
      "                  k*DZ; the CSV reports the mean over the starts, a second CSV (its name\n"
      "                  with _starts, default DIR/robots_%s_starts.csv) each start\n"
      "                  (default 1: the case as written, no second CSV)\n"
      "  --start-shift DZ  metres the plane drops from one start to the next (default 3e-4)\n"
      "  --list          list configs and exit\n",
      slash ? slash + 1 : program, BENCH_OUT_DIR, engine.c_str(), engine.c_str());
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

// One start's figures for one phase: the medians over the repetitions and the first
// repetition's observations.
struct StartPhase {
  double cpu = NAN, wall = NAN;
  RobotObs obs;
  bool observed = false;
};

// The line a child writes per phase (timings, observations, a tab, the note) and its reading.
std::string phaseLine(double cpu_ms, double wall_ms, const RobotObs& o) {
  std::ostringstream os;
  os.precision(17);
  os << cpu_ms << " " << wall_ms << " " << o.root_z << " " << o.kinetic << " " << o.contacts << " "
     << o.max_depth << " " << o.energy << " " << o.asleep << "\t" << sweep::csvSafe(o.note) << "\n";
  return os.str();
}

void readPhaseLine(const std::string& line, double* cpu, double* wall, RobotObs* o) {
  std::sscanf(line.c_str(), "%lf %lf %lf %lf %d %lf %lf %d", cpu, wall, &o->root_z, &o->kinetic,
              &o->contacts, &o->max_depth, &o->energy, &o->asleep);
  const size_t tab = line.find('\t');
  o->note = tab == std::string::npos ? "" : line.substr(tab + 1);
}

// DIR/name.csv -> DIR/name_starts.csv.
std::string startsCsvPath(const std::string& csv_path) {
  const std::string ext = ".csv";
  if (csv_path.size() > ext.size() &&
      csv_path.compare(csv_path.size() - ext.size(), ext.size(), ext) == 0)
    return csv_path.substr(0, csv_path.size() - ext.size()) + "_starts.csv";
  return csv_path + "_starts.csv";
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
  int reps = 3, starts = 1;
  double start_shift = 3e-4;
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
    else if (a == "--starts")
      starts = std::max(1, std::atoi(next().c_str()));
    else if (a == "--start-shift") {
      const std::string text = next();
      char* end = nullptr;
      start_shift = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0' || !std::isfinite(start_shift) || start_shift < 0) {
        std::fprintf(stderr, "--start-shift wants a distance >= 0 in metres\n");
        return 2;
      }
    } else if (a == "--list") {
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
  FILE* starts_csv = nullptr;
  if (starts > 1) {
    const std::string path = startsCsvPath(csv_path);
    starts_csv = std::fopen(path.c_str(), "w");
    if (!starts_csv) {
      std::fprintf(stderr, "cannot open %s\n", path.c_str());
      std::fclose(csv);
      return 2;
    }
    std::fprintf(starts_csv,
                 "engine,config,case,phase,start,ground_z,t_start,t_end,h,cpu_ms_per_step,"
                 "wall_ms_per_step,rtf_cpu,root_z,kinetic_J,contacts,max_depth_m,energy_J,asleep,"
                 "notes\n");
    std::fprintf(stderr, "[%s] %s -> %s, %s (%d starts, the plane lowered by %g m a start)\n",
                 engine.c_str(), version.c_str(), csv_path.c_str(), path.c_str(), starts,
                 start_shift);
  } else {
    std::fprintf(stderr, "[%s] %s -> %s\n", engine.c_str(), version.c_str(), csv_path.c_str());
  }

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
    // The starts: the case with its plane lowered by s·start_shift (contact cases only).
    const int case_starts = c.contacts ? starts : 1;
    std::vector<RobotCase> shifted(case_starts, c);
    for (int s = 0; s < case_starts; ++s) shifted[s].ground_z = c.ground_z - s * start_shift;
    for (const RobotConfig& cfg : configs) {
      if (!selected(config_filter, cfg.name) || !cfg.applies(c)) continue;
      // Per start and phase: CPU and wall times of every repetition; observations of the first.
      std::vector<std::vector<std::vector<double>>> cpu(case_starts,
                                                        std::vector<std::vector<double>>(np)),
          wall = cpu;
      std::vector<std::vector<StartPhase>> result(case_starts, std::vector<StartPhase>(np));
      std::vector<bool> crashed(case_starts, false);
      for (int r = 0; r < reps; ++r)
        for (int s = 0; s < case_starts; ++s) {
          if (crashed[s]) continue;
          const RobotCase& cs = shifted[s];
          std::string text;
          const bool ok = runIsolated(
              [&]() {
                std::unique_ptr<RobotSim> sim = cfg.make(cs, prepared);
                std::string lines;
                for (size_t k = 0; k < np; ++k) {
                  const double c0 = threadCpuSeconds();
                  const auto t0 = std::chrono::steady_clock::now();
                  sim->step(steps[k]);
                  const auto t1 = std::chrono::steady_clock::now();
                  const double c1 = threadCpuSeconds();
                  lines += phaseLine(
                      (c1 - c0) * 1e3 / double(steps[k]),
                      std::chrono::duration<double, std::milli>(t1 - t0).count() / double(steps[k]),
                      sim->observe());
                }
                return lines;
              },
              &text);
          if (!ok) {
            crashed[s] = true;
            continue;
          }
          std::istringstream is(text);
          for (size_t k = 0; k < np; ++k) {
            std::string line;
            std::getline(is, line);
            double cp = NAN, wl = NAN;
            RobotObs o;
            readPhaseLine(line, &cp, &wl, &o);
            cpu[s][k].push_back(cp);
            wall[s][k].push_back(wl);
            if (!result[s][k].observed) {
              result[s][k].obs = o;
              result[s][k].observed = true;
            }
          }
        }
      for (int s = 0; s < case_starts; ++s)
        for (size_t k = 0; k < np; ++k) {
          result[s][k].cpu = median(cpu[s][k]);
          result[s][k].wall = median(wall[s][k]);
        }
      for (size_t k = 0; k < np; ++k) {
        const double t0 = k ? c.phase_ends[k - 1] : 0.0, t1 = c.phase_ends[k];
        // Each start's row (K > 1) and its line.
        for (int s = 0; s < case_starts && case_starts > 1; ++s) {
          const StartPhase& sp = result[s][k];
          std::string note = crashed[s] ? "crashed (run aborted or threw) " : "";
          note += sp.obs.note;
          const RobotObs& o = sp.obs;
          const int ncon = sp.observed ? o.contacts : -1;
          const double z = sp.observed ? o.root_z : NAN, ke = sp.observed ? o.kinetic : NAN;
          std::fprintf(starts_csv,
                       "%s,%s,%s,%s,%d,%.9g,%g,%g,%g,%.6g,%.6g,%.4g,%.6g,%.6g,%d,%.4g,%.6g,%d,%s\n",
                       engine.c_str(), cfg.name.c_str(), c.name.c_str(), c.phase_names[k].c_str(),
                       s, shifted[s].ground_z, t0, t1, c.h, sp.cpu, sp.wall, c.h * 1e3 / sp.cpu, z,
                       ke, ncon, o.max_depth, o.energy, o.asleep, sweep::csvSafe(note).c_str());
          std::fflush(starts_csv);
          std::fprintf(stderr,
                       "[%s] %-12s %-10s %-6s start %d (plane %.6g): %8.4f ms/step cpu (%8.4f "
                       "wall)  root z %-9s KE %-9s contacts %d  %s\n",
                       engine.c_str(), cfg.name.c_str(), c.name.c_str(), c.phase_names[k].c_str(),
                       s, shifted[s].ground_z, sp.cpu, sp.wall, g5(z).c_str(), g5(ke).c_str(), ncon,
                       note.c_str());
        }
        // The (config, case, phase) row: start 0 alone, or the mean over the starts that ran.
        const StartPhase& first = result[0][k];
        double cp = first.cpu, wl = first.wall;
        std::string note = crashed[0] ? "crashed (run aborted or threw)" : "";
        if (case_starts > 1) {
          double cpu_sum = 0, wall_sum = 0, cpu_min = INFINITY, cpu_max = -INFINITY,
                 wall_min = INFINITY, wall_max = -INFINITY;
          int ran = 0, asleep = 0, sleep_known = 0;
          for (int s = 0; s < case_starts; ++s) {
            const StartPhase& sp = result[s][k];
            if (crashed[s] || !std::isfinite(sp.cpu)) continue;
            ++ran;
            cpu_sum += sp.cpu, wall_sum += sp.wall;
            cpu_min = std::min(cpu_min, sp.cpu), cpu_max = std::max(cpu_max, sp.cpu);
            wall_min = std::min(wall_min, sp.wall), wall_max = std::max(wall_max, sp.wall);
            if (sp.obs.asleep >= 0) ++sleep_known, asleep += sp.obs.asleep;
          }
          cp = ran ? cpu_sum / ran : NAN;
          wl = ran ? wall_sum / ran : NAN;
          char b[400];
          std::snprintf(b, sizeof b,
                        "mean of %d starts (plane lowered 0 to %.3g m); cpu [%.4g; %.4g]; "
                        "wall [%.4g; %.4g] ms/step",
                        ran, (case_starts - 1) * start_shift, cpu_min, cpu_max, wall_min, wall_max);
          const std::string asleep_of =
              std::to_string(asleep) + " of " + std::to_string(sleep_known);
          std::string summary = b;
          if (ran < case_starts)
            summary += "; " + std::to_string(case_starts - ran) + " starts crashed";
          if (sleep_known > 0) summary += "; asleep at the phase's end in " + asleep_of;
          note = summary + "; start 0: " + note;
          const std::string sleeping = sleep_known > 0 ? "  asleep at the end in " + asleep_of : "";
          std::fprintf(stderr,
                       "[%s] %-12s %-10s %-6s [%g, %g) s over %d starts: %8.4f ms/step cpu [%.4f, "
                       "%.4f] (%8.4f wall [%.4f, %.4f])  RTF %s%s\n",
                       engine.c_str(), cfg.name.c_str(), c.name.c_str(), c.phase_names[k].c_str(),
                       t0, t1, ran, cp, cpu_min, cpu_max, wl, wall_min, wall_max,
                       g5(c.h * 1e3 / cp).c_str(), sleeping.c_str());
        } else if (starts > 1) {
          note = "one start (no plane to lower); " + note;
        }
        double z = NAN, ke = NAN;
        int ncon = -1;
        if (first.observed) {
          z = first.obs.root_z, ke = first.obs.kinetic, ncon = first.obs.contacts;
          note += first.obs.note;
        }
        std::fprintf(csv, "%s,%s,%s,%s,%g,%g,%g,%.6g,%.6g,%.4g,%.6g,%.6g,%d,%s\n", engine.c_str(),
                     cfg.name.c_str(), c.name.c_str(), c.phase_names[k].c_str(), t0, t1, c.h, cp,
                     wl, c.h * 1e3 / cp, z, ke, ncon, sweep::csvSafe(note).c_str());
        std::fflush(csv);
        if (case_starts == 1)
          std::fprintf(stderr,
                       "[%s] %-12s %-10s %-6s [%g, %g) s: %8.4f ms/step cpu (%8.4f wall)  RTF %-7s"
                       "  root z %-9s KE %-9s contacts %d  %s\n",
                       engine.c_str(), cfg.name.c_str(), c.name.c_str(), c.phase_names[k].c_str(),
                       t0, t1, cp, wl, g5(c.h * 1e3 / cp).c_str(), g5(z).c_str(), g5(ke).c_str(),
                       ncon, note.c_str());
      }
    }
    fs::remove_all(prepared.dir);
  }
  std::fclose(csv);
  if (starts_csv) std::fclose(starts_csv);
  return 0;
}

}  // namespace robots
}  // namespace bench
