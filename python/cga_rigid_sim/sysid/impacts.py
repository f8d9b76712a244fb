"""The first impact of each measured cube toss, from the tracked poses
(doc/fitting.md#the-first-impact-measured).

For every run: the state just before its first impact (the scoring's free-flight start carried
ballistically to the last sample before the lowest corner reaches the surface), the state just
after (the velocities over the first whole sample interval after it), the landing geometry
(edge or corner, the tilt), and the impulse the surface gave: P = m (v⁺ − v⁻ − g Δt). A
point impulse at the landing point moves ω by I⁻¹ (r × P); what the poses show beside it is
printed, with the impact's restitution at the landing point and its friction ratio |P_t|/P_n.

  scripts/fit impacts DATA_DIR [--height -0.0012] [--json OUT] [--sim mu=0.18,...]

The body is a cube: its mass, moment of inertia and width are read from DATA_DIR/cube.urdf
(--urdf another), the first <mass>, ixx and <box size> in it.

With --sim the same quantities are measured on simulated poses from the same starts (the fit's
parameters, inertia_scale included; the point-impulse prediction uses the URDF's inertia), and
after the first impact: the angle turned in 0.4 s, what |ω| keeps where it drops (and how often
it turns back), and when the cube lies flat. --perturb W,V,N and --scatter MU,E,N count the runs
whose simulation ends on another face when the starts, or each run's μ and e, are drawn afresh;
--grid scores each run at the grid point best for it alone. --rocking: sysid/rocking.py.
--slides: how the error grows and the last flat slides replayed, sysid/slides.py.
--floor: the nominal simulation scored against simulations whose impacts scatter, sysid/floor.py.
--after-first: the runs simulated again from the real state just after the first impact,
sysid/restart.py.
"""
import argparse
import copy
import json
import math
import os
import re
import sys

import numpy as np

from . import floor, model, restart, rocking, scoring, slides, trajectories

RATE = 148.0
POST = 2
G = np.array([0.0, 0.0, -9.81])
SIGNS = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], float)
HALF, MASS, INERTIA = 0.0524, 0.37, 0.00081  # set from the URDF by main()


def read_cube(urdf_text):
    """(half-width, mass, moment of inertia) of the cube of a URDF."""
    def first(pattern):
        m = re.search(pattern, urdf_text)
        if not m:
            raise SystemExit('fit impacts: the URDF has no %s' % pattern)
        return m.group(1)
    size = [float(x) for x in first(r'<box\s+size="([^"]*)"').split()]
    return (0.5 * max(size), float(first(r'<mass\s+value="([^"]*)"')),
            float(first(r'\bixx="([^"]*)"')))


def corners_world(q, p):
    return scoring.quat_rotate(np.repeat(q[None], 8, 0), HALF * SIGNS) + p


def landing(q, p, height, edge_tol=0.004):
    """The landing point (world), its kind ('edge', 'corner', 'face') and the edge's axis."""
    c = corners_world(q, p)
    order = np.argsort(c[:, 2])
    z = c[order, 2]
    if z[3] - z[0] < edge_tol:
        return c[order[:4]].mean(0), 'face', None
    if z[1] - z[0] < edge_tol:
        a, b = c[order[0]], c[order[1]]
        axis = (b - a) / np.linalg.norm(b - a)
        return 0.5 * (a + b), 'edge', axis
    return c[order[0]], 'corner', None


def first_impact(positions, quats, start_pos, start_q, v0, w0, height):
    """The last sample before the free flight's lowest corner reaches `height` (None: never)."""
    n = len(positions)
    for k in range(n):
        t = k / RATE
        p = start_pos + v0 * t + 0.5 * G * t * t
        ang = w0 * t
        th = np.linalg.norm(ang)
        dq = np.r_[math.cos(th / 2), (ang / th * math.sin(th / 2)) if th > 0 else np.zeros(3)]
        q = scoring.quat_mul(dq, start_q)
        if corners_world(q, p)[:, 2].min() < height:
            return max(k - 1, 0)
    return None


