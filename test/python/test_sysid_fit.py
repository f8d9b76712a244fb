"""The fit (doc/fitting.md): the scoring against hand-computed truths, the fit recovering the
parameters of runs the simulator itself made, Dask on a LocalCluster of two workers giving the
in-process numbers, a failed simulation reported without losing the others, the report."""
import copy
import json
import os
import re

import numpy as np
import pytest

import cga_rigid_sim as cs
from cga_rigid_sim.sysid import cli, fit, model, scoring, trajectories
from cga_rigid_sim.sysid.runner import Runner

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, 'data', 'cube_tosses')
URDF = os.path.join(DATA, 'cube.urdf')
SIZE = 0.1048
RADIUS = 0.0524 * np.sqrt(3)
RATE, STEPS = 148.0, 7


def test_rotation_angle_is_the_angle_between_attitudes():
    # Truth: the angle between rotations by a and b about one axis is |a − b|, up to sign.
    axis = np.array([1.0, 2.0, 2.0]) / 3.0

    def q(a):
        return np.concatenate([[np.cos(a / 2)], np.sin(a / 2) * axis])
    assert scoring.rotation_angle(q(0.3), q(1.0)) == pytest.approx(0.7, abs=1e-15)
    assert scoring.rotation_angle(q(0.3), -q(0.3)) == pytest.approx(0.0, abs=1e-15)
    assert scoring.rotation_angle(q(1e-9), q(0.0)) == pytest.approx(1e-9, rel=1e-12)


def test_start_velocity_is_the_parabola_through_free_flight():
    # Truth: samples of x0 + v0 t + ½ g t² and a constant spin give back v at the start sample
    # and ω exactly (least squares on exact data: round-off, 1e-9).
    t = np.arange(40) / RATE
    v0 = np.array([0.8, -0.3, -0.5])
    g = np.array([0, 0, -9.81])
    p = np.array([0, 0, 0.3]) + np.outer(t, v0) + 0.5 * np.outer(t ** 2, g)
    w = np.array([2.0, -1.0, 4.0])
    ang = np.linalg.norm(w) * t
    q = np.concatenate([np.cos(ang / 2)[:, None],
                        np.sin(ang / 2)[:, None] * (w / np.linalg.norm(w))], axis=1)
    tr = trajectories.Trajectory('synthetic', t, p, q)
    st = scoring.find_start(tr, RADIUS)
    first = int(np.nonzero(p[:, 2] < RADIUS)[0][0])
    assert st.index == first - 3
    assert np.allclose(st.velocity, v0 + g * t[st.index], atol=1e-9)
    assert np.allclose(st.omega_world, w, atol=1e-9)


def synthetic_runs(params, n=4):
    """Runs 'measured' by the simulator itself under params, from the starts of real tosses."""
    urdf = open(URDF).read()
    trajs = trajectories.read_directory(DATA)[:n]
    runs = model.prepare_runs(trajs, RATE * STEPS, RADIUS, horizon=0.5)
    res = model.simulate_runs(urdf, 'body', runs, params, 1 / (RATE * STEPS), SIZE,
                              keep_poses=True)
    out = []
    for run, r in zip(runs, res):
        assert r['ok']
        run = copy.deepcopy(run)
        run.position = r['poses'][:, :3].copy()
        run.quaternion = r['poses'][:, 3:].copy()
        out.append(run)
    return urdf, out


