"""The rocking impacts of the measured cube tosses, one by one, and where the simulated
tosses that end on another face part from the real ones
(doc/fitting.md#the-rocking-impacts-measured, #the-tosses-that-end-on-another-face).

A rocking impact: the cube turns on one edge (A, the lower edge of its lowest face, the turn
about A's axis) and lands on the next (B, the face's opposite edge, coming down), as
Housner's rocking block. Each one found where |ω| falls by more than a quarter in one sample
interval (as `fit impacts` counts the later impacts) is measured as the first impact is
(sysid/impacts.py): the velocities over the sample interval before and the one after, the
impulse the surface gave between their middles, P = m (v⁺ − v⁻ − g Δt) (A's and B's together,
the weight's share included), its friction ratio |P_t|/P_n, what ω keeps along its direction,
and B's velocity before and after, along the normal and across the edge (B's slip: 0 if it
grips).

  scripts/fit impacts DATA_DIR --rocking [--sim PARAMS] [--json OUT]
"""
import math

import numpy as np

from . import impacts, scoring

AXIS = 0.8           # |cos| of the turn's axis with the edge's


def intervals(positions, quats):
    """Velocity of the centre and ω (world axes) over each sample interval."""
    v = np.diff(positions, axis=0) * impacts.RATE
    return v, impacts.turn_vectors(quats)


def drops(w, first=6, last=74):
    """(k, j): |ω| falls by more than a quarter from interval k to k + 1; j the interval after
    it (k + 1 or k + 2, the lower), as impacts.later counts them, but a fall that goes on into
    the interval after is one impact, not two."""
    out = []
    for k in range(first, min(len(w) - 2, last)):
        if w[k] > 3 and w[k + 1] < 0.75 * w[k] and not (out and k < out[-1][1]):
            out.append((k, k + 1 if w[k + 1] <= w[k + 2] else k + 2))
    return out


def edge_geometry(q, p, wv, max_tilt=20.0):
    """A (the pivot edge: its two corners' indices), B (the landing edge's) and the tilt of the
    face coming down, or None when the cube is not turning about an edge of its lowest face
    (the face within max_tilt of flat, ω within acos(AXIS) of one of its edges' direction)."""
    c = impacts.corners_world(q, p)
    axes = np.array([scoring.quat_rotate(q, e) for e in np.eye(3)])
    down = int(np.argmax(np.abs(axes[:, 2])))
    tilt = math.degrees(math.acos(min(1.0, abs(axes[down, 2]))))
    if tilt > max_tilt:
        return None
    s = impacts.SIGNS
    side = -np.sign(axes[down, 2])            # the lowest face: body coordinate `down` = side
    face = [m for m in range(8) if s[m, down] == side]
    cos = np.abs(axes @ (wv / np.linalg.norm(wv)))
    cos[down] = 0
    along = int(np.argmax(cos))
    if cos[along] < AXIS:
        return None
    across = 3 - down - along
    e0 = np.array([m for m in face if s[m, across] < 0])
    e1 = np.array([m for m in face if s[m, across] > 0])
    a, b = (e0, e1) if c[e0, 2].mean() < c[e1, 2].mean() else (e1, e0)
    return a, b, tilt


