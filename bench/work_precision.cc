// bench_work_precision: cost against accuracy of our integrators on the shared hard cases.
//
// For every case of bench/cases/cases.h, every integrator (cga2, cga4, exact, auto, euler, rk4)
// and every step size h: one Inertia, one BodyState, one Integrator and the case's Loads (the
// dynamics layer, no World) are advanced N = T/h steps to t = T = 100 s.
//   * ns_per_step: the whole run is timed (steady_clock, integrator made before the clock
//     starts); the median over R repetitions is reported, R = max(--reps, ⌈min_timed/N⌉) so
//     that short runs are repeated until they add up to at least --min-timed-steps steps.
//   * errors: from the final state of the run, against the shared reference solution with the
//     shared metrics (reference_solution.h), written exactly as the peers write them
//     (bench/out/peers_<engine>.csv; same columns, engine = "cga_rigid_sim", config = the
//     integrator's name). Every repetition must end in the bit-identical state (determinism);
//     a difference is reported on stderr.
//   * blow-up: the peers' rule (non-finite, or |w| > 10⁶ |w0|), checked every N/100 steps
//     inside the timed loop (the check reads |w_B|, a few flops per 1 % of the run); a run that
//     blows up stops there and its errors are written as inf.
//
// The conditioning floor (--floors, written to <out>/floors.csv and cached there): how far the
// orientation at T moves when the initial angular velocity is perturbed by one rounding error,
// δw_i = u |w0| along each body axis (u = 2⁻⁵³). It is computed with the long-double reference
// integrator on a perturbation of 2⁻⁴⁰ |w0| (representable in double, and still far inside the
// linear regime) scaled back by u / 2⁻⁴⁰; the three axes are combined as a root sum of squares.
// No double-precision method can be expected to beat it: every step rounds the state by about
// that much.

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "bench_clock.h"
#include "case_setup.h"
#include "cases.h"
#include "cga_rigid_sim/body/integrator.h"
#include "peers/sweep_util.h"
#include "reference_solution.h"

