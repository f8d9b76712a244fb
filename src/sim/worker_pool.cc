#include "cga_rigid_sim/sim/worker_pool.h"

namespace cga_rigid_sim {
namespace sim {

WorkerPool::WorkerPool(int threads) {
  const int workers = threads > 1 ? threads - 1 : 0;
  workers_.reserve(workers);
  for (int i = 0; i < workers; ++i) workers_.emplace_back(&WorkerPool::work, this, i + 1);
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  start_.notify_all();
  for (auto& t : workers_) t.join();
}

void WorkerPool::runChunk(int index) {
  const std::size_t T = static_cast<std::size_t>(threads());
  const std::size_t c = static_cast<std::size_t>(index);
  const std::size_t begin = n_ * c / T, end = n_ * (c + 1) / T;
  if (begin < end) fn_(context_, begin, end);
}

void WorkerPool::parallelFor(std::size_t n, RangeFn fn, void* context) {
  if (workers_.empty()) {
    if (n > 0) fn(context, 0, n);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    fn_ = fn;
    context_ = context;
    n_ = n;
    pending_ = static_cast<int>(workers_.size());
    ++generation_;
  }
  start_.notify_all();
  runChunk(0);
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [this] { return pending_ == 0; });
}

void WorkerPool::work(int index) {
  std::uint64_t seen = 0;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      start_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
    }
    // fn_, context_ and n_ were written before generation_ under the mutex; the caller does not
    // change them until every worker has reported done.
    runChunk(index);
    bool last = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      last = --pending_ == 0;
    }
    if (last) done_.notify_one();
  }
}

}  // namespace sim
}  // namespace cga_rigid_sim
