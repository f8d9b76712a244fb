// Many worlds at once in Python (doc/python.md): step_worlds and rollout_worlds, each world
// stepped by one thread with the GIL released; the rollouts the fitting tools run.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <limits>
#include <thread>
#include <vector>

#include "bindings.h"
#include "py_world.h"

namespace cga_rigid_sim {
namespace python {
namespace {

// Steps every world of `worlds` by `steps`, `threads` at a time (0 = the cores available).
// Each world is stepped by one thread from start to end, so its states are the ones a plain
// loop over the worlds gives, bit for bit; the order in which threads take worlds changes no
// result.
template <class PerWorld>
void forWorlds(std::size_t count, int threads, PerWorld&& f) {
  int t = threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency());
  t = std::max(1, std::min<int>(t, static_cast<int>(count)));
  if (t == 1) {
    for (std::size_t k = 0; k < count; ++k) f(k);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::vector<std::thread> pool;
  for (int i = 0; i < t; ++i)
    pool.emplace_back([&] {
      for (std::size_t k = next++; k < count; k = next++) f(k);
    });
  for (std::thread& th : pool) th.join();
}

}  // namespace

void bindBatch(py::module_& m) {
  m.def(
      "step_worlds",
      [](const std::vector<PyWorld*>& worlds, std::uint64_t n, int threads) {
        py::gil_scoped_release release;
        forWorlds(worlds.size(), threads, [&](std::size_t k) { worlds[k]->world().step(n); });
      },
      py::arg("worlds"), py::arg("n") = 1, py::arg("threads") = 0,
      "Steps each world n steps, worlds in parallel on `threads` threads (0: the cores), the "
      "GIL released; the same states as stepping them one by one.");

  m.def(
      "rollout_worlds",
      [](const std::vector<PyWorld*>& worlds, const std::vector<std::int64_t>& increments,
         int threads) {
        for (std::size_t s = 0; s < increments.size(); ++s)
          if (increments[s] < 0)
            throw py::value_error("increments[" + std::to_string(s) + "]: must be >= 0 steps");
        const py::ssize_t W = static_cast<py::ssize_t>(worlds.size());
        const py::ssize_t S = static_cast<py::ssize_t>(increments.size());
        py::ssize_t B = 0;
        for (PyWorld* w : worlds) B = std::max<py::ssize_t>(B, w->movingCount());
        Array out({W, S + 1, B, py::ssize_t(7)});
        py::array_t<bool> ok(W);
        std::fill(out.mutable_data(), out.mutable_data() + out.size(),
                  std::numeric_limits<double>::quiet_NaN());
        double* base = out.mutable_data();
        bool* okp = ok.mutable_data();
        {
          py::gil_scoped_release release;
          forWorlds(worlds.size(), threads, [&](std::size_t k) {
            PyWorld& w = *worlds[k];
            double* dst = base + k * (S + 1) * B * 7;
            w.posesInto(dst);
            bool finite = true;
            for (py::ssize_t s = 0; s < S && finite; ++s) {
              w.world().step(static_cast<std::uint64_t>(increments[s]));
              finite = finiteState(w.world());
              if (finite) w.posesInto(dst + (s + 1) * B * 7);
            }
            okp[k] = finite;
          });
        }
        return py::make_tuple(out, ok);
      },
      py::arg("worlds"), py::arg("increments"), py::arg("threads") = 0,
      "Steps each world through the samples: increments[s] steps before sample s + 1, "
      "recording its root-link poses at each: returns (poses (W, S + 1, bodies, 7), ok (W,)), "
      "sample 0 the state before; a world whose state became non-finite stops there, its later "
      "samples NaN, ok False. Worlds in parallel, the GIL released.");
}

}  // namespace python
}  // namespace cga_rigid_sim
