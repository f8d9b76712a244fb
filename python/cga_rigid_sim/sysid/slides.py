"""Where the error of the tosses that end on the real cube's face comes from: how it grows from
the start, and the last flat slide simulated again from the real cube's state at its start
(doc/fitting.md#the-slides-and-the-impacts).

  scripts/fit impacts DATA_DIR --sim PARAMS --slides

- growth: the mean position and rotation errors at given samples after the start, over the
  runs whose simulation ends on the real face (final rotation error below 40°) and over the
  others; the final rotation error of the first split into its part about the vertical (yaw).
- entry: the sample where each cube lies flat for good, its speed and its spin about the
  vertical there, and the sample where it stops, measured and simulated.
- replay: each run simulated again from the start of the real cube's last flat slide (the
  measured pose made level, the velocities from quadratic fits over five samples), and its end
  compared with the real end. An error left there is the slide's; one that is not was made
  before it, in the impacts.
"""
import math

import numpy as np

from . import impacts, model, rocking, scoring

RATE = 148.0
FIT_SAMPLES = 5   # samples of the quadratic fits giving the slide's starting velocities
FLAT_DEG = 1.0    # a cube tilted less than this from its nearest face lies flat
MARGIN = 5        # samples after it lies flat for good: the slide's start
# (Below 3° a cube may still rock on its face: the slide starts once it lies within 1°, and a
# few samples later; doc/fitting.md#the-slides-and-the-impacts.)


def level(q):
    """The attitude q turned by its tilt, so that the body axis nearest the vertical is
    vertical (the yaw kept): a cube lying flat on its nearest face."""
    face = rocking.down_face(q)
    axis_down = np.zeros(3)
    axis_down[abs(face) - 1] = math.copysign(1.0, face)
    down = scoring.quat_rotate(q, axis_down)
    target = np.array([0.0, 0.0, -1.0])
    axis = np.cross(down, target)
    s, c = np.linalg.norm(axis), float(down @ target)
    if s < 1e-15:
        return np.asarray(q, float).copy()
    half = 0.5 * math.atan2(s, c)
    turn = np.r_[math.cos(half), axis / s * math.sin(half)]
    out = scoring.quat_mul(turn, q)
    return out / np.linalg.norm(out)


def slide_start(quats):
    """The first sample of the last flat slide (MARGIN after the cube lies flat for good), or
    None when fewer than 10 samples remain after it."""
    k = impacts.settle_index(quats, FLAT_DEG) + MARGIN
    return k if k + 10 <= len(quats) else None


def slide_state(positions, quats, k, half, height):
    """The cube's state at sample k of a flat slide: the level pose on the plane, the horizontal
    velocity and the spin about the vertical from quadratic fits over FIT_SAMPLES samples from
    k (exact for a constant deceleration), evaluated at k."""
    idx = np.arange(k, k + FIT_SAMPLES)
    t = (idx - k) / RATE
    A = np.stack([np.ones_like(t), t, t * t], axis=1)
    coef, *_ = np.linalg.lstsq(A, positions[idx], rcond=None)
    velocity = np.array([coef[1][0], coef[1][1], 0.0])
    rel = scoring.quat_mul(quats[idx], scoring.quat_conj(quats[k]))
    yaw = np.unwrap(2 * np.arctan2(rel[:, 3], rel[:, 0]))   # the turn about the vertical
    spin = np.linalg.lstsq(A, yaw, rcond=None)[0][1]
    q = level(quats[k])
    p = np.array([positions[k][0], positions[k][1], height + half])
    return p, q, velocity, np.array([0.0, 0.0, spin])


def replay(urdf_text, body, runs, params, dt, size, half):
    """Each run simulated from the start of its real last flat slide to its end: per run the
    final position error (fraction of size), rotation error (rad), the real cube's travel from
    there (fraction of size) and the slide's start; None for a run without such a slide."""
    import cga_rigid_sim
    options = model.world_options(params, dt)
    scene = model.scene_of(model.scale_inertia(urdf_text, float(params.get('inertia_scale', 1))))
    height = float(params.get('height', 0.0))
    out = []
    for run in runs:
        k = slide_start(run.quaternion)
        if k is None:
            out.append(None)
            continue
        p, q, v, w = slide_state(run.position, run.quaternion, k, half, height)
        world = cga_rigid_sim.World(scene, **options)
        world.set_body_state(body, p, q, v, w)
        poses, ok = cga_rigid_sim.rollout_worlds([world], [int(x) for x in run.increments[k:]],
                                                 1)
        end = poses[0, -1, 0, :]
        out.append({'run': run.name, 'start': k, 'ok': bool(ok[0]),
                    'position': float(np.linalg.norm(end[:3] - run.position[-1]) / size),
                    'rotation': float(scoring.rotation_angle(run.quaternion[-1], end[3:])),
                    'travel': float(np.linalg.norm(run.position[-1][:2] - p[:2]) / size)})
    return out