namespace cga_rigid_sim {
namespace benchmark {
namespace {

const char* const kEngine = "cga_rigid_sim";
const char* const kHeader =
    "engine,config,case,h,ns_per_step,err_orientation_rad,err_com_m,err_energy_rel,err_L_rel,"
    "blew_up";

using bench::sweep::splitList;  // "a,b,c" → {a, b, c} (peers/sweep_util.h)

bool selected(const std::vector<std::string>& filter, const std::string& name) {
  return filter.empty() || std::find(filter.begin(), filter.end(), name) != filter.end();
}

struct Options {
  std::string out_dir = BENCH_OUT_DIR;
  std::string csv;  // default <out_dir>/ours.csv
  std::vector<std::string> cases, integrators = {"cga2", "cga4", "exact", "auto", "euler", "rk4"};
  // The peers' grid (bench/peers/peer_common.cc, defaultStepSizes): 10 values, 3 decades.
  std::vector<double> hs = {1e-4, 2e-4, 5e-4, 1e-3, 2e-3, 5e-3, 1e-2, 2e-2, 5e-2, 1e-1};
  int reps = 3;
  long min_timed_steps = 200000;
  int max_reps = 1000;
  bool floors = true;
  bool sweep = true;
};

void usage() {
  std::printf(
      "usage: bench_work_precision [options]\n"
      "  --out DIR              output directory (default %s)\n"
      "  --csv PATH             CSV file (default DIR/ours.csv); with it, the side files\n"
      "                         cputime_NAME and cases_NAME go beside PATH, not into DIR\n"
      "  --cases a,b            only these cases (default: all of cases.h)\n"
      "  --integrators a,b      only these integrators (default cga2,cga4,exact,auto,euler,rk4)\n"
      "  --hs 1e-3,1e-2         step sizes (default: the peers' 1e-4 ... 1e-1, 10 values)\n"
      "  --reps R               timing repetitions of the whole run, median (default 3)\n"
      "  --min-timed-steps S    repeat short runs until they add up to S steps (default 200000)\n"
      "  --no-floors            do not compute/refresh DIR/floors.csv (only read it)\n"
      "  --floors-only          only compute DIR/floors.csv\n"
      "  --fma-clock            print the core's clock from a chain of dependent FMAs (GHz)\n",
      BENCH_OUT_DIR);
}

// ---------------------------------------------------------------------------------------------
// Conditioning floor
// ---------------------------------------------------------------------------------------------

// Every parameter of a case, exactly (hex floats), as the cache key.
std::string caseKey(const ::bench::Case& c) {
  std::string key;
  char buf[64];
  auto add = [&](double v) {
    std::snprintf(buf, sizeof buf, "%a;", v);
    key += buf;
  };
  add(c.mass);
  for (int i = 0; i < 3; ++i) {
    add(c.inertia[i]);
    add(c.w0_body[i]);
    add(c.v0_world[i]);
    add(c.gravity[i]);
    add(c.torque_world[i]);
  }
  add(c.T);
  return key + "floor-v1";
}

double computeFloor(const ::bench::Case& c) {
  const long macro = std::max(100L, ::bench::defaultMacroSteps(c) / 4);
  const ::bench::Reference base = ::bench::integrateReference(c, c.T, macro, true);
  const double u = std::ldexp(1.0, -53);
  const double w0 = std::sqrt(c.w0_body[0] * c.w0_body[0] + c.w0_body[1] * c.w0_body[1] +
                              c.w0_body[2] * c.w0_body[2]);
  double sum_sq = 0;
  for (int i = 0; i < 3; ++i) {
    ::bench::Case p = c;
    p.w0_body[i] = c.w0_body[i] + std::ldexp(w0, -40);
    const double applied = p.w0_body[i] - c.w0_body[i];  // exact (Sterbenz)
    const ::bench::Reference r = ::bench::integrateReference(p, c.T, macro, true);
    const double angle = ::bench::orientationError(r.state.q, base.state.q) * (u * w0 / applied);
    sum_sq += angle * angle;
  }
  return std::sqrt(sum_sq);
}

// floors.csv: case,key,floor_orientation_rad. Recomputes the floors of cases whose key changed;
// with `compute` false (--no-floors) it only reads the file, and a case whose key changed is left
// out (its floor is then unknown, not stale).
std::map<std::string, double> floors(const std::vector<::bench::Case>& cases,
                                     const std::string& out_dir, bool compute) {
  const std::string path = out_dir + "/floors.csv";
  std::map<std::string, std::pair<std::string, double>> cached;
  {
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
      const std::vector<std::string> f = splitList(line);
      if (f.size() == 3) cached[f[0]] = {f[1], std::strtod(f[2].c_str(), nullptr)};
    }
  }
  std::map<std::string, double> result;
  for (const ::bench::Case& c : cases) {
    const std::string key = caseKey(c);
    auto it = cached.find(c.name);
    if (it != cached.end() && it->second.first == key) {
      result[c.name] = it->second.second;
      continue;
    }
    if (!compute) continue;
    const auto t0 = Clock::now();
    const double floor = computeFloor(c);
    cached[c.name] = {key, floor};
    result[c.name] = floor;
    std::fprintf(stderr, "[floor] %-16s %.3e rad  (%.1f s)\n", c.name.c_str(), floor,
                 std::chrono::duration<double>(Clock::now() - t0).count());
  }
  if (!compute) return result;
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) {
    std::fprintf(stderr, "cannot write %s\n", path.c_str());
    std::exit(2);
  }
  std::fprintf(f, "case,key,floor_orientation_rad\n");
  for (const auto& kv : cached)
    std::fprintf(f, "%s,%s,%.6e\n", kv.first.c_str(), kv.second.first.c_str(), kv.second.second);
  std::fclose(f);
  return result;
}

// A side file's path: DIR/<name> for the report's run, <csv's folder>/<stem>_<csv's name> beside
// --csv when one is given. A side run (an A/B timing of a few cases) then leaves the report's
// files alone: bench/report.py reads DIR/cases.csv and DIR/cputime_cga_rigid_sim.csv, and a side
// run's cases.csv, written over the report's with its few cases and no floors, once made the
// report print T1 with no floor and T5 as not measured.
std::string sideFile(const Options& o, const std::string& stem, const std::string& name) {
  if (o.csv.empty()) return o.out_dir + "/" + name;
  const std::size_t slash = o.csv.find_last_of('/');
  const std::size_t base = slash == std::string::npos ? 0 : slash + 1;
  return o.csv.substr(0, base) + stem + "_" + o.csv.substr(base);
}

// cases.csv: what report.py needs to know about each case (whether it is torque-free or under
// gravity, its floor, |x(T)| of the reference for the CoM round-off bound).
void writeCaseFacts(const std::vector<::bench::Case>& cases,
                    const std::vector<::bench::Reference>& refs,
                    const std::map<std::string, double>& floor_of, const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) {
    std::fprintf(stderr, "cannot write %s\n", path.c_str());
    std::exit(2);
  }
  std::fprintf(f, "case,torque_free,has_gravity,T,floor_orientation_rad,com_T_m\n");
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const ::bench::Case& c = cases[i];
    const bool gravity = c.gravity[0] != 0 || c.gravity[1] != 0 || c.gravity[2] != 0;
    const bool torque = c.torque_world[0] != 0 || c.torque_world[1] != 0 || c.torque_world[2] != 0;
    const auto it = floor_of.find(c.name);
    const auto& x = refs[i].state.x;
    std::fprintf(f, "%s,%d,%d,%.17g,%.6e,%.17g\n", c.name.c_str(), !gravity && !torque ? 1 : 0,
                 gravity ? 1 : 0, c.T,
                 it == floor_of.end() ? std::numeric_limits<double>::quiet_NaN() : it->second,
                 std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]));
  }
  std::fclose(f);
}

