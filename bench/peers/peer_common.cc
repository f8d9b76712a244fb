#include "peer_common.h"

#include "sweep_util.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <sstream>

#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#ifndef BENCH_OUT_DIR
#define BENCH_OUT_DIR "bench/out"
#endif

namespace bench {
namespace peers {
namespace {

using sweep::runIsolatedValue;
using sweep::selected;
using sweep::splitList;
using sweep::threadCpuSeconds;

double norm3(const std::array<double, 3>& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

bool blownUp(const Case& c, const BodyState& s) {
  for (double v : s.q)
    if (!std::isfinite(v)) return true;
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(s.w_world[i]) || !std::isfinite(s.x[i]) || !std::isfinite(s.v[i])) return true;
  return norm3(s.w_world) > 1e6 * norm3(c.w0_body);
}

struct TimingSample {
  double wall_ns;  // per step
  double cpu_ns;   // per step, CPU time of the stepping thread
};

struct ErrorRun {
  Errors err;
  int blew;
};

void usage(const std::string& engine) {
  std::printf(
      "usage: peer_%s [options]\n"
      "  --out DIR           output directory (default %s)\n"
      "  --csv PATH          CSV file (default DIR/peers_%s.csv)\n"
      "  --cases a,b         only these cases\n"
      "  --configs a,b       only these configs (default: the default-sweep ones)\n"
      "  --all-configs       all configs, including those left out of the default sweep\n"
      "  --hs 1e-3,1e-2      step sizes (engine default; usually 1e-4 ... 1e-1, 10 values)\n"
      "  --timing-steps N    steps per timing run, capped at T/h (engine default; usually 20000)\n"
      "  --reps R            timing repetitions, median reported (default 3)\n"
      "  --min-h H           skip step sizes below H (engine default: 0; Simbody 1e-3)\n"
      "  --list              list configs and exit\n"
      "  --prepare           only compute/cache the reference solutions, then exit\n"
      "  --version           print engine version and exit\n",
      engine.c_str(), BENCH_OUT_DIR, engine.c_str());
}

}  // namespace

std::vector<double> defaultStepSizes() { return {1e-4, 2e-4, 5e-4, 1e-3, 2e-3, 5e-3, 1e-2, 2e-2, 5e-2, 1e-1}; }

CsvWriter::CsvWriter(const std::string& path) : file_(std::fopen(path.c_str(), "w")) {
  if (!file_) {
    std::fprintf(stderr, "cannot open %s\n", path.c_str());
    std::exit(2);
  }
  std::fprintf(static_cast<FILE*>(file_), "%s\n", header());
  std::fflush(static_cast<FILE*>(file_));
}

CsvWriter::~CsvWriter() { std::fclose(static_cast<FILE*>(file_)); }

const char* CsvWriter::header() {
  return "engine,config,case,h,ns_per_step,err_orientation_rad,err_com_m,err_energy_rel,err_L_rel,blew_up";
}

void CsvWriter::row(const std::string& engine, const std::string& config, const std::string& case_name,
                    double h, double ns_per_step, const Errors& e, bool blew_up) {
  std::fprintf(static_cast<FILE*>(file_), "%s,%s,%s,%.6g,%.6g,%.6e,%.6e,%.6e,%.6e,%d\n", engine.c_str(),
               config.c_str(), case_name.c_str(), h, ns_per_step, e.orientation_rad, e.com_m, e.energy_rel,
               e.L_rel, blew_up ? 1 : 0);
  std::fflush(static_cast<FILE*>(file_));
}

int runSweep(const std::string& engine, const std::string& version, const std::vector<PeerConfig>& configs,
             int argc, char** argv, const SweepDefaults& defaults) {
  std::string out_dir = BENCH_OUT_DIR, csv_path;
  std::vector<std::string> case_filter, config_filter;
  std::vector<double> hs = defaults.hs.empty() ? defaultStepSizes() : defaults.hs;
  long timing_steps = defaults.timing_steps;
  int reps = defaults.reps;
  double min_h = defaults.min_h;
  bool all_configs = false, prepare_only = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        usage(engine);
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--out") out_dir = next();
    else if (a == "--csv") csv_path = next();
    else if (a == "--cases") case_filter = splitList(next());
    else if (a == "--configs") config_filter = splitList(next());
    else if (a == "--all-configs") all_configs = true;
    else if (a == "--prepare") prepare_only = true;
    else if (a == "--hs") {
      hs.clear();
      for (const std::string& t : splitList(next())) hs.push_back(std::strtod(t.c_str(), nullptr));
    } else if (a == "--timing-steps") timing_steps = std::atol(next().c_str());
    else if (a == "--reps") reps = std::atoi(next().c_str());
    else if (a == "--min-h") min_h = std::strtod(next().c_str(), nullptr);
    else if (a == "--list") {
      for (const PeerConfig& c : configs)
        std::printf("%s%s\n", c.name.c_str(), c.in_default_sweep ? "" : "  (not in default sweep)");
      return 0;
    } else if (a == "--version") {
      std::printf("%s %s\n", engine.c_str(), version.c_str());
      return 0;
    } else {
      usage(engine);
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  if (csv_path.empty()) csv_path = out_dir + "/peers_" + engine + ".csv";
  {
    std::vector<double> kept;
    for (double h : hs) {
      if (h >= min_h * (1 - 1e-12)) kept.push_back(h);
      else std::fprintf(stderr, "[%s] h=%g skipped: below this runner's budget floor %g (--min-h 0 runs it)\n",
                        engine.c_str(), h, min_h);
    }
    hs = kept;
  }
  if (reps < 1) reps = 1;
  if (timing_steps < 1) timing_steps = 1;

  std::fprintf(stderr, "[%s] %s -> %s\n", engine.c_str(), version.c_str(), csv_path.c_str());
  std::vector<std::pair<Case, Reference>> cases;
  for (const Case& c : allCases()) {
    if (!selected(case_filter, c.name)) continue;
    cases.emplace_back(c, referenceSolution(c, out_dir));  // creates out_dir if needed
  }
  if (prepare_only) return 0;  // reference cache is filled
  CsvWriter csv(csv_path);
  // Side file cputime_<engine>.csv (kept out of the peers_*.csv namespace,
  // which holds only work-precision files): the same timing runs measured in
  // thread CPU time, robust to other load on the machine; the main CSV has
  // wall time as specified.
  const std::string cpu_path = out_dir + "/cputime_" + engine + ".csv";
  FILE* cpu_csv = std::fopen(cpu_path.c_str(), "w");
  if (cpu_csv) std::fprintf(cpu_csv, "engine,config,case,h,wall_ns_per_step,cpu_ns_per_step\n");
  using Clock = std::chrono::steady_clock;
  const auto t_start = Clock::now();
  const double inf = std::numeric_limits<double>::infinity();

  for (const auto& cr : cases) {
    const Case& c = cr.first;
    const Reference& ref = cr.second;
    for (const PeerConfig& cfg : configs) {
      if (!selected(config_filter, cfg.name)) continue;
      if (config_filter.empty() && !all_configs && !cfg.in_default_sweep) continue;
      for (double h : hs) {
        const long N = std::lround(c.T / h);
        bool blew = false;
        Errors err{inf, inf, inf, inf};
        double ns = std::numeric_limits<double>::quiet_NaN();
        // Timing runs (each in a fresh simulation, in a child process).
        const long nt = std::min(N, timing_steps);
        std::vector<double> samples, cpu_samples;
        for (int r = 0; r < reps; ++r) {
          TimingSample sample{0, 0};
          const bool ok = runIsolatedValue(
              [&]() {
                std::unique_ptr<PeerSim> sim = cfg.make(c, h);
                const double c0 = threadCpuSeconds();
                const auto t0 = Clock::now();
                sim->run(nt);
                const auto t1 = Clock::now();
                const double c1 = threadCpuSeconds();
                return TimingSample{std::chrono::duration<double, std::nano>(t1 - t0).count() / double(nt),
                                    (c1 - c0) * 1e9 / double(nt)};
              },
              &sample);
          if (ok) {
            samples.push_back(sample.wall_ns);
            cpu_samples.push_back(sample.cpu_ns);
          }
        }
        double cpu_ns = std::numeric_limits<double>::quiet_NaN();
        if (!samples.empty()) {
          std::sort(samples.begin(), samples.end());
          std::sort(cpu_samples.begin(), cpu_samples.end());
          ns = samples[samples.size() / 2];
          cpu_ns = cpu_samples[cpu_samples.size() / 2];
        }
        // Error run: the full N steps to t = T.
        ErrorRun er{err, 1};
        const bool ok = runIsolatedValue(
            [&]() {
              ErrorRun res{Errors{inf, inf, inf, inf}, 0};
              std::unique_ptr<PeerSim> sim = cfg.make(c, h);
              const long chunk = std::max(1L, N / 100);
              long done = 0;
              while (done < N) {
                const long n = std::min(chunk, N - done);
                sim->run(n);
                done += n;
                if (blownUp(c, sim->state()) || sim->engineReportedFailure()) {
                  res.blew = 1;
                  return res;
                }
              }
              res.err = computeErrors(c, ref, sim->state());
              return res;
            },
            &er);
        if (!ok) {
          std::fprintf(stderr, "[%s] %s %s h=%g: run crashed or threw (recorded as blow-up)\n", engine.c_str(),
                       cfg.name.c_str(), c.name.c_str(), h);
          er.blew = 1;
        }
        blew = er.blew != 0;
        if (!blew) err = er.err;
        csv.row(engine, cfg.name, c.name, h, ns, err, blew);
        if (cpu_csv) {
          std::fprintf(cpu_csv, "%s,%s,%s,%.6g,%.6g,%.6g\n", engine.c_str(), cfg.name.c_str(), c.name.c_str(), h,
                       ns, cpu_ns);
          std::fflush(cpu_csv);
        }
        std::fprintf(stderr, "[%s] %-24s %-16s h=%-7g %9.1f ns/step (cpu %9.1f)  ang=%.3e  com=%.3e  E=%.3e  L=%.3e%s\n",
                     engine.c_str(), cfg.name.c_str(), c.name.c_str(), h, ns, cpu_ns, err.orientation_rad, err.com_m,
                     err.energy_rel, err.L_rel, blew ? "  BLEW UP" : "");
      }
    }
  }
  if (cpu_csv) std::fclose(cpu_csv);
  const double secs = std::chrono::duration<double>(Clock::now() - t_start).count();
  std::fprintf(stderr, "[%s] done in %.1f s\n", engine.c_str(), secs);
  return 0;
}

}  // namespace peers
}  // namespace bench
