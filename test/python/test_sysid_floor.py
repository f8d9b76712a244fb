"""`fit impacts --floor` (sysid/floor.py, doc/fitting.md#the-floor-of-one-deterministic-model):
the tracking's noise read from free flight, and the simulations with redrawn impacts that the
nominal simulation is scored against."""
import math
import os

import numpy as np
import pytest

from cga_rigid_sim.sysid import floor, impacts, model, scoring, trajectories

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, 'data', 'cube_tosses')
URDF = open(os.path.join(DATA, 'cube.urdf')).read()
SIZE, RATE, STEPS = 0.1048, 148.0, 7
DT = 1.0 / (RATE * STEPS)
RADIUS = SIZE / 2 * math.sqrt(3)
PARAMS = {'mu': 0.21, 'restitution': 0.2, 'height': -0.0012, 'box_edge_radius': 0.005,
          'impact_friction_ratio': 0.78, 'inertia_scale': 1.3}


def exp(v):
    """Unit quaternions of rotation vectors (n, 3)."""
    th = np.linalg.norm(v, axis=1)
    s = np.where(th > 0, np.sin(th / 2) / np.where(th > 0, th, 1.0), 0.5)
    return np.c_[np.cos(th / 2), v * s[:, None]]


def flight(sigma_p, sigma_r, rng, samples=40):
    """A cube thrown from 0.4 m: a parabola under gravity and a constant spin (equal moments)
    sampled at 148 Hz, with white noise of deviation sigma_p (m) on each position axis and
    sigma_r (rad) about each attitude axis, until it is 5 cm from z = 0."""
    t = np.arange(samples) / RATE
    p = np.array([0.0, 0.0, 0.4]) + np.outer(t, [0.8, -0.3, -0.5]) \
        + 0.5 * np.outer(t * t, [0.0, 0.0, -9.81])
    w = np.array([4.0, -6.0, 2.5])
    q = scoring.quat_mul(exp(np.outer(t, w)), np.tile([1.0, 0, 0, 0], (samples, 1)))
    p = p + sigma_p * rng.normal(size=p.shape)
    q = scoring.quat_mul(exp(sigma_r * rng.normal(size=(samples, 3))), q)
    keep = p[:, 2] > 0.05
    return trajectories.Trajectory('flight', t[keep], p[keep], q[keep])


def test_tracking_noise_reads_the_noise_put_on_a_free_flight():
    # Truth: the deviations the noise was drawn with. Each flight's estimate comes from ~28
    # second differences per axis, correlated (their lag-1 correlation is -2/3): about 11 %
    # deviation on σ, and the median of 40 flights about 2 % (fixed seed); 8 % is 4 of those.
    rng = np.random.default_rng(0)
    flights = [flight(2e-5, 3e-4, rng) for _ in range(40)]
    sp, sr, n = floor.tracking_noise(flights, RADIUS)
    assert n == 40
    assert sp == pytest.approx(2e-5, rel=0.08)
    assert sr == pytest.approx(3e-4, rel=0.08)
    # Without noise the parabola and the spin leave round-off only.
    sp, sr, _ = floor.tracking_noise([flight(0.0, 0.0, rng)], RADIUS)
    assert sp < 1e-12 and sr < 1e-12


def runs_of_the_test_data():
    trajs = trajectories.read_directory(DATA, RATE)
    return model.prepare_runs(trajs, RATE * STEPS, RADIUS, 0.0, horizon=1.0)


def test_one_draw_at_the_start_is_the_simulation_with_the_drawn_values():
    # A second method: drawn once at the start and never again (every beyond the run), the
    # rollout is the fit's batch simulation under the values drawn with the same seed; both
    # step the same World the same number of steps, so they agree to round-off.
    runs = runs_of_the_test_data()[:3]
    scatter = {'impact_friction_ratio': 0.16, 'restitution': 0.04, 'mu': 0.1}
    scene = model.scene_of(model.scale_inertia(URDF, PARAMS['inertia_scale']))
    for k, run in enumerate(runs):
        drawn = floor.draw(PARAMS, scatter, np.random.default_rng(k))
        assert drawn['mu'] != PARAMS['mu']
        poses = floor.rollout_redrawn(scene, 'body', run, PARAMS, scatter, 10 ** 6,
                                      np.random.default_rng(k), DT)
        ref = model.simulate_runs(URDF, 'body', [run], drawn, DT, SIZE, keep_poses=True)[0]
        assert poses.shape == ref['poses'].shape
        assert np.abs(poses - ref['poses']).max() < 1e-12


