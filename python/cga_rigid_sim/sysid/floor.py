"""The floor of one deterministic model on scattering impacts (`fit impacts --floor`,
doc/fitting.md#the-floor-of-one-deterministic-model).

Real impacts scatter from toss to toss and from impact to impact: the first impacts' friction
ratio by about 16 % about its median, and no state before them predicts it. A simulation with
one set of parameters cannot follow that scatter; how much error it leaves is measured here by
making the model itself the world: each run is simulated again with the parameters of its
impacts drawn afresh every `every` samples over its first `span` samples (the impacts; then
the cube slides), and the nominal simulation is scored against each draw as if the draw were
the data. What it scores is the error the nominal values would have on a world that is the
model with impacts that scatter so: the part of the error on real data that no single set of
values can remove.

The first impact also leaves a spin that departs from the model's by more than its parameters
can make (`departure`: the measured change of spin against the model's law applied to the
measured impulse, in the landing's frame); `kick_spin` adds such a departure to the model's
first impact, with the deviations `spin_scatter` measures.

The tracking's own noise (`tracking_noise`) says whether the measured scatter is the tracking's:
in free flight a parabola under gravity and a constant spin (a cube's equal moments) leave
second differences that are the noise alone.
"""
import math

import numpy as np

from . import model, scoring

# name: whether its standard deviation is relative to the value (True) or absolute (False).
SCATTERED = {'impact_friction_ratio': True, 'restitution': False, 'mu': True}
SPAN = 60  # samples (0.4 s at 148 Hz): the impacts of a toss, before it slides flat


def draw(params, scatter, rng):
    """`params` with each scattered parameter drawn about its value (normal; a relative
    standard deviation for k_i and μ, absolute for e), kept inside its physical range."""
    out = dict(params)
    for name, sd in scatter.items():
        if sd == 0:
            continue
        value = float(params.get(name, model.PARAMETERS[name][2]))
        value = value * (1 + sd * rng.normal()) if SCATTERED[name] else value + sd * rng.normal()
        lo, hi = model.PARAMETERS[name][:2]
        if name in model.OPEN_BELOW:  # k_i > 0: a draw 6 deviations out keeps a little
            lo = 1e-3 * float(params.get(name, model.PARAMETERS[name][2]))
        out[name] = min(hi, max(lo, value))
    return out


def landing_frame(lever):
    """The landing's frame (rows): the horizontal direction of the lever from the centre of
    mass to the landing point, the horizontal direction across it, and the vertical."""
    n = np.array([0.0, 0.0, 1.0])
    h = np.array([lever[0], lever[1], 0.0])
    h1 = h / np.linalg.norm(h) if np.linalg.norm(h) > 0 else np.array([1.0, 0.0, 0.0])
    return np.array([h1, np.cross(n, h1), n])


def kick_spin(world, body, spin, rng):
    """After the step of a run's first impact: adds to the body's spin a departure drawn
    normal with deviations `spin` (rad/s) about the landing frame's three axes (the first
    contact's point against the centre of mass; `landing_frame`). A couple, which the model's
    impact law cannot make. Returns the spin added."""
    lever = world.contacts()['point'][0] - world.com()[0]
    kick = landing_frame(lever).T @ (np.asarray(spin, float) * rng.normal(size=3))
    pose, vel = world.poses()[0], world.velocities()[0]
    world.set_body_state(body, pose[:3], pose[3:], vel[:3], vel[3:] + kick)
    return kick


def rollout_redrawn(scene, body, run, params, scatter, every, rng, dt, span=SPAN,
                    spin=(0.0, 0.0, 0.0)):
    """The poses (samples, 7) of `run` simulated from its start, its parameters drawn afresh
    (`draw`) every `every` samples while fewer than `span` have passed: each draw makes a new
    World of `scene` and carries the body's pose and velocities over. With `spin` (three
    deviations, rad/s) the spin the first impact leaves is scattered too (`kick_spin`): the
    steps are taken one by one until the first with a contact."""
    import cga_rigid_sim

    def world(pose, vel):
        w = cga_rigid_sim.World(scene, **model.world_options(draw(params, scatter, rng), dt))
        w.set_body_state(body, pose[:3], pose[3:], vel[:3], vel[3:])
        return w
    st = run.start
    w = world(np.r_[st.position, st.quaternion], np.r_[st.velocity, st.omega_world])
    out = [w.poses()[0].copy()]
    kick = any(spin)
    for j, n in enumerate(run.increments):
        if 0 < j < span and j % every == 0:
            w = world(w.poses()[0], w.velocities()[0])
        if kick:
            for _ in range(int(n)):
                w.step(1)
                if kick and len(w.contacts()['normal_impulse']):
                    kick_spin(w, body, spin, rng)
                    kick = False
        else:
            w.step(int(n))
        out.append(w.poses()[0].copy())
    return np.array(out)