def rocking_impacts(positions, quats):
    """Every rocking impact of one run (poses from its start)."""
    v, wv = intervals(positions, quats)
    w = np.linalg.norm(wv, axis=1)
    out = []
    for k, j in drops(w):
        geo = edge_geometry(quats[k], positions[k], wv[k])
        if geo is None:
            continue
        a, b, tilt = geo
        dt = (j - k) / impacts.RATE
        P = impacts.MASS * (v[j] - v[k] - impacts.G * dt)
        c = impacts.corners_world(quats[k], positions[k])
        centre = positions[k]
        rb = c[b].mean(0) - centre
        ra = c[a].mean(0) - centre
        axis = c[a[1]] - c[a[0]]
        axis /= np.linalg.norm(axis)
        across = np.cross(axis, [0.0, 0.0, 1.0])
        across /= np.linalg.norm(across)
        if np.dot(across, rb - ra) < 0:
            across = -across                   # from A towards B
        ub0, ub1 = v[k] + np.cross(wv[k], rb), v[j] + np.cross(wv[j], rb)
        ua1 = v[j] + np.cross(wv[j], ra)
        if ub0[2] >= 0:
            continue                           # B not coming down: not a landing on B
        out.append({'k': int(k), 'j': int(j), 'tilt_deg': float(tilt),
                    'w_pre': float(w[k]), 'kept': float(wv[j] @ wv[k] / w[k] ** 2),
                    'Pn': float(P[2]), 'Pt': float(np.linalg.norm(P[:2])),
                    'Pt_across': float(P @ across),
                    'ratio': float(np.linalg.norm(P[:2]) / P[2]) if P[2] > 0 else math.nan,
                    'ub_n_pre': float(ub0[2]), 'ub_n_post': float(ub1[2]),
                    'bounce': float(-ub1[2] / ub0[2]),
                    'ub_slip_pre': float(ub0 @ across), 'ub_slip_post': float(ub1 @ across),
                    'ua_n_post': float(ua1[2])})
    return out


def summarize_rocking(side, rows):
    """Medians and quartiles over a side's rocking impacts; the gripping against the slipping."""
    if not rows:
        print('%s: no rocking impacts' % side)
        return
    def col(key, rs=rows):
        return np.array([r[key] for r in rs], float)
    print('%s: %d rocking impacts (tilt %.0f deg median); median [quartiles]'
          % (side, len(rows), np.median(col('tilt_deg'))))
    for key, name in (('w_pre', '|w| before, rad/s'), ('kept', 'w kept along its direction'),
                      ('Pn', 'normal impulse P_n, N s'), ('ratio', 'friction ratio |P_t|/P_n'),
                      ('ub_n_pre', "B's normal velocity before, m/s"),
                      ('ub_n_post', "B's normal velocity after, m/s"),
                      ('bounce', "B's restitution (after over before)"),
                      ('ub_slip_pre', "B's slip across the edge before, m/s"),
                      ('ub_slip_post', "B's slip across the edge after, m/s"),
                      ('ua_n_post', "A's normal velocity after (> 0: lifts), m/s")):
        q = np.nanpercentile(col(key), [50, 25, 75])
        print('  %-48s %7.3f [%7.3f %7.3f]' % (name, *q))
    kept = col('kept')
    print('  turned back (kept < -0.1) in %.0f %%' % (100 * np.mean(kept < -0.1)))
    slip = np.abs(col('ub_slip_post'))
    for name, m in (('B grips (|slip after| < 0.03 m/s)', slip < 0.03),
                    ('B slips', slip >= 0.03)):
        if m.any():
            rs = [r for r, x in zip(rows, m) if x]
            print('  %-34s %3d: kept %.2f, ratio %.2f, turned back in %.0f %%'
                  % (name, m.sum(), np.median(col('kept', rs)), np.nanmedian(col('ratio', rs)),
                     100 * np.mean(col('kept', rs) < -0.1)))


def down_face(q):
    """The body axis (±1, ±2, ±3) pointing most nearly down."""
    d = scoring.quat_rotate(scoring.quat_conj(q), np.array([0.0, 0.0, -1.0]))
    i = int(np.argmax(np.abs(d)))
    return (i + 1) * (1 if d[i] > 0 else -1)