// ---------------------------------------------------------------------------------------------
// The sweep
// ---------------------------------------------------------------------------------------------

struct Run {
  double ns_per_step = 0;
  double cpu_ns_per_step = 0;  // thread CPU time: robust to other load on the machine
  dynamics::BodyState final_state;
  bool blew_up = false;
};

// One whole run of N steps of h, timed. Blow-up is checked every N/100 steps.
Run runOnce(const CaseSetup& s, dynamics::Integrator& integrator, double h, long N,
            double w_limit) {
  Run run;
  dynamics::BodyState state = s.state0;
  const long chunk = std::max(1L, N / 100);
  long done = 0;
  const double c0 = threadCpuSeconds();
  const auto t0 = Clock::now();
  while (done < N) {
    const long n = std::min(chunk, N - done);
    for (long i = 0; i < n; ++i) integrator.step(s.inertia, s.loads, s.lambda, h, state);
    done += n;
    if (!state.allFinite() || !(state.omega_B.angular().norm() <= w_limit)) {
      run.blew_up = true;
      break;
    }
  }
  const auto t1 = Clock::now();
  const double c1 = threadCpuSeconds();
  run.ns_per_step = std::chrono::duration<double, std::nano>(t1 - t0).count() / double(done);
  run.cpu_ns_per_step = (c1 - c0) * 1e9 / double(done);
  run.final_state = state;
  return run;
}

bool sameState(const dynamics::BodyState& a, const dynamics::BodyState& b) {
  const auto ma = a.M_WB.coefficients(), mb = b.M_WB.coefficients();
  const auto wa = a.omega_B.coefficients(), wb = b.omega_B.coefficients();
  return std::memcmp(ma.data(), mb.data(), sizeof(double) * ma.size()) == 0 &&
         std::memcmp(wa.data(), wb.data(), sizeof(double) * wa.size()) == 0;
}