def measure(positions, quats, st, height):
    """The first impact of one run (positions, quats from the start on)."""
    k = first_impact(positions, quats, st.position, st.quaternion, st.velocity, st.omega_world,
                     height)
    if k is None or k + POST + 2 >= len(positions):
        return None
    t = k / RATE
    v_pre = st.velocity + G * t                 # ballistic to sample k
    w_pre = st.omega_world                      # torque-free cube: ω constant
    q_pre = quats[k]
    # After: the interval [k+POST, k+POST+1], the first whole one after the impact (a
    # rounded corner touches up to 3 mm below the sharp one's free-flight estimate).
    dt = 1.0 / RATE
    a, b = k + POST, k + POST + 1
    v_post = (positions[b] - positions[a]) / dt
    rel = scoring.quat_mul(quats[b], scoring.quat_conj(quats[a]))
    w_post = scoring.rotation_vector(rel) / dt  # world axes (left quotient)
    c, kind, axis = landing(quats[k + 1], positions[k + 1], height)
    r = c - positions[k + 1]
    elapsed = (POST + 0.5) * dt                 # from sample k to the interval's middle
    P = MASS * (v_post - v_pre - G * elapsed)
    dw_point = np.cross(r, P) / INERTIA         # a point impulse at the landing point
    dw = w_post - w_pre
    u_pre = v_pre + np.cross(w_pre, r)
    u_post = v_post + np.cross(w_post, r)
    n = np.array([0.0, 0.0, 1.0])
    Pn = P[2]
    Pt = np.linalg.norm(P[:2])
    # The tilt: the angle of the body axis nearest the vertical from it.
    R = np.array([scoring.quat_rotate(q_pre, e) for e in np.eye(3)])
    tilt = math.degrees(math.acos(min(1.0, np.abs(R[:, 2]).max())))
    corner = int(np.argmin(corners_world(quats[k + 1], positions[k + 1])[:, 2]))
    out = {'k': k, 'kind': kind, 'tilt_deg': tilt, 'v_pre': v_pre, 'v_post': v_post,
           'corner': corner, 'place': positions[k][:2],
           'w_pre': w_pre, 'w_post': w_post, 'r': r, 'P': P, 'dw': dw, 'dw_point': dw_point,
           'un_pre': float(u_pre @ n), 'un_post': float(u_post @ n),
           'ut_pre': float(np.linalg.norm(u_pre[:2])), 'ut_post': float(np.linalg.norm(u_post[:2])),
           'Pn': float(Pn), 'Pt': float(Pt)}
    return out


def turn_vectors(quats):
    """ω (world axes) over each sample interval, rad/s."""
    return scoring.turn_vectors(quats) * RATE


def settle_index(quats, degrees=3.0):
    """The first sample from which the cube lies flat for good (tilt below `degrees`)."""
    up = np.stack([scoring.quat_rotate(quats, np.tile(e, (len(quats), 1))) for e in np.eye(3)], 1)
    flat = np.degrees(np.arccos(np.clip(np.abs(up[:, :, 2]).max(1), 0, 1))) < degrees
    k = len(flat)
    while k > 0 and flat[k - 1]:
        k -= 1
    return k


def later(runs, sims):
    """After the first impact: the angle turned in the first 0.4 s, what |ω| keeps where it
    falls by more than a quarter in one sample, and when the cube lies flat, measured and
    simulated."""
    turned, settle = {'data': [], 'sim': []}, []
    kept, signed = {'data': [], 'sim': []}, {'data': [], 'sim': []}
    for run, sim in zip(runs, sims):
        if not sim['ok']:
            continue
        for side, q in (('data', run.quaternion), ('sim', sim['poses'][:, 3:])):
            wv = turn_vectors(q)
            w = np.linalg.norm(wv, axis=1)
            turned[side].append(w[:60].sum() / RATE)
            for k in range(6, min(len(w) - 2, 74)):
                if w[k] > 3 and w[k + 1] < 0.75 * w[k]:  # a drop: an impact after the first
                    j = k + 1 if w[k + 1] <= w[k + 2] else k + 2
                    kept[side].append(w[j] / w[k])
                    signed[side].append(wv[j] @ wv[k] / w[k] ** 2)  # < 0: the turn reversed
        settle.append(settle_index(sim['poses'][:, 3:]) - settle_index(run.quaternion))
    d, s = np.array(turned['data']), np.array(turned['sim'])
    print('angle turned in the first 0.4 s (median): data %.2f rad, sim %.2f rad; the sim less '
          'by more than 0.3 rad in %d runs' % (np.median(d), np.median(s), (s < d - 0.3).sum()))
    for side in ('data', 'sim'):
        q = np.percentile(kept[side], [50, 25, 75])
        r = np.percentile(signed[side], [50, 25, 75])
        print('  %s: |w| kept where it falls by more than 1/4 in a sample: %.2f [%.2f %.2f]; '
              'along its direction %.2f [%.2f %.2f], reversed (< -0.1) in %.0f %% of %d drops'
              % (side, *q, *r, 100 * np.mean(np.array(signed[side]) < -0.1), len(kept[side])))
    settle = np.array(settle)
    print('the sim lies flat %.0f ms before the data on average; sooner by more than 10 samples '
          'in %d runs, later in %d' % (-1000 * settle.mean() / RATE, (settle < -10).sum(),
                                        (settle > 10).sum()))