def parting(runs, sims, threshold=40.0):
    """The runs whose simulation ends on another face than the real cube (final rotation error
    above `threshold` degrees), each with the sample where the two part for good (rotation error
    above 15 deg from there on) and what each cube was doing there: its impacts before, those
    within 6 samples of it, |ω|, its tilt, the largest tilt in the next 30 samples (45 deg:
    over an edge) and whether it turns about an edge of its lowest face."""
    rows = []
    for run, sim in zip(runs, sims):
        if not sim['ok']:
            continue
        rot = np.degrees(sim['rotation_series'])
        if rot[-1] < threshold:
            continue
        above = rot > 15
        m = len(above)
        while m > 0 and above[m - 1]:
            m -= 1
        row = {'run': run.name, 'part': int(m), 'final_deg': float(rot[-1]),
               'face_data': down_face(run.quaternion[-1]),
               'face_sim': down_face(sim['poses'][-1, 3:])}
        for side, p, q in (('data', run.position, run.quaternion),
                           ('sim', sim['poses'][:, :3], sim['poses'][:, 3:])):
            v, wv = intervals(p, q)
            w = np.linalg.norm(wv, axis=1)
            ks = [k for k, _ in drops(w, first=0, last=len(w))]
            lo = max(0, m - 6)
            row[side] = {'drops_before': sum(k < m for k in ks),
                         'drop_near': [k for k in ks if lo <= k <= m + 1],
                         'w': float(w[min(m, len(w) - 1)]),
                         'tilt_deg': float(tilt_of(q[m])),
                         'max_tilt_after': float(max(tilt_of(x) for x in q[m:m + 30])),
                         'on_edge': edge_geometry(q[m], p[m], wv[min(m, len(w) - 1)]) is not None}
        rows.append(row)
    return rows


def face_sequence(quats):
    """The faces the cube lies nearest to, in the order it visits them."""
    out = []
    for q in quats:
        f = down_face(q)
        if not out or out[-1] != f:
            out.append(f)
    return out


def trend(quats, k):
    """'back' if the tilt falls by more than 1 deg from sample k + 3 to k + 9 after the first
    impact at k (the cube falling back from the edge it landed on onto the face), 'over' if it
    rises by as much, else 'level'."""
    a, b = tilt_of(quats[k + 3]), tilt_of(quats[k + 9])
    return 'over' if b > a + 1 else ('back' if b < a - 1 else 'level')


def compare_after_first_impact(runs, sims, first, threshold=40.0):
    """The runs ending on another face against the others: how their face sequences differ,
    ω's difference after the first impact (at sample first[i]) relative to the measured one,
    the attitude's difference 10 samples after it, how high the lowest (sharp) corner rises
    after it (z of the data's frame: the table is 1.2 mm below 0), and the tilt's trend from
    the edge landed on, measured and simulated."""
    kinds, err = {}, {True: [], False: []}
    trends = {}
    for run, sim, k in zip(runs, sims, first):
        if not sim['ok'] or k is None:
            continue
        qs = sim['poses'][:, 3:]
        wrong = bool(np.degrees(sim['rotation_series'][-1]) > threshold)
        if wrong:
            d, s = face_sequence(run.quaternion), face_sequence(qs)
            kind = ('simulated one face further' if s[:-1] == d else
                    'real one face further' if d[:-1] == s else
                    'simulated further' if s[:len(d)] == d else
                    'real further' if d[:len(s)] == s else 'different ways')
            kinds.setdefault(kind, []).append(run.name)
        wd = impacts.turn_vectors(run.quaternion)
        ws = impacts.turn_vectors(qs)
        lift = [1e3 * max(impacts.corners_world(q[i], p[i])[:, 2].min()
                          for i in range(k + 2, k + 12)) for p, q in
                ((run.position, run.quaternion), (sim['poses'][:, :3], qs))]
        err[wrong].append([np.linalg.norm(wd[k + 3] - ws[k + 3]) / np.linalg.norm(wd[k + 3]),
                           math.degrees(sim['rotation_series'][k + 10])] + lift)
        key = (trend(run.quaternion, k), trend(qs, k))
        n, m = trends.get(key, (0, 0))
        trends[key] = (n + 1, m + wrong)
    for kind, names in sorted(kinds.items()):
        print('  %-28s %2d: %s' % (kind, len(names), ' '.join(names)))
    for wrong in (True, False):
        if err[wrong]:
            e = np.median(np.array(err[wrong]), 0)
            print('  runs %s: |w_sim - w_data|/|w_data| just after the first impact %.2f, '
                  'attitude apart 10 samples after it %.1f deg, highest lowest corner 2-11 '
                  'samples after it %.1f mm measured, %.1f mm simulated (medians of %d)'
                  % ('on another face' if wrong else 'on the same face', e[0], e[1], e[2],
                     e[3], len(err[wrong])))
    print('  tilt 3 -> 9 samples after the first impact (data, sim): runs, of them on another face')
    for key, (n, m) in sorted(trends.items()):
        print('    %-6s %-6s %3d %3d' % (key[0], key[1], n, m))


