"""The `fit` command (scripts/fit, or python3 -m cga_rigid_sim.sysid): fit simulation parameters
to measured runs with cross-validation, sweep parameters, or score one choice
(doc/fitting.md).

    fit cv    DATA --urdf URDF --model NAME:RANGES [--model …] [--folds 2] [--out DIR]
    fit sweep DATA --urdf URDF --params RANGES --points 200 [--workers N]
    fit eval  DATA --urdf URDF --set mu=0.18,restitution=0.1,height=-0.0012
    fit impacts CUBE_DATA [--sim PARAMS]   (each toss's first impact: fit impacts --help)

DATA: a directory of CSV files, CSV files, or a rosbag of tf (with --frame). RANGES:
name=low:high or name=value, comma-separated (model.PARAMETERS lists the names). Simulations
run as Dask tasks on an embedded LocalCluster (--workers, default the cores), on a cluster
(--scheduler tcp://host:port) or in this process (--no-dask); the results are the same.
"""
import argparse
import os
import sys
import time

import numpy as np

from . import fit as fitting
from . import impacts, model, report, scoring, trajectories
from .runner import Runner


class InputError(ValueError):
    pass


def load_data(paths, rate, frame=None, parent='world'):
    runs = []
    for p in paths:
        if os.path.isdir(p):
            runs.extend(trajectories.read_directory(p, rate=rate))
        elif p.endswith('.bag'):
            if not frame:
                raise InputError('%s: a bag needs --frame (the tf frame of the body)' % p)
            runs.extend(trajectories.read_bag(p, frame, parent))
        else:
            runs.append(trajectories.read_csv(p, rate=rate))
    if not runs:
        raise InputError('no trajectory given')
    return runs


def select(runs, spec):
    """Runs by index ranges '0-49,60' (in data order)."""
    if not spec:
        return runs
    keep = []
    for part in spec.split(','):
        a, _, b = part.partition('-')
        try:
            lo, hi = int(a), int(b or a)
        except ValueError:
            raise InputError('--runs: %r is not an index or a range a-b' % part) from None
        if not 0 <= lo <= hi < len(runs):
            raise InputError('--runs: %r outside 0-%d' % (part, len(runs) - 1))
        keep.extend(range(lo, hi + 1))
    return [runs[k] for k in keep]


def setup(args):
    import cga_rigid_sim
    try:
        with open(args.urdf) as f:
            urdf_text = f.read()
    except OSError as e:
        raise InputError('%s: cannot read the URDF (%s)' % (args.urdf, e.strerror)) from None
    scene = cga_rigid_sim.load_urdf_string(urdf_text, args.urdf)
    body = args.body or (scene.body_names[0] if scene.body_names else None)
    if body is None or body not in scene.body_names:
        raise InputError('%s: --body %r is not a body of the URDF (bodies: %s)'
                         % (args.urdf, body, ', '.join(scene.body_names)))
    size, radius = model.object_size(scene, body)
    if args.size:
        size = args.size
    trajs = select(load_data(args.data, args.rate, args.frame, args.parent), args.runs)
    steps_per_second = args.rate * args.steps_per_sample
    runs = model.prepare_runs(trajs, steps_per_second, radius, 0.0, scene.gravity,
                              horizon=args.horizon)
    runner = Runner(urdf_text, body, runs, 1.0 / steps_per_second, size,
                    integrator=args.integrator, scheduler=args.scheduler, workers=args.workers,
                    use_dask=not args.no_dask)
    return urdf_text, body, size, runs, runner


def starts(texts, problem, name):
    """The --start points of a model: each NAME=VALUE,... with every free parameter in range
    (values of parameters the model holds fixed or lacks are left out)."""
    out = []
    for text in texts:
        try:
            p = {k: float(v) for k, v in (x.split('=') for x in text.split(','))}
        except ValueError:
            raise InputError('--start %r: expected NAME=VALUE,...' % text) from None
        point = {k: v for k, v in p.items() if k in problem.free}
        try:
            problem.scaled(point, '--start (model %s)' % name)
        except ValueError as e:
            raise InputError(str(e)) from None
        out.append(point)
    return out


