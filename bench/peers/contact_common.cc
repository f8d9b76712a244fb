#include "contact_common.h"

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

#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#ifndef BENCH_OUT_DIR
#define BENCH_OUT_DIR "bench/out"
#endif

namespace bench {
namespace contacts {
namespace {

using sweep::runIsolated;
using sweep::selected;
using sweep::splitList;
using sweep::threadCpuSeconds;

void usage(const char* program, const std::string& engine) {
  const char* slash = std::strrchr(program, '/');
  std::printf(
      "usage: %s [options]\n"
      "  --out DIR       output directory (default %s)\n"
      "  --csv PATH      CSV file (default DIR/contacts_%s.csv)\n"
      "  --cases a,b     only these cases (bounce, incline_stick, incline_slide, slide_stop,\n"
      "                  rolling_sphere, stack10, pile1000)\n"
      "  --configs a,b   only these configs\n"
      "  --hs 1e-3,2e-3  step sizes (default 5e-4,1e-3,2e-3)\n"
      "  --pile-hs 1e-3  step sizes for pile1000 (default: 1e-3 only, it is the expensive case)\n"
      "  --pile-T S      simulated time of pile1000 (default 5 s; shorter for slow engines, noted)\n"
      "  --reps R        timing repetitions, median reported (default 3)\n"
      "  --list          list configs and exit\n"
      "  --version       print engine version and exit\n",
      slash ? slash + 1 : program, BENCH_OUT_DIR, engine.c_str());
}

}  // namespace

ContactCsv::ContactCsv(const std::string& path) : file_(std::fopen(path.c_str(), "w")) {
  if (!file_) {
    std::fprintf(stderr, "cannot open %s\n", path.c_str());
    std::exit(2);
  }
  std::fprintf(static_cast<FILE*>(file_), "%s\n", header());
  std::fflush(static_cast<FILE*>(file_));
}

ContactCsv::~ContactCsv() { std::fclose(static_cast<FILE*>(file_)); }

void ContactCsv::row(const std::string& engine, const std::string& config, const std::string& case_name, double h,
                     double ns_per_step, double error, const std::string& metric, const std::string& notes) {
  std::fprintf(static_cast<FILE*>(file_), "%s,%s,%s,%.6g,%.6g,%.6e,%s,%s\n", engine.c_str(), config.c_str(),
               case_name.c_str(), h, ns_per_step, error, metric.c_str(), sweep::csvSafe(notes).c_str());
  std::fflush(static_cast<FILE*>(file_));
}

int runContactSweep(const std::string& engine, const std::string& version, const std::vector<ContactConfig>& configs,
                    int argc, char** argv, double default_pile_T) {
  std::string out_dir = BENCH_OUT_DIR, csv_path;
  std::vector<std::string> case_filter, config_filter;
  std::vector<double> hs = {5e-4, 1e-3, 2e-3}, pile_hs = {1e-3};
  int reps = 3;
  double pile_T = default_pile_T;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        usage(argv[0], engine);
        std::exit(2);
      }
      return argv[++i];
    };
    auto doubles = [&](std::vector<double>* v) {
      v->clear();
      for (const std::string& t : splitList(next())) v->push_back(std::strtod(t.c_str(), nullptr));
    };
    if (a == "--out") out_dir = next();
    else if (a == "--csv") csv_path = next();
    else if (a == "--cases") case_filter = splitList(next());
    else if (a == "--configs") config_filter = splitList(next());
    else if (a == "--hs") doubles(&hs);
    else if (a == "--pile-hs") doubles(&pile_hs);
    else if (a == "--pile-T") pile_T = std::strtod(next().c_str(), nullptr);
    else if (a == "--reps") reps = std::max(1, std::atoi(next().c_str()));
    else if (a == "--list") {
      for (const ContactConfig& c : configs) std::printf("%s\n", c.name.c_str());
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
  if (csv_path.empty()) csv_path = out_dir + "/contacts_" + engine + ".csv";
  std::fprintf(stderr, "[%s] %s -> %s\n", engine.c_str(), version.c_str(), csv_path.c_str());
  ContactCsv csv(csv_path);
  // Side file named so that neither the single-body tools' cputime_*.csv glob
  // nor our contacts_*.csv glob picks it up.
  const std::string cpu_path = out_dir + "/cpu_contacts_" + engine + ".csv";
  FILE* cpu_csv = std::fopen(cpu_path.c_str(), "w");
  if (cpu_csv) std::fprintf(cpu_csv, "engine,config,case,h,wall_ns_per_step,cpu_ns_per_step\n");

  using Clock = std::chrono::steady_clock;
  const auto t_start = Clock::now();
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();

  for (ContactCase c : allContactCases()) {
    if (!selected(case_filter, c.name)) continue;
    if (c.observe_end_only && pile_T > 0) c.T = pile_T;
    for (const ContactConfig& cfg : configs) {
      if (!selected(config_filter, cfg.name)) continue;
      if (std::find(cfg.skip_cases.begin(), cfg.skip_cases.end(), c.name) != cfg.skip_cases.end()) {
        std::fprintf(stderr, "[%s] %s %s skipped: %s\n", engine.c_str(), cfg.name.c_str(), c.name.c_str(),
                     cfg.skip_reason.c_str());
        continue;
      }
      for (double h : c.observe_end_only ? pile_hs : hs) {
        const long N = std::lround(c.T / h);
        // Error run (+ timing when observe_end_only). Output: first line
        // "wall_ns cpu_ns", then one line per metric row "error\tmetric\tnote".
        std::string text;
        const bool ok = runIsolated(
            [&]() {
              std::unique_ptr<ContactSim> sim = cfg.make(c, h);
              ContactMonitor mon(c);
              std::vector<BodyObs> obs;
              double wall = nan, cpu = nan;
              if (c.observe_end_only) {
                const double c0 = threadCpuSeconds();
                const auto t0 = Clock::now();
                sim->step(N);
                const auto t1 = Clock::now();
                cpu = (threadCpuSeconds() - c0) * 1e9 / double(N);
                wall = std::chrono::duration<double, std::nano>(t1 - t0).count() / double(N);
                sim->observe(&obs);
                mon.observe(double(N) * h, obs);
              } else {
                for (long k = 1; k <= N; ++k) {
                  sim->step(1);
                  sim->observe(&obs);
                  mon.observe(double(k) * h, obs);
                }
              }
              std::ostringstream os;
              os.precision(17);
              os << wall << " " << cpu << "\n";
              const std::string ev = sim->events();
              for (const MetricRow& r : mon.finish())
                os << r.error << "\t" << r.metric << "\t" << r.note << (ev.empty() ? "" : " [" + ev + "]") << "\n";
              return os.str();
            },
            &text);
        std::vector<MetricRow> rows;
        double wall = nan, cpu = nan;
        if (!ok) {
          rows.push_back({inf, "crashed", "engine run crashed or threw"});
        } else {
          std::istringstream is(text);
          std::string line;
          std::getline(is, line);
          std::sscanf(line.c_str(), "%lf %lf", &wall, &cpu);
          while (std::getline(is, line)) {
            const size_t a = line.find('\t'), b = line.find('\t', a + 1);
            if (a == std::string::npos || b == std::string::npos) continue;
            rows.push_back({std::strtod(line.substr(0, a).c_str(), nullptr), line.substr(a + 1, b - a - 1),
                            line.substr(b + 1)});
          }
        }
        // Timing runs without read-back.
        if (!c.observe_end_only && ok) {
          std::vector<double> ws, cs;
          for (int r = 0; r < reps; ++r) {
            std::string t;
            if (runIsolated(
                    [&]() {
                      std::unique_ptr<ContactSim> sim = cfg.make(c, h);
                      const double c0 = threadCpuSeconds();
                      const auto t0 = Clock::now();
                      sim->step(N);
                      const auto t1 = Clock::now();
                      std::ostringstream os;
                      os.precision(17);
                      os << std::chrono::duration<double, std::nano>(t1 - t0).count() / double(N) << " "
                         << (threadCpuSeconds() - c0) * 1e9 / double(N);
                      return os.str();
                    },
                    &t)) {
              double w = nan, cp = nan;
              std::sscanf(t.c_str(), "%lf %lf", &w, &cp);
              ws.push_back(w);
              cs.push_back(cp);
            }
          }
          if (!ws.empty()) {
            std::sort(ws.begin(), ws.end());
            std::sort(cs.begin(), cs.end());
            wall = ws[ws.size() / 2];
            cpu = cs[cs.size() / 2];
          }
        }
        for (MetricRow& r : rows) {
          if (c.observe_end_only && std::isfinite(wall))
            r.note += " (RTF " + fmtG(h * 1e9 / wall) + " wall; " + fmtG(h * 1e9 / cpu) + " cpu)";
          csv.row(engine, cfg.name, c.name, h, wall, r.error, r.metric, r.note);
          std::fprintf(stderr, "[%s] %-14s %-15s h=%-7g %11.1f ns/step (cpu %11.1f)  %-18s %.4e  %s\n",
                       engine.c_str(), cfg.name.c_str(), c.name.c_str(), h, wall, cpu, r.metric.c_str(), r.error,
                       r.note.c_str());
        }
        if (cpu_csv) {
          std::fprintf(cpu_csv, "%s,%s,%s,%.6g,%.6g,%.6g\n", engine.c_str(), cfg.name.c_str(), c.name.c_str(), h,
                       wall, cpu);
          std::fflush(cpu_csv);
        }
      }
    }
  }
  if (cpu_csv) std::fclose(cpu_csv);
  std::fprintf(stderr, "[%s] done in %.1f s\n", engine.c_str(),
               std::chrono::duration<double>(Clock::now() - t_start).count());
  return 0;
}

}  // namespace contacts
}  // namespace bench
