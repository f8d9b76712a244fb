#include "articulated_common.h"

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "articulated_reference.h"
#include "sweep_util.h"

#ifndef BENCH_OUT_DIR
#define BENCH_OUT_DIR "bench/out"
#endif

namespace bench {
namespace articulated {
namespace {

using sweep::runIsolated;
using sweep::selected;
using sweep::splitList;
using sweep::threadCpuSeconds;

constexpr double kMaxJointSpeed = 1e3;  // rad/s: beyond it a run counts as blown up

void usage(const char* program, const std::string& engine) {
  const char* slash = std::strrchr(program, '/');
  std::printf(
      "usage: %s [options]\n"
      "  --out DIR          output directory (default %s)\n"
      "  --csv PATH         CSV file (default DIR/articulated_%s.csv)\n"
      "  --cases a,b        only these cases (double_pendulum, arm7, satellite)\n"
      "  --configs a,b      only these configs (default: the default-sweep ones)\n"
      "  --all-configs      all configs, including those left out of the default sweep\n"
      "  --hs 1e-3,1e-4     step sizes (default 1e-2 ... 1e-5, 10 values)\n"
      "  --timing-steps N   steps per timing run, capped at T/h (default 20000)\n"
      "  --reps R           timing repetitions, median reported (default 3)\n"
      "  --min-h H          skip step sizes below H (this runner's default budget floor: see "
      "--list)\n"
      "  --list             list configs and exit\n"
      "  --prepare          only compute/cache the reference solutions, then exit\n"
      "  --version          print engine version and exit\n",
      slash ? slash + 1 : program, BENCH_OUT_DIR, engine.c_str());
}

struct Timing {
  double cpu_ns, wall_ns;
};

struct ErrorRun {
  double err_q, err_qd, drift;
  int blew;
};

bool badState(const std::vector<double>& q, const std::vector<double>& qd) {
  for (double v : q)
    if (!std::isfinite(v)) return true;
  for (double v : qd)
    if (!std::isfinite(v) || std::fabs(v) > kMaxJointSpeed) return true;
  return false;
}

}  // namespace

std::vector<double> defaultArticulatedSteps() {
  return {1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5};
}

ArticulatedCsv::ArticulatedCsv(const std::string& path) : file_(std::fopen(path.c_str(), "w")) {
  if (!file_) {
    std::fprintf(stderr, "cannot open %s\n", path.c_str());
    std::exit(2);
  }
  std::fprintf(static_cast<FILE*>(file_), "%s\n", header());
  std::fflush(static_cast<FILE*>(file_));
}

ArticulatedCsv::~ArticulatedCsv() { std::fclose(static_cast<FILE*>(file_)); }

void ArticulatedCsv::row(const std::string& engine, const std::string& config,
                         const std::string& case_name, double h, double cpu_ns, double wall_ns,
                         double err_q, double err_qd, double drift, bool blew,
                         const std::string& notes) {
  std::fprintf(static_cast<FILE*>(file_), "%s,%s,%s,%.6g,%.6g,%.6g,%.6e,%.6e,%.6e,%d,%s\n",
               engine.c_str(), config.c_str(), case_name.c_str(), h, cpu_ns, wall_ns, err_q, err_qd,
               drift, blew ? 1 : 0, sweep::csvSafe(notes).c_str());
  std::fflush(static_cast<FILE*>(file_));
}

int runArticulatedSweep(const std::string& engine, const std::string& version,
                        const std::vector<ArticulatedConfig>& configs, int argc, char** argv,
                        const ArticulatedDefaults& defaults) {
  std::string out_dir = BENCH_OUT_DIR, csv_path;
  std::vector<std::string> case_filter, config_filter;
  std::vector<double> hs = defaults.hs.empty() ? defaultArticulatedSteps() : defaults.hs;
  long timing_steps = defaults.timing_steps;
  int reps = defaults.reps;
  double min_h = defaults.min_h;
  bool all_configs = false, prepare_only = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        usage(argv[0], engine);
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--out")
      out_dir = next();
    else if (a == "--csv")
      csv_path = next();
    else if (a == "--cases")
      case_filter = splitList(next());
    else if (a == "--configs")
      config_filter = splitList(next());
    else if (a == "--all-configs")
      all_configs = true;
    else if (a == "--prepare")
      prepare_only = true;
    else if (a == "--hs") {
      hs.clear();
      for (const std::string& t : splitList(next())) hs.push_back(std::strtod(t.c_str(), nullptr));
    } else if (a == "--timing-steps")
      timing_steps = std::max(1L, std::atol(next().c_str()));
    else if (a == "--reps")
      reps = std::max(1, std::atoi(next().c_str()));
    else if (a == "--min-h")
      min_h = std::strtod(next().c_str(), nullptr);
    else if (a == "--list") {
      for (const ArticulatedConfig& c : configs)
        std::printf("%s%s\n", c.name.c_str(), c.in_default_sweep ? "" : "  (not in default sweep)");
      if (defaults.min_h > 0)
        std::printf("# budget floor: h >= %g unless --min-h\n", defaults.min_h);
      return 0;
    } else if (a == "--version") {
      std::printf("%s %s\n", engine.c_str(), version.c_str());
      return 0;
    } else {
      usage(argv[0], engine);
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  ::mkdir(out_dir.c_str(), 0755);
  if (csv_path.empty()) csv_path = out_dir + "/articulated_" + engine + ".csv";
  {
    std::vector<double> kept;
    for (double h : hs) {
      if (h >= min_h * (1 - 1e-12))
        kept.push_back(h);
      else
        std::fprintf(stderr,
                     "[%s] h=%g skipped: below this runner's budget floor %g (--min-h 0 runs it)\n",
                     engine.c_str(), h, min_h);
    }
    hs = kept;
  }
  std::vector<std::pair<ArticulatedCase, ArticulatedReference>> cases;
  for (const ArticulatedCase& c : allArticulatedCases())
    if (selected(case_filter, c.name)) cases.emplace_back(c, articulatedReference(c, out_dir));
  if (prepare_only) return 0;

  std::fprintf(stderr, "[%s] %s -> %s\n", engine.c_str(), version.c_str(), csv_path.c_str());
  ArticulatedCsv csv(csv_path);
  using Clock = std::chrono::steady_clock;
  const auto t_start = Clock::now();
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();

  for (const auto& cr : cases) {
    const ArticulatedCase& c = cr.first;
    const ArticulatedReference& ref = cr.second;
    for (const ArticulatedConfig& cfg : configs) {
      if (!selected(config_filter, cfg.name)) continue;
      if (config_filter.empty() && !all_configs && !cfg.in_default_sweep) continue;
      for (double h : hs) {
        const long N = std::lround(c.T / h);
        const long nt = std::min(N, timing_steps);
        // Timing runs, without read-back.
        std::vector<double> cpus, walls;
        for (int r = 0; r < reps; ++r) {
          Timing t{nan, nan};
          if (sweep::runIsolatedValue(
                  [&]() {
                    std::unique_ptr<ArticulatedSim> sim = cfg.make(c, h);
                    const double c0 = threadCpuSeconds();
                    const auto t0 = Clock::now();
                    sim->step(nt);
                    const auto t1 = Clock::now();
                    const double c1 = threadCpuSeconds();
                    return Timing{
                        (c1 - c0) * 1e9 / double(nt),
                        std::chrono::duration<double, std::nano>(t1 - t0).count() / double(nt)};
                  },
                  &t)) {
            cpus.push_back(t.cpu_ns);
            walls.push_back(t.wall_ns);
          }
        }
        double cpu = nan, wall = nan;
        if (!cpus.empty()) {
          std::sort(cpus.begin(), cpus.end());
          std::sort(walls.begin(), walls.end());
          cpu = cpus[cpus.size() / 2];
          wall = walls[walls.size() / 2];
        }
        // Error run: every step, to T.
        std::string text;
        const bool ok = runIsolated(
            [&]() {
              std::unique_ptr<ArticulatedSim> sim = cfg.make(c, h);
              const EnergyMeter<double> energy_of(c);
              std::vector<double> q, qd;
              BaseState<double> base;
              double drift = 0;
              int blew = 0;
              for (long k = 1; k <= N; ++k) {
                sim->step(1);
                sim->joints(&q, &qd);
                if (c.base.floating && !sim->base(&base))
                  throw std::runtime_error("the runner reports no floating base");
                if (badState(q, qd) || !base.R.allFinite() || !base.w.allFinite() ||
                    !base.v.allFinite() || base.w.norm() > kMaxJointSpeed || sim->failed()) {
                  blew = 1;
                  break;
                }
                double E = 0;
                if (!sim->bodyEnergy(&E)) E = energy_of(base, q.data(), qd.data());
                drift = std::max(drift, std::fabs(E - ref.E0) / std::fabs(ref.E0));
              }
              std::ostringstream os;
              os.precision(17);
              if (blew) {
                os << inf << " " << inf << " " << inf << " 1\n";
              } else {
                double eq = jointPositionError(q, ref), eqd = jointVelocityError(qd, ref);
                if (c.base.floating) {
                  eq = std::max(eq, baseOrientationError(base.R, ref));
                  eqd = std::max(eqd, baseAngularVelocityError(base.w, ref));
                }
                os << eq << " " << eqd << " " << drift << " 0\n";
              }
              os << sim->events() << "\n";
              return os.str();
            },
            &text);
        ErrorRun er{inf, inf, inf, 1};
        std::string notes;
        if (!ok) {
          notes = "engine run crashed or threw";
        } else {
          std::istringstream is(text);
          std::string line;
          std::getline(is, line);
          std::sscanf(line.c_str(), "%lf %lf %lf %d", &er.err_q, &er.err_qd, &er.drift, &er.blew);
          std::getline(is, notes);
        }
        if (nt < N)
          notes += (notes.empty() ? "" : "; ") + std::string("timed ") + std::to_string(nt) +
                   " of " + std::to_string(N) + " steps";
        csv.row(engine, cfg.name, c.name, h, cpu, wall, er.err_q, er.err_qd, er.drift, er.blew != 0,
                notes);
        std::fprintf(stderr,
                     "[%s] %-18s %-15s h=%-7g %9.1f ns/step cpu (wall %9.1f)  q %.3e  qd %.3e  E "
                     "%.3e%s  %s\n",
                     engine.c_str(), cfg.name.c_str(), c.name.c_str(), h, cpu, wall, er.err_q,
                     er.err_qd, er.drift, er.blew ? "  BLEW UP" : "", notes.c_str());
      }
    }
  }
  std::fprintf(stderr, "[%s] done in %.1f s\n", engine.c_str(),
               std::chrono::duration<double>(Clock::now() - t_start).count());
  return 0;
}

}  // namespace articulated
}  // namespace bench