def yaw_part(qa, qb):
    """The angle (rad) of the turn about the vertical in R_a R_bᵀ."""
    rel = scoring.quat_mul(qa, scoring.quat_conj(qb))
    return 2 * math.atan2(abs(rel[3]), abs(rel[0]))


def same_face(sims, threshold=40.0):
    """Indices of the simulations ending within `threshold` degrees of the real cube."""
    return [i for i, s in enumerate(sims)
            if s['ok'] and math.degrees(s['rotation_series'][-1]) < threshold]


def growth(runs, sims, samples=(5, 10, 20, 40, 60, 80), threshold=40.0):
    """{'same'|'other': {'runs': n, 'at': [(sample, runs, position, rotation deg)],
    'mean': (position, rotation deg)}} and, for 'same', the final rotation error and its yaw
    part (deg)."""
    same = set(same_face(sims, threshold))
    out = {}
    for name, group in (('same', sorted(same)),
                        ('other', [i for i, s in enumerate(sims) if s['ok'] and i not in same])):
        at = []
        for s in samples:
            ks = [i for i in group if len(sims[i]['rotation_series']) > s]
            if ks:
                at.append((s, len(ks),
                           float(np.mean([sims[i]['position_series'][s] for i in ks])),
                           float(np.degrees(np.mean([sims[i]['rotation_series'][s]
                                                     for i in ks])))))
        g = {'runs': len(group), 'at': at,
             'mean': (float(np.mean([sims[i]['position'] for i in group])) if group else math.nan,
                      float(np.degrees(np.mean([sims[i]['rotation'] for i in group])))
                      if group else math.nan)}
        if name == 'same' and group:
            g['final_deg'] = float(np.degrees(np.mean([sims[i]['rotation_series'][-1]
                                                       for i in group])))
            g['final_yaw_deg'] = float(np.degrees(np.mean([
                yaw_part(runs[i].quaternion[-1], sims[i]['poses'][-1, 3:]) for i in group])))
        out[name] = g
    return out


def entry(runs, sims, indices):
    """Medians over `indices` of: the sample where the cube lies flat for good (within 3° of a
    face), its speed and |spin about the vertical| 2 samples later, and the last sample it
    moves (speed above 0.02 m/s or spin above 0.3 rad/s); measured and simulated."""
    rows = {'data': [], 'sim': []}
    for i in indices:
        for side, p, q in (('data', runs[i].position, runs[i].quaternion),
                           ('sim', sims[i]['poses'][:, :3], sims[i]['poses'][:, 3:])):
            f = impacts.settle_index(q)
            speed = np.linalg.norm(np.diff(p[:, :2], axis=0), axis=1) * RATE
            spin = impacts.turn_vectors(q)[:, 2]
            moving = np.nonzero((speed > 0.02) | (np.abs(spin) > 0.3))[0]
            j = min(f + 2, len(speed) - 1)
            rows[side].append((f, speed[j], abs(spin[j]),
                               int(moving[-1]) + 1 if moving.size else 0))
    return {side: tuple(float(x) for x in np.median(np.array(r), axis=0)) if r else None
            for side, r in rows.items()}


def report(urdf_text, body, runs, sims, params, dt, size, half):
    """Prints growth, entry and replay (the module's docstring)."""
    g = growth(runs, sims)
    for name, label in (('same', 'ending on the real face'), ('other', 'ending on another')):
        x = g[name]
        print('runs %s: %d, %.1f %% and %.1f deg (mean over the run)'
              % (label, x['runs'], 100 * x['mean'][0], x['mean'][1]))
        print('  at sample ' + ', '.join('%d: %.1f %% %.1f deg' % (s, 100 * p, r)
                                         for s, _, p, r in x['at']))
    if g['same']['runs']:
        print('  final rotation error of those ending on the real face: %.1f deg, %.1f deg of '
              'it about the vertical' % (g['same']['final_deg'], g['same']['final_yaw_deg']))
    e = entry(runs, sims, same_face(sims))
    if e['data'] is not None:
        print('lying flat for good (median sample), speed and spin there, last moving sample:')
        for side in ('data', 'sim'):
            print('  %s: flat at %.0f, %.3f m/s, %.2f rad/s, stops at %.0f' % (side, *e[side]))
    rep = [r for r in replay(urdf_text, body, runs, params, dt, size, half) if r and r['ok']]
    if rep:
        pos = np.array([r['position'] for r in rep])
        rot = np.degrees([r['rotation'] for r in rep])
        print('the last flat slide simulated from the real state at its start (%d runs): the end '
              '%.1f %% (median %.1f %%) and %.1f deg (median %.1f) from the real end, after a '
              'real travel of %.1f %% of the size'
              % (len(rep), 100 * pos.mean(), 100 * np.median(pos), rot.mean(), np.median(rot),
                 100 * np.mean([r['travel'] for r in rep])))
    return g, e, rep