def face_changes(urdf, runs, nominal, params, draws, perturb=None, scatter=None):
    """Runs whose final attitude differs by more than 40° from the nominal simulation's when
    each start (perturb = (relative ω, m/s)) or each run's μ and e (scatter = (relative μ, e))
    is drawn afresh, `draws` times (seed 0)."""
    rng = np.random.default_rng(0)
    changed = np.zeros(len(runs), int)
    rotation = []
    for _ in range(draws):
        res = []
        for run in runs:
            st = copy.copy(run.start)
            p = dict(params)
            if perturb:
                w = st.omega_world
                st.omega_world = w + perturb[0] * np.linalg.norm(w) * rng.normal(size=3) / 3 ** .5
                st.velocity = st.velocity + perturb[1] * rng.normal(size=3) / 3 ** .5
            if scatter:
                p['mu'] = p.get('mu', 0.5) * (1 + scatter[0] * rng.normal())
                p['restitution'] = min(1.0, max(0.0, p.get('restitution', 0.0)
                                                + scatter[1] * rng.normal()))
            r = copy.copy(run)
            r.start = st
            res += model.simulate_runs(urdf, 'body', [r], p, 1.0 / (RATE * 7), 2 * HALF,
                                       keep_poses=True)
        for i, (a, b) in enumerate(zip(nominal, res)):
            if a['ok'] and b['ok'] and math.degrees(scoring.rotation_angle(
                    a['poses'][-1, 3:], b['poses'][-1, 3:])) > 40:
                changed[i] += 1
        rotation.append(np.degrees(np.nanmean([b['rotation'] for b in res])))
    print('final face changed in %d runs in any of %d draws, %.1f per draw; mean rotation error '
          'per draw %s deg (nominal %.1f)' % ((changed > 0).sum(), draws, changed.sum() / draws,
                                              np.round(rotation, 1),
                                              np.degrees(np.nanmean([a['rotation']
                                                                     for a in nominal]))))


