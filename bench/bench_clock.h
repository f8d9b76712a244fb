// Clocks and the output folder shared by our benchmark programs (bench_work_precision,
// bench_scaling). Wall time on the steady clock; thread CPU time beside it, because on a busy
// machine the wall clock also counts the other processes' share of the cores.
#pragma once

#include <time.h>

#include <algorithm>
#include <chrono>

#ifndef BENCH_OUT_DIR
#define BENCH_OUT_DIR "bench/out"
#endif

namespace cga_rigid_sim {
namespace benchmark {

using Clock = std::chrono::steady_clock;

/// CPU time of the calling thread, s.
inline double threadCpuSeconds() {
  timespec ts;
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

#if defined(__x86_64__) && defined(__GNUC__)
/// The core's clock as a chain of dependent fused multiply-adds runs it, GHz: 4 cycles per FMA
/// (the latency on the x86-64 cores this project has run on: AMD Zen 3, Intel Golden Cove), the
/// fastest of 5 timings of 10⁸. The machine kind changes between sessions, and a step costs about
/// the same cycles on each, so the report prints this beside the ns figures. 0 without FMA.
__attribute__((target("fma"), noinline)) inline double fmaChainGHzOnFma() {
  constexpr long kOps = 100000000;
  double best_ns = 1e300;
  for (int rep = 0; rep < 5; ++rep) {
    double x = 1.0, a = 0.999999, b = 1e-7;
    asm("" : "+x"(a), "+x"(b));  // not constants: the chain is not folded
    const double t0 = threadCpuSeconds();
    for (long i = 0; i < kOps; ++i) x = __builtin_fma(x, a, b);
    const double t1 = threadCpuSeconds();
    asm volatile("" : : "x"(x));
    best_ns = std::min(best_ns, 1e9 * (t1 - t0) / double(kOps));
  }
  return 4.0 / best_ns;
}
// The check outside the FMA-compiled function: nothing of that target runs on a CPU without it.
inline double fmaChainGHz() { return __builtin_cpu_supports("fma") ? fmaChainGHzOnFma() : 0.0; }
#else
inline double fmaChainGHz() { return 0.0; }
#endif

}  // namespace benchmark
}  // namespace cga_rigid_sim