def cmd_cv(args):
    models = []
    for spec in args.model:
        name, sep, ranges = spec.partition(':')
        if not sep:
            raise InputError('--model %r: expected NAME:RANGES, e.g. plain:mu=0.05:0.6' % spec)
        models.append((name, model.parse_ranges(ranges)))
    if not models:
        raise InputError('cv: give at least one --model NAME:RANGES')
    for name, ranges in models:  # refused before any simulation
        starts(args.start, fitting.Problem(ranges), name)
    urdf_text, body, size, runs, runner = setup(args)
    log = (lambda s: print(s, flush=True)) if args.verbose else None
    summary = {'data': ' '.join(args.data), 'runs': len(runs), 'urdf': args.urdf, 'body': body,
               'size': size, 'dt': runner.dt, 'runner': runner.description,
               'ranges': {}, 'folds': [], 'models': [], 'plots': [],
               'in_sample': args.folds == 1}
    per_model_rows, sens_by_model = {}, {}
    t0 = time.time()
    with runner:
        fold_sets = fitting.folds(len(runs), args.folds)
        for name, ranges in models:
            summary['ranges'].update({'%s.%s' % (name, k): v for k, v in ranges.items()})
            problem = fitting.Problem(ranges)
            held = []
            for f, test in enumerate(fold_sets):
                train = [k for k in range(len(runs)) if k not in set(test)] if args.folds > 1 \
                    else test
                print('fit: model %s, fold %d: fitting on %d runs, testing on %d'
                      % (name, f, len(train), len(test)), flush=True)
                res = fitting.fit(runner, train, problem, initial=args.initial,
                                  max_evaluations=args.max_evaluations, log=log,
                                  starts=starts(args.start, problem, name))
                test_res = model.simulate_runs(urdf_text, body, [runs[k] for k in test],
                                               res['params'], runner.dt, size, args.integrator,
                                               threads=0, keep_poses=True)
                ok = [r for r in test_res if r['ok']]
                stats = scoring.summarize([r['position'] for r in ok],
                                          [r['rotation'] for r in ok])
                failed = [{'run': x['run'], 'params': x['params'], 'error': x['error']}
                          for h in res['history'] for x in
                          [{'params': h['params'], **y} for y in h['failed']]]
                failed += [{'run': r['run'], 'params': res['params'], 'error': r['error']}
                           for r in test_res if not r['ok']]
                summary['folds'].append({
                    'model': name, 'fold': f, 'train_runs': _span(runs, train),
                    'test_runs': _span(runs, test), 'params': res['params'],
                    'train': {k: res['train'][k] for k in ('position', 'rotation_deg',
                                                           'objective')},
                    'test': stats, 'evaluations': res['evaluations'], 'failed': failed})
                print('fit: model %s, fold %d: %s; test position %.1f %%, rotation %.1f deg'
                      % (name, f, ', '.join('%s=%.4g' % kv for kv in res['params'].items()),
                         100 * stats['position_mean'], stats['rotation_mean_deg']), flush=True)
                held.extend(ok)
                if args.sensitivity and f == 0:
                    sens_by_model[name] = fitting.sensitivity(runner, train, problem,
                                                              res['params'])
            per_model_rows[name] = held
            m = scoring.summarize([r['position'] for r in held], [r['rotation'] for r in held])
            summary['models'].append({'model': name, **m})
    summary['wall_time_s'] = time.time() - t0
    if args.out:
        os.makedirs(args.out, exist_ok=True)
        runs_are = 'run fitted on' if summary['in_sample'] else 'held-out run'
        report.plot_errors(os.path.join(args.out, 'errors_per_run.png'), per_model_rows,
                           runs_are)
        report.plot_error_vs_time(os.path.join(args.out, 'error_vs_time.png'), per_model_rows,
                                  args.rate)
        summary['plots'] = [('error per ' + runs_are, 'errors_per_run.png'),
                            ('error against time', 'error_vs_time.png')]
        if sens_by_model:
            report.plot_sensitivity(os.path.join(args.out, 'sensitivity.png'), sens_by_model)
            summary['plots'].append(('sensitivity of the objective', 'sensitivity.png'))
        details = {name: [{k: (v.tolist() if isinstance(v, np.ndarray) else v)
                           for k, v in r.items() if k != 'poses'} for r in rows]
                   for name, rows in per_model_rows.items()}
        details['sensitivity'] = sens_by_model
        text = report.write(args.out, summary, details)
    else:
        text = report.write(None, summary)
    print(text)
    return 0


def _span(runs, idx):
    """'000–049' for a contiguous set of runs, else their count."""
    if idx and idx == list(range(idx[0], idx[-1] + 1)):
        return '%s–%s' % (runs[idx[0]].name, runs[idx[-1]].name)
    return '%d runs' % len(idx)


def cmd_sweep(args):
    from scipy.stats import qmc
    ranges = model.parse_ranges(args.params)
    problem = fitting.Problem(ranges)
    if args.points < 1:
        raise InputError('--points: must be >= 1 (got %d)' % args.points)
    urdf_text, body, size, runs, runner = setup(args)
    d = len(problem.free)
    us = qmc.Sobol(d, scramble=True, seed=0).random(args.points) if d else \
        np.zeros((args.points, 0))
    points = [problem.params(u) for u in us]
    with runner:
        t0 = time.time()
        results = runner.evaluate(points, range(len(runs)))
        wall = time.time() - t0
        desc = runner.description
    rows = []
    failed = 0
    for p, res in zip(points, results):
        a = fitting.aggregate(res)
        failed += len(a['failed'])
        rows.append((p, a))
        for x in a['failed']:
            print('sweep: failed simulation: run %s at %s: %s' % (
                x['run'], ', '.join('%s=%.6g' % kv for kv in p.items()), x['error']))
    best = min(rows, key=lambda r: r[1]['objective'])
    if args.out:
        with open(args.out, 'w') as f:
            names = list(points[0].keys())
            f.write(','.join(names + ['position', 'rotation_deg', 'objective', 'failed']) + '\n')
            for p, a in rows:
                f.write(','.join(['%.9g' % p[n] for n in names] + [
                    '%.9g' % a['position'], '%.9g' % a['rotation_deg'], '%.9g' % a['objective'],
                    str(len(a['failed']))]) + '\n')
    print('sweep: %d points x %d runs = %d simulations on %s: %.2f s wall; %d failed' % (
        len(points), len(runs), len(points) * len(runs), desc, wall, failed))
    print('sweep: best %s: position %.2f %%, rotation %.2f deg' % (
        ', '.join('%s=%.4g' % kv for kv in best[0].items()), 100 * best[1]['position'],
        best[1]['rotation_deg']))
    return 0