def per_run_best(urdf, runs, params, grid):
    """Each run scored at the point of `grid` (name -> values, every combination, the other
    parameters from `params`) best for that run alone (J of fit.py), against the one point
    best for all: what choosing the parameters toss by toss would reach (an optimistic bound:
    each run picks the best of the grid)."""
    import itertools
    names = sorted(grid)
    pos, rot = [], []
    for values in itertools.product(*(grid[n] for n in names)):
        p = dict(params, **dict(zip(names, values)))
        res = model.simulate_runs(urdf, 'body', runs, p, 1.0 / (RATE * 7), 2 * HALF, threads=0)
        pos.append([r['position'] if r['ok'] else 1.0 for r in res])
        rot.append([math.degrees(r['rotation']) if r['ok'] else 90.0 for r in res])
    pos, rot = np.array(pos), np.array(rot)
    J = pos / 0.10 + rot / 15.0
    each, one = J.argmin(0), J.mean(1).argmin()
    i = np.arange(len(runs))
    out = (pos[each, i].mean(), rot[each, i].mean(), pos[one].mean(), rot[one].mean())
    print('grid of %d points (%s): each run at its own best %.1f %%, %.1f deg; all at the one '
          'best point %.1f %%, %.1f deg' % (len(J), ', '.join(names), 100 * out[0], out[1],
                                          100 * out[2], out[3]))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(prog='fit impacts', description=__doc__.split('\n\n')[0])
    ap.add_argument('data')
    ap.add_argument('--height', type=float, default=-0.0012)
    ap.add_argument('--sim', default=None, help='parameters name=value,...')
    ap.add_argument('--runs', default=None, help='first:last (inclusive) run indices')
    ap.add_argument('--json', default=None, help='write every impact measured to this file')
    ap.add_argument('--urdf', default=None, help='the cube (default DATA_DIR/cube.urdf)')
    ap.add_argument('--perturb', default=None, metavar='W,V,N',
                    help='with --sim: draw each start N times, ω changed by W of itself and v by '
                         'V m/s (random directions), and count the runs ending on another face')
    ap.add_argument('--scatter', default=None, metavar='MU,E,N',
                    help='with --sim: draw μ (relative standard deviation MU) and e (standard '
                         'deviation E) afresh for each run, N times, and count the same')
    ap.add_argument('--rocking', action='store_true',
                    help='also measure the rocking impacts (an edge landing after a turn on the '
                         'next edge) and, with --sim, where the runs ending on another face part '
                         '(sysid/rocking.py)')
    ap.add_argument('--grid', default=None, metavar='NAME=V1/V2/...,...',
                    help='with --sim: score each run at the grid point best for it alone and '
                         'all at the one best point (the other parameters from --sim)')
    ap.add_argument('--slides', action='store_true',
                    help='with --sim: how the error grows from the start in the runs ending on '
                         'the real face and the others, and each last flat slide simulated from '
                         'the real state at its start (sysid/slides.py)')
    ap.add_argument('--floor', default=None, metavar='KI,E,MU,N[,EVERY]',
                    help='with --sim: score the nominal simulation against N simulations whose '
                         'k_i, e and μ are drawn afresh every EVERY samples (3) over the first '
                         '%d (standard deviations KI and MU relative, E absolute): the error '
                         'one set of values leaves on impacts that scatter so '
                         '(sysid/floor.py)' % floor.SPAN)
    ap.add_argument('--floor-spin', default='0,0,0', metavar='LEVER,ACROSS,VERTICAL',
                    help='with --floor: also add to the spin the first impact leaves a departure '
                         'drawn with these deviations (rad/s) about the landing\'s lever, across '
                         'it and about the vertical (what "the first impact\'s spin against the '
                         'model\'s" measures)')
    ap.add_argument('--after-first', action='store_true',
                    help='with --sim: simulate each run again from the real state just after '
                         'its first impact and score the rest of it (sysid/restart.py)')
    args = ap.parse_args(argv)
    if args.after_first and not args.sim:
        ap.error('--after-first needs --sim (the parameters)')
    try:
        spin = tuple(float(x) for x in args.floor_spin.split(','))
        if len(spin) != 3:
            raise ValueError
    except ValueError:
        ap.error('--floor-spin %r: expected LEVER,ACROSS,VERTICAL (three numbers)'
                 % args.floor_spin)
    if args.slides and not args.sim:
        ap.error('--slides needs --sim (the parameters)')
    if any(spin) and not args.floor:
        ap.error('--floor-spin needs --floor (the scatter it adds to)')
    if args.floor:
        if not args.sim:
            ap.error('--floor needs --sim (the nominal parameters)')
        try:
            parts = [float(x) for x in args.floor.split(',')]
            if len(parts) not in (4, 5) or any(x != int(x) for x in parts[3:]):
                raise ValueError
        except ValueError:
            ap.error('--floor %r: expected KI,E,MU,N[,EVERY] (three deviations, then whole '
                     'numbers)' % args.floor)
        scatter = dict(zip(('impact_friction_ratio', 'restitution', 'mu'), parts[:3]))
        draws, every = int(parts[3]), int(parts[4]) if len(parts) == 5 else 3
    if args.grid:
        if not args.sim:
            ap.error('--grid needs --sim (the other parameters)')
        try:
            grid = {k: [float(x) for x in v.split('/')] for k, v in
                    (p.split('=') for p in args.grid.split(','))}
        except ValueError:
            ap.error('--grid %r: expected NAME=V1/V2/...,... (numbers)' % args.grid)
        for name, values in grid.items():
            for v in values:
                try:
                    model.check_value(name, v)
                except model.ParameterError as e:
                    ap.error('--grid: %s' % e)
    global HALF, MASS, INERTIA
    urdf = open(args.urdf or os.path.join(args.data, 'cube.urdf')).read()
    HALF, MASS, INERTIA = read_cube(urdf)
    trajs = trajectories.read_directory(args.data, RATE)
    if args.runs:
        a, b = (int(x) for x in args.runs.split(':'))
        trajs = trajs[a:b + 1]
    radius = HALF * math.sqrt(3)
    runs = model.prepare_runs(trajs, RATE * 7, radius, 0.0, horizon=1.0)
    sims = None
    if args.sim:
        params = {k: float(v) for k, v in (p.split('=') for p in args.sim.split(','))}
        sims = model.simulate_runs(urdf, 'body', runs, params, 1.0 / (RATE * 7), 2 * HALF,
                                   keep_poses=True)
    rows, impact_samples = [], []  # the last sample before each run's first impact, or None
    for i, run in enumerate(runs):
        md = measure(run.position, run.quaternion, run.start, args.height)
        impact_samples.append(md['k'] if md else None)
        if md is None:
            continue
        row = {'run': run.name, 'data': md}
        if sims is not None and sims[i]['ok']:
            poses = sims[i]['poses']
            ms = measure(poses[:, :3], poses[:, 3:], run.start, args.height)
            row['sim'] = ms
        rows.append(row)

    def summary(side):
        rs = [row[side] for row in rows if row.get(side) is not None]
        if not rs:
            return
        proj = [np.dot(r['dw'], r['dw_point']) / np.dot(r['dw_point'], r['dw_point'])
                for r in rs]
        e = [-r['un_post'] / r['un_pre'] for r in rs]
        ratio = [r['Pt'] / r['Pn'] for r in rs]
        cols = [('turn by the impulse over a point impulse at the corner', proj),
                ('normal impulse P_n, N s', [r['Pn'] for r in rs]),
                ('friction ratio |P_t|/P_n', ratio),
                ('restitution at the landing point', e),
                ('slip before, m/s', [r['ut_pre'] for r in rs]),
                ('slip after, m/s', [r['ut_post'] for r in rs])]
        print('%s (%d impacts: %d on a corner, %d on an edge); median [quartiles]'
              % (side, len(rs), sum(r['kind'] == 'corner' for r in rs),
                 sum(r['kind'] == 'edge' for r in rs)))
        for name, x in cols:
            q = np.nanpercentile(x, [50, 25, 75])
            print('  %-56s %6.3f [%6.3f %6.3f]' % (name, *q))
    summary('data')
    summary('sim')
    dep = floor.spin_scatter(rows)
    if dep is not None:
        print("the first impact's spin against the model's (the same runs; the data's departure "
              "less the measure's own): deviations %.2f, %.2f, %.2f rad/s about the lever, "
              "across it and about the vertical (--floor-spin %.2f,%.2f,%.2f)" % (*dep, *dep))
        if args.floor:
            rocking.predictability(rows, floor.departure_targets())
    if args.rocking:
        for side in ('data', 'sim') if sims is not None else ('data',):
            found = []
            for i, run in enumerate(runs):
                if side == 'data':
                    found += rocking.rocking_impacts(run.position, run.quaternion)
                elif sims[i]['ok']:
                    found += rocking.rocking_impacts(sims[i]['poses'][:, :3],
                                                     sims[i]['poses'][:, 3:])
            rocking.summarize_rocking(side, found)
        rocking.predictability(rows)
        if sims is not None:
            rocking.print_parting(rocking.parting(runs, sims))
            rocking.compare_after_first_impact(runs, sims, impact_samples)
    if sims is not None:
        later(runs, sims)
        if args.slides:
            slides.report(urdf, 'body', runs, sims, params, 1.0 / (RATE * 7), 2 * HALF, HALF)
        if args.grid:
            per_run_best(urdf, runs, params, grid)
        if args.after_first:
            restart.report(restart.after_first(urdf, 'body', runs, sims, impact_samples,
                                               params, 1.0 / (RATE * 7), 2 * HALF, RATE))
        if args.floor:
            try:
                f = floor.floor(urdf, 'body', runs, params, scatter, draws, every,
                                1.0 / (RATE * 7), 2 * HALF, spin=spin)
            except model.ParameterError as e:
                ap.error('--floor: %s' % e)
            sp, sr, n = floor.tracking_noise(trajs, radius)
            print('tracking noise in free flight (%d runs, median): %.3f mm and %.3f deg per '
                  'axis' % (n, 1e3 * sp, math.degrees(sr)))
            print('floor: the nominal simulation scored against %d draws of each of %d runs '
                  '(k_i %.0f %%, e %.3f, mu %.0f %% drawn every %d samples over the first %d; '
                  'the first impact\'s spin %.2f, %.2f, %.2f rad/s): %.1f %%, %.1f deg, '
                  'another final face in %.1f runs per draw; against the data %.1f %%, %.1f deg'
                  % (draws, f['runs'], 100 * scatter['impact_friction_ratio'],
                     scatter['restitution'], 100 * scatter['mu'], every, floor.SPAN, *spin,
                     100 * f['position'], math.degrees(f['rotation']),
                     f['other_faces_per_draw'], 100 * f['data_position'],
                     math.degrees(f['data_rotation'])))
            print('  where the data falls among the draws (per run the share of draws nearer '
                  'the nominal than the data; 0.5 if the data is a typical draw): position '
                  '%.2f, rotation %.2f' % (f['rank_position'], f['rank_rotation']))
        for opt, key in ((args.perturb, 'perturb'), (args.scatter, 'scatter')):
            if opt:
                a, b, n = opt.split(',')
                face_changes(urdf, runs, sims, params, int(n), **{key: (float(a), float(b))})
    if args.json:
        def conv(o):
            if isinstance(o, np.ndarray):
                return o.tolist()
            raise TypeError(o)
        with open(args.json, 'w') as f:
            json.dump(rows, f, default=conv)
    return 0


if __name__ == '__main__':
    sys.exit(main())