def first_impact_targets():
    """The first impact's friction ratio and bounce: what `predictability` asks of by default."""
    return [('friction ratio', lambda row: row['data']['Pt'] / row['data']['Pn']),
            ('bounce', lambda row: -row['data']['un_post'] / row['data']['un_pre'])]


def predictability(rows, targets=None):
    """Whether quantities of the first corner impacts (`targets`: (name, function of a row ->
    value or None); the friction ratio and the bounce by default) follow from the state before
    them: a linear least-squares model in the tilt, the slip speed, the normal speed, |ω|, the
    spin about the vertical, the slip's direction against the lever's and the place on the
    table, scored leave-one-out (R²); and a Kruskal–Wallis test across the cube's eight
    corners."""
    from scipy.stats import kruskal
    targets = targets or first_impact_targets()
    X, Y, corner = [], [], []
    for row in rows:
        md = row['data']
        if md['kind'] != 'corner':
            continue
        y = [f(row) for _, f in targets]
        if any(v is None for v in y):
            continue
        w, r = md['w_pre'], md['r']
        slip = (md['v_pre'] + np.cross(w, r))[:2]
        X.append([md['tilt_deg'], md['ut_pre'], -md['un_pre'], np.linalg.norm(w), abs(w[2]),
                  (slip / np.linalg.norm(slip)) @ (r[:2] / np.linalg.norm(r[:2])),
                  *md['place']])
        Y.append(y)
        corner.append(md['corner'])
    X, Y, corner = np.array(X), np.array(Y), np.array(corner)
    A = np.c_[np.ones(len(X)), (X - X.mean(0)) / np.where(X.std(0) > 0, X.std(0), 1.0)]
    out = {}
    for j, (name, _) in enumerate(targets):
        loo = []
        for i in range(len(X)):
            m = np.arange(len(X)) != i
            c = np.linalg.lstsq(A[m], Y[m, j], rcond=None)[0]
            loo.append(Y[i, j] - A[i] @ c)
        r2 = 1 - np.sum(np.square(loo)) / np.sum(np.square(Y[:, j] - Y[:, j].mean()))
        p = kruskal(*[Y[corner == c, j] for c in np.unique(corner)]).pvalue
        print('  %s of the %d corner impacts: sd %.3f, leave-one-out R^2 of the linear model '
              '%.2f; across the 8 corners Kruskal-Wallis p = %.2f' % (name, len(X),
                                                                      Y[:, j].std(), r2, p))
        out[name] = (r2, p)
    return out


def tilt_of(q):
    """Angle of the body axis nearest the vertical from it, degrees."""
    up = [scoring.quat_rotate(q, e) for e in np.eye(3)]
    return math.degrees(math.acos(min(1.0, max(abs(u[2]) for u in up))))


def print_parting(rows):
    print('runs ending on another face: %d' % len(rows))
    print('  run  part(sample)  final  | data: impacts before, tilt, max tilt next 30 (45: over '
          'an edge), |w|, on an edge | sim: the same')
    for r in rows:
        d, s = r['data'], r['sim']
        print('  %s %4d %5.0f deg | %d %4.0f %4.0f %5.1f %d | %d %4.0f %4.0f %5.1f %d | drops near '
              'data %s sim %s' % (r['run'], r['part'], r['final_deg'], d['drops_before'],
                                  d['tilt_deg'], d['max_tilt_after'], d['w'], d['on_edge'],
                                  s['drops_before'], s['tilt_deg'], s['max_tilt_after'], s['w'],
                                  s['on_edge'], d['drop_near'], s['drop_near']))