def test_the_fit_recovers_the_parameters_of_simulated_runs():
    # Truth: runs made by the simulator under μ = 0.3, height −1 mm are fitted by those values:
    # the objective is 0 there. Near it the objective is rough on the scale of a step's travel
    # (0.05 mm of height moves a landing by a step and the errors by 0.1 % of the size, J by
    # 0.03), so the search ends in a hollow beside the truth, not on it: measured μ 0.3009,
    # height −1.098 mm. Tolerances: μ within 0.005, the height within 0.15 mm, and the fitted
    # runs within 0.5 % of the size and 1° of the 'measured' ones.
    truth = {'mu': 0.3, 'restitution': 0.1, 'height': -0.001}
    urdf, runs = synthetic_runs(truth)
    with Runner(urdf, 'body', runs, 1 / (RATE * STEPS), SIZE, use_dask=False) as r:
        problem = fit.Problem({'mu': (0.1, 0.5), 'height': (-0.003, 0.001)},
                              fixed={'restitution': 0.1})
        res = fit.fit(r, range(len(runs)), problem, initial=8, max_evaluations=120,
                      tolerance=1 / 256)
    assert abs(res['params']['mu'] - 0.3) <= 0.005, res['params']
    assert abs(res['params']['height'] + 0.001) <= 0.00015, res['params']
    assert res['train']['position'] < 0.005 and res['train']['rotation_deg'] < 1.0


def test_a_start_at_the_truth_ends_the_search_there():
    # Truth: at the parameters that made the runs the objective is 0, its minimum; a search
    # that also starts there (--start, e.g. measured values) keeps it: the same values to
    # round-off (the start passes through the search's scaled coordinates and back, 1e-16) and
    # errors of 0 to round-off (1e-12). A start outside the ranges or missing a free parameter is refused
    # by name.
    truth = {'mu': 0.3, 'restitution': 0.1, 'height': -0.001}
    urdf, runs = synthetic_runs(truth, n=2)
    problem = fit.Problem({'mu': (0.1, 0.5), 'height': (-0.003, 0.001)},
                          fixed={'restitution': 0.1})
    assert problem.params(problem.scaled(truth)) == pytest.approx(truth, abs=1e-15)
    with Runner(urdf, 'body', runs, 1 / (RATE * STEPS), SIZE, use_dask=False) as r:
        res = fit.fit(r, range(len(runs)), problem, initial=2, max_evaluations=12,
                      starts=[{'mu': 0.3, 'height': -0.001}])
    assert res['train']['objective'] < 1e-12
    assert res['params'] == pytest.approx(truth, abs=1e-15)
    with pytest.raises(ValueError, match='mu=0.6 is outside its range 0.1:0.5'):
        problem.scaled({'mu': 0.6, 'height': 0.0})
    with pytest.raises(ValueError, match='height is not given'):
        problem.scaled({'mu': 0.3})


def test_dask_on_two_workers_gives_the_in_process_numbers():
    # Truth: each simulation is deterministic and the results are put back in order, so a
    # LocalCluster of two workers returns exactly the in-process numbers, including a run that
    # fails (a starting speed the core refuses), reported with its parameters while the others
    # keep their results.
    urdf = open(URDF).read()
    runs = model.prepare_runs(trajectories.read_directory(DATA)[:5], RATE * STEPS, RADIUS,
                              horizon=0.4)
    runs[2].start.velocity = np.array([2e9, 0.0, 0.0])  # refused: faster than 1e9 m/s
    points = [{'mu': 0.2, 'restitution': 0.1}, {'mu': 0.4, 'restitution': 0.0}]
    with Runner(urdf, 'body', runs, 1 / (RATE * STEPS), SIZE, use_dask=False) as r:
        local = r.evaluate(points, range(5))
    with Runner(urdf, 'body', runs, 1 / (RATE * STEPS), SIZE, workers=2, chunk=2) as r:
        assert r.description == 'Dask LocalCluster, 2 workers'
        remote = r.evaluate(points, range(5))
    for a, b in zip(local, remote):
        for x, y in zip(a, b):
            assert x['run'] == y['run'] and x['ok'] == y['ok']
            if x['ok']:
                assert x['position'] == y['position'] and x['rotation'] == y['rotation']
    failed = [x for x in remote[0] if not x['ok']]
    assert [x['run'] for x in failed] == ['002']
    assert failed[0]['error'].startswith('set_body_state.linear_velocity: ')
    assert sum(x['ok'] for x in remote[0]) == 4
    agg = fit.aggregate(remote[0])
    assert len(agg['failed']) == 1