def test_redrawing_without_scatter_keeps_the_motion():
    # With every deviation 0 a redraw only makes a new World and carries the pose and the
    # velocities over (every 3 samples for 0.4 s): what it loses is the contact solver's warm
    # start, whose effect is below the solver's tolerance. Scored against the nominal
    # simulation the eight tosses stay within 0.5 % of the width and 0.5° (measured on the
    # 100 tosses: 0.0 % and 0.1°); a pose or a velocity carried over wrongly (body axes for
    # world, a root for a centre) moves them by tens of per cent and degrees.
    runs = runs_of_the_test_data()
    f = floor.floor(URDF, 'body', runs, PARAMS, {'impact_friction_ratio': 0.0}, 1, 3, DT, SIZE)
    assert f['runs'] == 8
    assert f['position'] < 0.005
    assert math.degrees(f['rotation']) < 0.5
    assert f['other_faces_per_draw'] == 0


def test_scattered_impacts_move_the_draws_away_from_the_nominal():
    # The floor is not zero when the impacts scatter: k_i drawn with 16 % deviation every 3
    # samples moves the draws of the eight tosses by more than 1 % of the width (measured: 7.6 %
    # and 9.3°); a scatter that was not applied would leave them at 0.
    runs = runs_of_the_test_data()
    f = floor.floor(URDF, 'body', runs, PARAMS, {'impact_friction_ratio': 0.16}, 2, 3, DT, SIZE)
    assert f['position'] > 0.01
    assert f['data_position'] == pytest.approx(
        np.mean([r['position'] for r in model.simulate_runs(URDF, 'body', runs, PARAMS, DT,
                                                            SIZE)]), rel=1e-12)


def test_data_that_is_the_nominal_simulation_falls_below_every_draw():
    # Where the data falls among the draws, checked at its two ends. Runs whose data is the
    # nominal simulation itself are nearer it than any draw (error 0): rank 0. Runs whose data
    # is a simulation with μ three times the nominal's (slides a third as long) are further from
    # it than every draw of a 16 % k_i scatter: rank 1 in position.
    runs = runs_of_the_test_data()
    nominal = model.simulate_runs(URDF, 'body', runs, PARAMS, DT, SIZE, keep_poses=True)
    as_data = [model.Run(r.name, r.start, r.increments, n['poses'][:, :3], n['poses'][:, 3:])
               for r, n in zip(runs, nominal)]
    f = floor.floor(URDF, 'body', as_data, PARAMS, {'impact_friction_ratio': 0.16}, 2, 3, DT,
                    SIZE)
    assert f['data_position'] < 1e-12
    assert f['rank_position'] == 0 and f['rank_rotation'] == 0
    far = model.simulate_runs(URDF, 'body', runs, dict(PARAMS, mu=0.63), DT, SIZE,
                              keep_poses=True)
    as_data = [model.Run(r.name, r.start, r.increments, n['poses'][:, :3], n['poses'][:, 3:])
               for r, n in zip(runs, far)]
    f = floor.floor(URDF, 'body', as_data, PARAMS, {'impact_friction_ratio': 0.16}, 2, 3, DT,
                    SIZE)
    assert f['rank_position'] == 1


def test_a_negative_deviation_is_refused_with_its_name():
    with pytest.raises(model.ParameterError, match='restitution: its standard deviation'):
        floor.floor(URDF, 'body', [], PARAMS, {'restitution': -0.1}, 1, 3, DT, SIZE)
    with pytest.raises(model.ParameterError, match='height: not a scattered parameter'):
        floor.floor(URDF, 'body', [], PARAMS, {'height': 0.001}, 1, 3, DT, SIZE)


@pytest.mark.parametrize('args, message', [
    (['--floor', '0.16,0.04,0.1,4'], '--floor needs --sim'),
    (['--sim', 'mu=0.2', '--floor', '0.16,0.04,4'], 'expected KI,E,MU,N'),
    (['--sim', 'mu=0.2', '--floor', '0.16,0.04,0.1,2.5'], 'expected KI,E,MU,N'),
    (['--sim', 'mu=0.2', '--floor-spin', '2,2,0.4'], '--floor-spin needs --floor'),
    (['--sim', 'mu=0.2', '--floor', '0,0,0,1', '--floor-spin', '2,2'], 'expected LEVER,ACROSS'),
])
def test_fit_impacts_floor_refuses_what_it_cannot_use(capsys, args, message):
    with pytest.raises(SystemExit) as e:
        impacts.main([DATA] + args)
    assert e.value.code == 2
    assert message in capsys.readouterr().err


