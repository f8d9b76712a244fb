// WorkerPool: a fixed set of threads for the parallel parts of the step. It runs one loop at a
// time: parallelFor(n, fn, context) splits [0, n) into one contiguous chunk per thread (chunk
// c = [n c / T, n (c + 1) / T)), the calling thread doing chunk 0, and returns when every chunk
// is done. The pool starts its threads when it is made and ends them when it is destroyed;
// parallelFor never allocates, so the step stays allocation-free.
//
// Determinism: a stage may use it only for work whose items are independent (each body's
// integration reads its own data and the constant Model), so the result does not depend on how
// the items are split: states are bit-identical for any number of threads.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace cga_rigid_sim {
namespace sim {

class WorkerPool {
 public:
  /// The work of one chunk: items [begin, end).
  using RangeFn = void (*)(void* context, std::size_t begin, std::size_t end);

  /// `threads` ≥ 1 threads in all: the caller of parallelFor and threads − 1 workers.
  explicit WorkerPool(int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()) + 1; }

  /// fn(context, begin, end) on every chunk of [0, n); returns when all are done.
  void parallelFor(std::size_t n, RangeFn fn, void* context);

 private:
  void work(int index);
  void runChunk(int index);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_;
  std::condition_variable done_;
  std::uint64_t generation_ = 0;  ///< bumped for every loop; workers wait for a new one
  int pending_ = 0;               ///< workers still busy with the current loop
  bool stop_ = false;
  RangeFn fn_ = nullptr;
  void* context_ = nullptr;
  std::size_t n_ = 0;
};

}  // namespace sim
}  // namespace cga_rigid_sim