def floor(urdf_text, body, runs, params, scatter, draws, every, dt, size, seed=0, span=SPAN,
          spin=(0.0, 0.0, 0.0)):
    """The nominal simulation of every run scored against `draws` simulations of it with
    scattered impacts (`rollout_redrawn`, seed `seed`, `spin` for the first impact's): the
    mean position error (fraction of size), the mean rotation error (rad), the number of other
    final faces (final attitudes more than 40° apart) per draw over all runs, the nominal's own
    errors against the data, and where the data falls among the draws: per run the share of
    draws nearer the nominal than the data is, averaged over the runs (rank_position,
    rank_rotation). If the world is the model with this scatter the data is a typical draw and
    both are near 0.5; below, the scatter is too large, above, too small or the model wrong."""
    for name in scatter:
        if name not in SCATTERED:
            raise model.ParameterError('%s: not a scattered parameter (%s)'
                                       % (name, ', '.join(SCATTERED)))
        if not math.isfinite(scatter[name]) or scatter[name] < 0:
            raise model.ParameterError('%s: its standard deviation must be finite and >= 0 '
                                       '(got %r)' % (name, scatter[name]))
    if len(spin) != 3 or not all(math.isfinite(x) and x >= 0 for x in spin):
        raise model.ParameterError('spin: three deviations, finite and >= 0 (got %r)' % (spin,))
    if draws < 1 or every < 1:
        raise model.ParameterError('draws and every must be at least 1 (got %d, %d)'
                                   % (draws, every))
    nominal = model.simulate_runs(urdf_text, body, runs, params, dt, size, keep_poses=True)
    scene = model.scene_of(model.scale_inertia(urdf_text, float(params.get('inertia_scale', 1))))
    rng = np.random.default_rng(seed)
    pos, rot, faces, rank_pos, rank_rot = [], [], 0, [], []
    for run, nom in zip(runs, nominal):
        if not nom['ok']:
            continue
        mine = []
        for _ in range(draws):
            other = rollout_redrawn(scene, body, run, params, scatter, every, rng, dt, span,
                                    spin)
            if not np.all(np.isfinite(other)):
                continue
            mine.append(scoring.pose_errors(nom['poses'], other, size))
            faces += math.degrees(scoring.rotation_angle(nom['poses'][-1:, 3:],
                                                         other[-1:, 3:])[0]) > 40
        if mine:
            mine = np.array(mine)
            pos += list(mine[:, 0])
            rot += list(mine[:, 1])
            rank_pos.append(np.mean(mine[:, 0] < nom['position']))
            rank_rot.append(np.mean(mine[:, 1] < nom['rotation']))
    ok = [r for r in nominal if r['ok']]
    return {'position': float(np.mean(pos)), 'rotation': float(np.mean(rot)),
            'other_faces_per_draw': faces / draws, 'runs': len(ok),
            'data_position': float(np.mean([r['position'] for r in ok])),
            'data_rotation': float(np.mean([r['rotation'] for r in ok])),
            'rank_position': float(np.mean(rank_pos)), 'rank_rotation': float(np.mean(rank_rot))}


def departure(row):
    """How the measured first impact's change of spin departs from the model's (a row of `fit
    impacts` with 'data' and 'sim', the same run): the data's Δω less the model's law applied
    to the data's impulse (the simulation's own ratio of Δω to a point impulse at the landing
    point, times the data's point impulse), and the same on the simulation (the measure's own
    error), each in the landing frame (rad/s). None without a simulated row."""
    if row.get('sim') is None:
        return None
    sim = row['sim']
    dwp = np.asarray(sim['dw_point'])
    ratio = np.asarray(sim['dw']) @ dwp / (dwp @ dwp)
    out = []
    for m in (row['data'], sim):
        res = np.asarray(m['dw']) - ratio * np.asarray(m['dw_point'])
        out.append(landing_frame(m['r']) @ res)
    return out[0], out[1]


def spin_scatter(rows):
    """The deviations `kick_spin` draws with, from rows of `fit impacts` (`departure`): per
    axis of the landing frame, the robust deviation (quartiles) of the data's departure less
    the simulation's in quadrature. None with fewer than 4 simulated rows."""
    d = [x for x in (departure(row) for row in rows) if x is not None]
    if len(d) < 4:
        return None
    data, sim = np.array([x[0] for x in d]), np.array([x[1] for x in d])

    def robust(x):
        q1, q3 = np.percentile(x, [25, 75], axis=0)
        return (q3 - q1) / 1.349
    return tuple(float(v) for v in np.sqrt(np.maximum(robust(data) ** 2 - robust(sim) ** 2, 0)))


def departure_targets():
    """The data's departure about the three axes of the landing frame, as targets of
    `rocking.predictability`."""
    def part(j):
        def value(row):
            d = departure(row)
            return None if d is None else float(d[0][j])
        return value
    return [("the spin's departure about the lever", part(0)),
            ("the spin's departure across it", part(1)),
            ("the spin's departure about the vertical", part(2))]


def tracking_noise(trajs, radius, gravity=(0.0, 0.0, -9.81)):
    """The tracking's noise (standard deviation per axis: m, rad) from each trajectory's free
    flight (the samples before its centre first comes within `radius` of z = 0; a uniform
    rate): white noise of deviation σ on samples gives second differences of deviation √6 σ,
    and a parabola under gravity and a constant spin have none of their own. Median over the
    trajectories with at least 8 such samples."""
    sp, sr = [], []
    g = np.asarray(gravity, float)
    for traj in trajs:
        below = np.nonzero(traj.position[:, 2] < radius)[0]
        k = int(below[0]) if len(below) else len(traj)
        if k < 8:
            continue
        dt = traj.t[1] - traj.t[0]
        p, q = traj.position[:k], traj.quaternion[:k]
        a = p[2:] - 2 * p[1:-1] + p[:-2] - g * dt * dt
        sp.append(math.sqrt(np.mean(a ** 2) / 6))
        turn = scoring.turn_vectors(q)
        d2 = turn[1:] - turn[:-1]
        sr.append(math.sqrt(np.mean(d2 ** 2) / 6))
    if not sp:
        return math.nan, math.nan, 0
    return float(np.median(sp)), float(np.median(sr)), len(sp)