def test_a_vanishing_spin_kick_steps_the_same_run():
    # With a spin scatter of 1e-300 rad/s the rollout steps one step at a time until the first
    # contact and sets the state there again: it is the batch simulation still, to round-off
    # (measured 1.3e-13 on four tosses; a second after a kick set wrongly it is centimetres).
    runs = runs_of_the_test_data()[:4]
    scene = model.scene_of(model.scale_inertia(URDF, PARAMS['inertia_scale']))
    for run in runs:
        ref = model.simulate_runs(URDF, 'body', [run], PARAMS, DT, SIZE, keep_poses=True)[0]
        poses = floor.rollout_redrawn(scene, 'body', run, PARAMS, {}, 10 ** 6,
                                      np.random.default_rng(0), DT, spin=(1e-300, 0.0, 0.0))
        assert np.abs(poses - ref['poses']).max() < 1e-11


def corner_landing():
    """A World of the cube falling onto one corner, stepped to the first step with a
    contact."""
    import cga_rigid_sim as cs
    scene = model.scene_of(model.scale_inertia(URDF, PARAMS['inertia_scale']))
    w = cs.World(scene, **model.world_options(PARAMS, DT))
    tilt = np.array([1.0, 1.0, 0.0]) / math.sqrt(2) * math.radians(35)  # a corner lowest
    w.set_body_state('body', [0, 0, 0.12], exp(tilt[None])[0], [0.5, 0.2, -1.5],
                     [2.0, -3.0, 1.0])
    for _ in range(2000):
        w.step(1)
        if len(w.contacts()['normal_impulse']):
            return w
    raise AssertionError('no contact')


def test_a_spin_kick_adds_the_drawn_departure_in_the_landing_frame():
    # Truth: the normal deviates the same seed gives, times the deviations, along the landing
    # frame computed here from the contact point and the centre: the horizontal lever from the
    # centre to the corner, the horizontal across it, the vertical. The world holds the spin
    # plus the kick, to round-off.
    w = corner_landing()
    before = w.velocities()[0].copy()
    point, centre = w.contacts()['point'][0], w.com()[0]
    kick = floor.kick_spin(w, 'body', (2.0, 1.0, 0.5), np.random.default_rng(7))
    z = np.random.default_rng(7).normal(size=3)
    h = (point - centre) * [1, 1, 0]
    h1 = h / np.linalg.norm(h)
    h2 = np.cross([0, 0, 1], h1)
    assert np.linalg.norm(h) > 0.02  # a corner out to the side
    expected = 2.0 * z[0] * h1 + 1.0 * z[1] * h2 + 0.5 * z[2] * np.array([0, 0, 1])
    assert kick == pytest.approx(expected, abs=1e-12)
    assert w.velocities()[0][3:] == pytest.approx(before[3:] + expected, abs=1e-12)
    assert w.velocities()[0][:3] == pytest.approx(before[:3], abs=1e-12)


def test_spin_scatter_reads_the_deviations_it_was_made_with():
    # Rows whose measured change of spin is the model's law (0.6 of a point impulse's) plus a
    # departure of deviations 2.5, 1.5 and 0.4 rad/s in the landing frame (normal quantiles,
    # shuffled per axis), and simulated rows that follow the law exactly: the robust deviations
    # give them back to the quantiles' resolution (2 %). Levers point every way round.
    from scipy.stats import norm
    n = 201
    z = norm.ppf((np.arange(n) + 0.5) / n)
    rng = np.random.default_rng(1)
    cols = [rng.permutation(z) * sd for sd in (2.5, 1.5, 0.4)]
    rows = []
    for k in range(n):
        a = 2 * math.pi * k / n
        r = np.array([0.04 * math.cos(a), 0.04 * math.sin(a), -0.03])
        point = np.cross(r, [0.05, 0.0, 0.5]) / 0.001
        frame = floor.landing_frame(r)
        dev = frame.T @ np.array([c[k] for c in cols])
        sim = {'dw_point': point, 'dw': 0.6 * point, 'r': r}
        data = {'dw_point': point, 'dw': 0.6 * point + dev, 'r': r}
        rows.append({'data': data, 'sim': sim})
    got = floor.spin_scatter(rows)
    assert got == pytest.approx((2.5, 1.5, 0.4), rel=0.02)
    d, s_ = floor.departure(rows[3])
    assert s_ == pytest.approx([0, 0, 0], abs=1e-9)
    assert d == pytest.approx([c[3] for c in cols], abs=1e-9)