int sweep(const Options& o, const std::vector<::bench::Case>& cases) {
  const std::string csv_path = o.csv.empty() ? o.out_dir + "/ours.csv" : o.csv;
  FILE* csv = std::fopen(csv_path.c_str(), "w");
  if (!csv) {
    std::fprintf(stderr, "cannot write %s\n", csv_path.c_str());
    return 2;
  }
  std::fprintf(csv, "%s\n", kHeader);
  // Side file, as the peers write it: the same timing runs in wall and thread-CPU time.
  const std::string cpu_path = sideFile(o, "cputime", std::string("cputime_") + kEngine + ".csv");
  FILE* cpu_csv = std::fopen(cpu_path.c_str(), "w");
  if (cpu_csv) std::fprintf(cpu_csv, "engine,config,case,h,wall_ns_per_step,cpu_ns_per_step\n");
  const double inf = std::numeric_limits<double>::infinity();
  const auto t_start = Clock::now();

  for (const ::bench::Case& c : cases) {
    const ::bench::Reference ref = ::bench::referenceSolution(c, o.out_dir);
    const CaseSetup setup = setupCase(c);
    const double w_limit = 1e6 * setup.state0.omega_B.angular().norm();
    for (const std::string& name : o.integrators) {
      for (double h : o.hs) {
        const long N = std::lround(c.T / h);
        const int reps = static_cast<int>(
            std::min<long>(o.max_reps, std::max<long>(o.reps, (o.min_timed_steps + N - 1) / N)));
        std::vector<double> ns, cpu_ns;
        Run first;
        bool deterministic = true;
        for (int r = 0; r < reps; ++r) {
          auto integrator = dynamics::makeIntegrator(name);
          if (!integrator) {
            std::fprintf(stderr, "%s\n", integrator.error().c_str());
            return 2;
          }
          const Run run = runOnce(setup, **integrator, h, N, w_limit);
          ns.push_back(run.ns_per_step);
          cpu_ns.push_back(run.cpu_ns_per_step);
          if (r == 0)
            first = run;
          else if (!first.blew_up && !sameState(run.final_state, first.final_state))
            deterministic = false;
        }
        std::sort(ns.begin(), ns.end());
        std::sort(cpu_ns.begin(), cpu_ns.end());
        const double ns_median = ns[ns.size() / 2];
        const double cpu_median = cpu_ns[cpu_ns.size() / 2];
        const ::bench::BodyState final_state = toCaseState(setup, first.final_state);
        const bool blew = first.blew_up || blownUp(c, final_state);
        ::bench::Errors e{inf, inf, inf, inf};
        if (!blew) e = ::bench::computeErrors(c, ref, final_state);
        std::fprintf(csv, "%s,%s,%s,%.6g,%.6g,%.6e,%.6e,%.6e,%.6e,%d\n", kEngine, name.c_str(),
                     c.name.c_str(), h, ns_median, e.orientation_rad, e.com_m, e.energy_rel,
                     e.L_rel, blew ? 1 : 0);
        std::fflush(csv);
        if (cpu_csv) {
          std::fprintf(cpu_csv, "%s,%s,%s,%.6g,%.6g,%.6g\n", kEngine, name.c_str(), c.name.c_str(),
                       h, ns_median, cpu_median);
          std::fflush(cpu_csv);
        }
        std::fprintf(stderr,
                     "[ours] %-6s %-16s h=%-7g %8.1f ns/step (cpu %8.1f, x%-4d) ang=%.3e com=%.3e "
                     "E=%.3e L=%.3e%s%s\n",
                     name.c_str(), c.name.c_str(), h, ns_median, cpu_median, reps,
                     e.orientation_rad, e.com_m, e.energy_rel, e.L_rel, blew ? "  BLEW UP" : "",
                     deterministic ? "" : "  NOT DETERMINISTIC");
      }
    }
  }
  std::fclose(csv);
  if (cpu_csv) std::fclose(cpu_csv);
  std::fprintf(stderr, "[ours] done in %.1f s -> %s\n",
               std::chrono::duration<double>(Clock::now() - t_start).count(), csv_path.c_str());
  return 0;
}

int run(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        usage();
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--out") {
      o.out_dir = next();
    } else if (a == "--csv") {
      o.csv = next();
    } else if (a == "--cases") {
      o.cases = splitList(next());
    } else if (a == "--integrators") {
      o.integrators = splitList(next());
    } else if (a == "--hs") {
      o.hs.clear();
      for (const std::string& t : splitList(next()))
        o.hs.push_back(std::strtod(t.c_str(), nullptr));
    } else if (a == "--reps") {
      o.reps = std::max(1, std::atoi(next().c_str()));
    } else if (a == "--min-timed-steps") {
      o.min_timed_steps = std::max(1L, std::atol(next().c_str()));
    } else if (a == "--no-floors") {
      o.floors = false;
    } else if (a == "--floors-only") {
      o.sweep = false;
    } else if (a == "--fma-clock") {
      std::printf("%.2f\n", fmaChainGHz());
      return 0;
    } else {
      usage();
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  std::vector<::bench::Case> cases;
  for (const ::bench::Case& c : ::bench::allCases())
    if (selected(o.cases, c.name)) cases.push_back(c);
  if (cases.empty()) {
    std::fprintf(stderr, "no case selected\n");
    return 2;
  }
  // The references first (referenceSolution also creates the output directory), the floors,
  // and the facts report.py needs about each case.
  std::vector<::bench::Reference> refs;
  for (const ::bench::Case& c : cases) refs.push_back(::bench::referenceSolution(c, o.out_dir));
  const std::map<std::string, double> floor_of = floors(cases, o.out_dir, o.floors || !o.sweep);
  writeCaseFacts(cases, refs, floor_of, sideFile(o, "cases", "cases.csv"));
  return o.sweep ? sweep(o, cases) : 0;
}

}  // namespace
}  // namespace benchmark
}  // namespace cga_rigid_sim

int main(int argc, char** argv) { return cga_rigid_sim::benchmark::run(argc, argv); }
