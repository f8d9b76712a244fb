"""Where the fit's simulations run: in this process (the batch's threads), or as Dask tasks on an
embedded LocalCluster or on a cluster given by its scheduler address (doc/fitting.md#dask).

A task simulates a chunk of runs under one parameter point (model.simulate_runs). Results are
put back in the order of the points and runs asked for, so they are the same numbers whichever
way and on however many workers they were computed (each simulation is deterministic and the
sums over runs are taken here, in one order).
"""
import math

from . import model

CHUNK = 25  # runs per task: a task then takes ~0.1-0.5 s, well above Dask's ~1 ms overhead


def _task(urdf_text, body, runs, indices, params, dt, size, integrator):
    """One Dask task: runs[indices] under params; never raises (a failure is a result)."""
    chunk = [runs[i] for i in indices]
    try:
        return model.simulate_runs(urdf_text, body, chunk, params, dt, size, integrator)
    except Exception as e:  # reported with its parameters, the other tasks keep theirs
        return [{'run': r.name, 'ok': False, 'position': math.nan, 'rotation': math.nan,
                 'error': '%s: %s' % (type(e).__name__, e)} for r in chunk]


class Runner:
    """evaluate(points, indices) → per point, per run the result dicts of simulate_runs."""

    def __init__(self, urdf_text, body, runs, dt, size, integrator='auto', scheduler=None,
                 workers=None, use_dask=True, chunk=CHUNK):
        self.urdf_text, self.body, self.runs = urdf_text, body, runs
        self.dt, self.size, self.integrator, self.chunk = dt, size, integrator, chunk
        self.client = None
        self.cluster = None
        self.description = 'in-process'
        if use_dask or scheduler:
            from distributed import Client, LocalCluster  # Debian's python3-distributed
            if scheduler:
                self.client = Client(scheduler)
                self.description = 'Dask scheduler %s' % scheduler
            else:
                self.cluster = LocalCluster(n_workers=workers, threads_per_worker=1,
                                            processes=True, dashboard_address=':0')
                self.client = Client(self.cluster)
                self.description = 'Dask LocalCluster, %d workers' % len(
                    self.cluster.scheduler_info['workers'])
            self._urdf = self.client.scatter(urdf_text, broadcast=True)
            self._runs = self.client.scatter(runs, broadcast=True)

    def close(self):
        if self.client is not None:
            self.client.close()
        if self.cluster is not None:
            self.cluster.close()
        self.client = self.cluster = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def evaluate(self, points, indices):
        indices = list(indices)
        chunks = [indices[i:i + self.chunk] for i in range(0, len(indices), self.chunk)]
        if self.client is None:
            out = []
            for params in points:
                res = []
                for ch in chunks:
                    res.extend(_task(self.urdf_text, self.body, self.runs, ch, params, self.dt,
                                     self.size, self.integrator))
                out.append(res)
            return out
        futures = [[self.client.submit(_task, self._urdf, self.body, self._runs, ch, params,
                                       self.dt, self.size, self.integrator, pure=False)
                    for ch in chunks] for params in points]
        out = []
        for row in futures:
            res = []
            for ch, f in zip(chunks, row):
                try:
                    res.extend(f.result())
                except Exception as e:  # the worker died or the task could not run
                    res.extend({'run': self.runs[k].name, 'ok': False, 'position': math.nan,
                                'rotation': math.nan,
                                'error': 'task failed on its worker: %s: %s'
                                         % (type(e).__name__, e)} for k in ch)
            out.append(res)
        return out
