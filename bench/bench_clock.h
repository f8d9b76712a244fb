// Clocks and the output folder shared by our benchmark programs (bench_work_precision,
// bench_scaling). Wall time on the steady clock; thread CPU time beside it, because on a busy
// machine the wall clock also counts the other processes' share of the cores.
#pragma once

#include <time.h>

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

}  // namespace benchmark
}  // namespace cga_rigid_sim
