"""Fitting parameters to measured runs, with k-fold cross-validation (doc/fitting.md#the-fit).

Objective: J = ē_pos / 0.10 + ē_rot / 15°, the mean position error (fraction of the size) and
the mean rotation error over the training runs, each in units of the acceptance target of
doc/fitting.md, so that neither dominates by its unit. A run whose simulation failed counts as
e_pos = 1, e_rot = 90° (and is reported with its parameters).

Search (deterministic: the same data give the same fit, on any number of workers):
1. a scrambled Sobol sequence of `initial` points over the ranges (scipy's, seed 0), and the
   `starts` given (e.g. measured values; in the ranges);
2. a compass (pattern) search from the best of them, in coordinates scaled to the ranges
   (logarithmically for a range from lo > 0 over at least a factor 30):
   each iteration evaluates the 2d neighbours x ± s e_i together (one batch of tasks), moves to
   the best if it improves J, else halves s; it stops when s < `tolerance` or after
   `max_evaluations`.
Sensitivity: J at the optimum and along each parameter ± 5 %, 10 % and 20 % of its range (of its
value for a log-scaled one).
"""
import math

import numpy as np

POSITION_TARGET = 0.10   # fraction of the size
ROTATION_TARGET = 15.0   # degrees
FAILED_POSITION, FAILED_ROTATION = 1.0, math.pi / 2


def aggregate(results):
    """Mean errors over runs (failed runs at the penalty), the objective and the failures."""
    pos = np.array([r['position'] if r['ok'] else FAILED_POSITION for r in results])
    rot = np.array([r['rotation'] if r['ok'] else FAILED_ROTATION for r in results])
    e_pos, e_rot = float(pos.mean()), float(np.degrees(rot.mean()))
    return {'position': e_pos, 'rotation_deg': e_rot,
            'objective': e_pos / POSITION_TARGET + e_rot / ROTATION_TARGET,
            'failed': [r for r in results if not r['ok']]}


class Problem:
    """The parameters to fit (ranges; a range of one value is held fixed) and fixed values."""

    # A range from lo > 0 spanning at least this ratio is searched in log(x): a stiffness from
    # 300 to 30 000 N/m matters by its factor, not by its difference.
    LOG_RATIO = 30.0

    def __init__(self, ranges, fixed=None):
        self.free = [n for n, (lo, hi) in ranges.items() if hi > lo]
        self.lo = np.array([ranges[n][0] for n in self.free])
        self.hi = np.array([ranges[n][1] for n in self.free])
        self.log = np.array([lo > 0 and hi / lo >= self.LOG_RATIO for lo, hi in
                             zip(self.lo, self.hi)], dtype=bool)
        self.fixed = dict(fixed or {})
        self.fixed.update({n: lo for n, (lo, hi) in ranges.items() if hi == lo})

    def params(self, u):
        """Parameters at scaled coordinates u in [0, 1]^d (log-scaled where self.log)."""
        p = dict(self.fixed)
        u = np.clip(u, 0.0, 1.0)
        lin = self.lo + u * (self.hi - self.lo)
        with np.errstate(divide='ignore', invalid='ignore'):
            logs = self.lo * (self.hi / np.where(self.log, self.lo, 1.0)) ** u
        x = np.where(self.log, logs, lin)
        p.update({n: float(v) for n, v in zip(self.free, x)})
        return p

    def scaled(self, params, what='start'):
        """The scaled coordinates u of a point (the inverse of params()); each free parameter
        must be given, within its range."""
        u = np.zeros(len(self.free))
        for i, n in enumerate(self.free):
            if n not in params:
                raise ValueError('%s: %s is not given (the free parameters: %s)'
                                 % (what, n, ', '.join(self.free)))
            x = float(params[n])
            if not self.lo[i] <= x <= self.hi[i]:
                raise ValueError('%s: %s=%g is outside its range %g:%g'
                                 % (what, n, x, self.lo[i], self.hi[i]))
            u[i] = (math.log(x / self.lo[i]) / math.log(self.hi[i] / self.lo[i]) if self.log[i]
                    else (x - self.lo[i]) / (self.hi[i] - self.lo[i]))
        return u


def fit(runner, indices, problem, initial=16, max_evaluations=80, tolerance=1.0 / 64,
        log=None, starts=()):
    """Fits on runs[indices]; returns the best parameters, their errors and the history.
    `starts`: points (dicts of every free parameter) evaluated with the Sobol points."""
    history = []
    d = len(problem.free)

    def evaluate(us):
        us = [np.clip(u, 0.0, 1.0) for u in us]
        points = [problem.params(u) for u in us]
        results = runner.evaluate(points, indices)
        out = []
        for u, p, res in zip(us, points, results):
            a = aggregate(res)
            history.append({'params': p, **{k: a[k] for k in ('position', 'rotation_deg',
                                                             'objective')},
                            'failed': [{'run': f['run'], 'error': f['error']}
                                       for f in a['failed']]})
            out.append((a['objective'], u, p, a))
        return out

    if d == 0:
        (J, u, p, a), = evaluate([np.zeros(0)])
        return {'params': p, 'train': a, 'evaluations': 1, 'history': history}
    from scipy.stats import qmc
    sobol = qmc.Sobol(d, scramble=True, seed=0)
    start = list(sobol.random(max(2, initial))) + [problem.scaled(p) for p in starts]
    scored = evaluate(start)
    best = min(scored, key=lambda s: (s[0], tuple(s[1])))
    step = 0.25
    while step >= tolerance and len(history) < max_evaluations:
        nbrs = []
        for i in range(d):
            for sgn in (1.0, -1.0):
                u = best[1].copy()
                u[i] = min(1.0, max(0.0, u[i] + sgn * step))
                if not np.array_equal(u, best[1]):
                    nbrs.append(u)
        cand = evaluate(nbrs) if nbrs else []
        top = min(cand, key=lambda s: (s[0], tuple(s[1]))) if cand else None
        if top is not None and top[0] < best[0]:
            best = top
        else:
            step *= 0.5
        if log:
            log('  J %.4f  (position %.4f, rotation %.2f deg) step %.4f  %s' % (
                best[0], best[3]['position'], best[3]['rotation_deg'], step,
                ', '.join('%s=%.4g' % kv for kv in best[2].items())))
    return {'params': best[2], 'train': best[3], 'evaluations': len(history),
            'history': history, 'scaled': best[1].tolist()}


def sensitivity(runner, indices, problem, params,
                fractions=(-0.2, -0.1, -0.05, 0.0, 0.05, 0.1, 0.2)):
    """J along each free parameter about `params`: {name: [(value, objective), …]}."""
    out = {}
    points, keys = [], []
    for i, name in enumerate(problem.free):
        span = problem.hi[i] - problem.lo[i]
        for f in fractions:
            v = params[name] * (1 + f) if problem.log[i] else params[name] + f * span
            if problem.lo[i] <= v <= problem.hi[i]:
                p = dict(params)
                p[name] = float(v)
                points.append(p)
                keys.append((name, float(v)))
    results = runner.evaluate(points, indices) if points else []
    for (name, v), res in zip(keys, results):
        out.setdefault(name, []).append((v, aggregate(res)['objective']))
    for name in out:
        out[name].sort()
    return out


def folds(n, k):
    """k contiguous folds of range(n) (fold f holds runs f n/k … (f+1) n/k − 1)."""
    if not 1 <= k <= n:
        raise ValueError('folds: need 1 <= k <= %d runs (got k = %d)' % (n, k))
    edges = [round(f * n / k) for f in range(k + 1)]
    return [list(range(edges[f], edges[f + 1])) for f in range(k)]