def cmd_eval(args):
    params = {k: v[0] for k, v in model.parse_ranges(args.set).items()}
    urdf_text, body, size, runs, runner = setup(args)
    with runner:
        res = runner.evaluate([params], range(len(runs)))[0]
    for r in res:
        print('%s: position %.2f %%, rotation %.2f deg%s' % (
            r['run'], 100 * r['position'], np.degrees(r['rotation']),
            '' if r['ok'] else ' FAILED: ' + r['error']))
    a = fitting.aggregate(res)
    ok = [r for r in res if r['ok']]
    s = scoring.summarize([r['position'] for r in ok], [r['rotation'] for r in ok])
    print('eval: %d runs: position %.2f %% ± %.2f, rotation %.2f ± %.2f deg; %d failed' % (
        s['runs'], 100 * s['position_mean'], 100 * s['position_std'], s['rotation_mean_deg'],
        s['rotation_std_deg'], len(a['failed'])))
    return 0


def parser():
    p = argparse.ArgumentParser(prog='fit', description=__doc__.split('\n\n')[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest='command', required=True)

    def common(s):
        s.add_argument('data', nargs='+', help='directory of CSV files, CSV files, or a .bag')
        s.add_argument('--urdf', required=True, help="the object's URDF")
        s.add_argument('--body', help='the body in the URDF (default: its first)')
        s.add_argument('--size', type=float, help='size errors are divided by, m (default: '
                       'the largest box edge or diameter of its collision shapes)')
        s.add_argument('--rate', type=float, default=148.0,
                       help='samples per second of CSV files without a t column (148)')
        s.add_argument('--frame', help='bag input: the tf frame of the body')
        s.add_argument('--parent', default='world', help='bag input: its parent frame')
        s.add_argument('--runs', help="a subset by index, e.g. '0-49' or '0-9,20'")
        s.add_argument('--horizon', type=float, help='simulate at most this long, s')
        s.add_argument('--steps-per-sample', type=int, default=7,
                       help='simulation steps between samples (7: dt = 0.97 ms at 148 Hz)')
        s.add_argument('--integrator', default='auto')
        s.add_argument('--scheduler', help='a Dask scheduler, tcp://host:port')
        s.add_argument('--workers', type=int, help='LocalCluster workers (default: the cores)')
        s.add_argument('--no-dask', action='store_true', help='simulate in this process')

    s = sub.add_parser('cv', help='fit with k-fold cross-validation and write a report')
    common(s)
    s.add_argument('--model', action='append', default=[],
                   help="NAME:RANGES, e.g. 'plain:mu=0.05:0.6,restitution=0:0.5'; repeatable")
    s.add_argument('--folds', type=int, default=2)
    s.add_argument('--initial', type=int, default=16, help='Sobol points to start from')
    s.add_argument('--max-evaluations', type=int, default=80)
    s.add_argument('--start', action='append', default=[], metavar='NAME=VALUE,...',
                   help='a point the search also starts from (e.g. measured values): every free '
                        'parameter of each model, in its range; may be given several times')
    s.add_argument('--sensitivity', action='store_true',
                   help='profile the objective about each optimum (fold 0)')
    s.add_argument('--out', help='report directory (report.md, results.json, plots)')
    s.add_argument('--verbose', action='store_true')
    s.set_defaults(func=cmd_cv)

    s = sub.add_parser('sweep', help='evaluate a Sobol sweep of parameter points')
    common(s)
    s.add_argument('--params', required=True, help='RANGES')
    s.add_argument('--points', type=int, default=200)
    s.add_argument('--out', help='CSV of the points and their errors')
    s.set_defaults(func=cmd_sweep)

    s = sub.add_parser('eval', help='score one choice of parameters')
    common(s)
    s.add_argument('--set', required=True, help='name=value,…')
    s.set_defaults(func=cmd_eval)

    s = sub.add_parser('impacts', add_help=False,
                       help="measure each cube toss's first impact against the simulation "
                            '(sysid/impacts.py; fit impacts --help)')
    s.set_defaults(func=lambda args: impacts.main([]))  # main() hands it its arguments
    return p


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv[:1] == ['impacts']:  # its own options, --help included
        return impacts.main(argv[1:])
    args = parser().parse_args(argv)
    if getattr(args, 'steps_per_sample', 1) < 1:
        print('fit: --steps-per-sample: must be >= 1', file=sys.stderr)
        return 2
    try:
        return args.func(args)
    except (InputError, trajectories.TrajectoryError, model.ParameterError, ValueError) as e:
        print('fit: error: %s' % e, file=sys.stderr)
        return 2