def test_cross_validation_report_is_deterministic(tmp_path):
    # The same data and options give the same fitted values and errors, in-process or on a
    # LocalCluster of two workers; the report holds the table, the JSON and the plots.
    args = ['cv', DATA, '--urdf', URDF, '--model', 'plain:mu=0.1:0.5,restitution=0.1',
            '--folds', '2', '--initial', '4', '--max-evaluations', '8', '--horizon', '0.4']
    assert cli.main(args + ['--no-dask', '--out', str(tmp_path / 'a')]) == 0
    assert cli.main(args + ['--workers', '2', '--out', str(tmp_path / 'b'),
                            '--sensitivity']) == 0
    a = json.load(open(tmp_path / 'a' / 'results.json'))['summary']
    b = json.load(open(tmp_path / 'b' / 'results.json'))['summary']
    for fa, fb in zip(a['folds'], b['folds']):
        assert fa['params'] == fb['params']
        assert fa['test'] == fb['test']
    assert [f['test_runs'] for f in a['folds']] == ['000–003', '004–007']
    report = open(tmp_path / 'b' / 'report.md').read()
    assert '| plain | 0 | 004–007 | 000–003 |' in report
    for png in ('errors_per_run.png', 'error_vs_time.png', 'sensitivity.png'):
        assert os.path.getsize(tmp_path / 'b' / png) > 1000


def test_one_fold_is_reported_in_sample_not_held_out(tmp_path):
    # --folds 1 fits on every run and tests on the same runs: the report says so, and its
    # errors are the training errors (the same runs, the same parameters).
    args = ['cv', DATA, '--urdf', URDF, '--model', 'plain:mu=0.1:0.5,restitution=0.1',
            '--folds', '1', '--initial', '4', '--max-evaluations', '8', '--horizon', '0.4',
            '--no-dask', '--out', str(tmp_path)]
    assert cli.main(args) == 0
    summary = json.load(open(tmp_path / 'results.json'))['summary']
    fold = summary['folds'][0]
    assert fold['train_runs'] == fold['test_runs'] == '000–007'
    assert fold['test']['position_mean'] == pytest.approx(fold['train']['position'], rel=1e-12)
    report = open(tmp_path / 'report.md').read()
    assert 'in sample, not held out' in report
    assert 'held-out runs of every fold' not in report


def test_inertia_scale_multiplies_every_moment_and_the_turn_an_impulse_gives():
    # Truth: scale_inertia multiplies ixx … izz of every <inertia> by s and touches nothing else
    # (the mass stays); an impulse J off the centre by p then turns the body by p × J / (s I):
    # the cube's I = 0.00081 kg m², s = 1.25 (to round-off, 1e-12 rad/s).
    urdf = open(URDF).read()
    scaled = model.scale_inertia(urdf, 1.25)
    assert model.scale_inertia(urdf, 1.0) == urdf
    moments = dict(re.findall(r'\b(i[xyz]{2})="([^"]*)"', scaled))
    assert {k: float(v) for k, v in moments.items()} == pytest.approx(
        {'ixx': 1.25 * 0.00081, 'iyy': 1.25 * 0.00081, 'izz': 1.25 * 0.00081, 'ixy': 0.0,
         'ixz': 0.0, 'iyz': 0.0}, rel=1e-15)
    assert '<mass value="0.37" />' in scaled
    w = cs.world_from_urdf(scaled, gravity=[0, 0, 0])
    w.apply_impulse('body', [0.0, 0.0, 0.01], point=[0.05, 0.0, 0.0])
    w.step()
    v = w.velocities()[0]
    assert np.allclose(v[:3], [0, 0, 0.01 / 0.37], atol=1e-12)
    assert np.allclose(v[3:], np.cross([0.05, 0, 0], [0, 0, 0.01]) / (1.25 * 0.00081),
                       atol=1e-12)
    with pytest.raises(model.ParameterError, match='inertia_scale'):
        model.world_options({'inertia_scale': 0.0}, 1e-3)


def test_impacts_reads_the_simulated_friction_in_impacts_back(tmp_path):
    # Truth: a landing corner that slides through its impact takes |P_t| = μ_i P_n, so `fit
    # impacts` measuring the simulated first impacts on one corner reads back the model's
    # friction in impacts, μ k_i (0.12 · 0.75; off, 0.12). The interval it measures after the
    # impact holds ~7 ms more of the same sliding contact: to 1e-3 (the median; a second corner
    # touching within it would move one run's). An edge's two corners slide in different
    # directions, their friction partly cancelling: left out.
    from cga_rigid_sim.sysid import impacts
    for ratio in (0.75, 1.0):
        out = tmp_path / ('%g.json' % ratio)
        assert impacts.main([DATA, '--json', str(out), '--sim', 'mu=0.12,restitution=0.3,'
                             'height=-0.0012,impact_friction_ratio=%g' % ratio]) == 0
        rows = json.load(open(out))
        sliding = [r['sim'] for r in rows if r.get('sim') and r['sim']['kind'] == 'corner'
                   and r['sim']['ut_post'] > 0.05]
        assert len(sliding) >= 3
        assert np.median([r['Pt'] / r['Pn'] for r in sliding]) == pytest.approx(0.12 * ratio,
                                                                                 abs=1e-3)


def rocking_turn(e, mu, scale, impact_ratio=1.0, tilt=np.radians(8), omega=-3.0):
    """A cube pivoting on one bottom edge falls onto the next: ω about the edges' axis in the
    last step before that edge lands and in the first after."""
    a = SIZE / 2
    w = cs.world_from_urdf(model.scale_inertia(open(URDF).read(), scale), dt=1 / (RATE * STEPS),
                           contact_mu=mu, contact_restitution=e,
                           ground_plane={'height': 0.0, 'mu': mu, 'restitution': e},
                           contact_model={'impact_friction_ratio': impact_ratio})
    c, s = np.cos(tilt), np.sin(tilt)
    pivot = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]) @ np.array([a, 0, -a])
    centre = -pivot + [0, 0, 1e-9]                 # the pivot edge on the plane
    w_vec = np.array([0.0, omega, 0.0])            # turning the other edge down
    w.set_body_state('body', centre, [np.cos(tilt / 2), 0, np.sin(tilt / 2), 0],
                     np.cross(w_vec, centre - (centre + pivot)), w_vec)
    om = []
    for _ in range(400):
        w.step()
        om.append(w.velocities()[0][4])
    k = int(np.argmax(np.abs(np.diff(om))))
    return om[k], om[k + 1]


def test_a_rocking_cube_keeps_housners_turn():
    # Truth (Housner's rocking block): a cube of half-width a turning at ω⁻ about one bottom
    # edge lands flat on the next; held from slipping, that edge stops its approach with the
    # impulse that turns the cube about it, and e more (Newton's law at one contact, Poisson's
    # the same there): ω⁺/ω⁻ = (I − 2 e m a²)/(I + 2 m a²), I about the centre. The cube with
    # the measured inertia (1.26 × the URDF's: the pivot lifts off, the landing edge is the
    # only contact): 0.334 at e = 0, 0.135 at e = 0.3. Tolerance 0.003: ω⁻ is read one step
    # before the landing (its tilt, ω h = 5 mrad, moves the levers by that fraction).
    m, a, I = 0.37, SIZE / 2, 1.26 * 0.00081
    for e in (0.0, 0.3):
        before, after = rocking_turn(e, 1.0, 1.26)
        assert after / before == pytest.approx((I - 2 * e * m * a * a) / (I + 2 * m * a * a),
                                               abs=3e-3)
    # Sliding instead (μ 0.21 with the impact ratio 0.78: the edge would need |P_t|/P_n ≈ 0.5
    # to hold), the landing edge slips and Newton's bounce sends the cube back (ω⁺ against ω⁻),
    # which the measured cubes do not do (doc/fitting.md#the-first-impact-measured).
    before, after = rocking_turn(0.3, 0.21, 1.26, 0.78)
    assert after / before < 0
