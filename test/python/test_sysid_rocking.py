"""`fit impacts --rocking` (sysid/rocking.py, doc/fitting.md#the-rocking-impacts-measured):
the rocking impact's measure read on a simulated rocking cube against the simulator's own
velocities, gripping and slipping."""
import os

import numpy as np
import pytest

import cga_rigid_sim as cs
from cga_rigid_sim.sysid import impacts, model, rocking

HERE = os.path.dirname(os.path.abspath(__file__))
URDF = os.path.join(HERE, 'data', 'cube_tosses', 'cube.urdf')
SIZE, RATE, STEPS = 0.1048, 148.0, 7


def rocking_poses(e, mu, impact_ratio=1.0, scale=1.26, tilt=np.radians(35), omega=-3.0):
    """A cube turning on one bottom edge falls onto the next, sampled at 148 Hz; with ω about
    the edges' axis in the last step before the landing and in the first after it."""
    a = SIZE / 2
    w = cs.world_from_urdf(model.scale_inertia(open(URDF).read(), scale), dt=1 / (RATE * STEPS),
                           ground_plane={'height': 0.0, 'mu': mu, 'restitution': e},
                           contact_mu=mu, contact_restitution=e,
                           contact_model={'impact_friction_ratio': impact_ratio})
    c, s = np.cos(tilt), np.sin(tilt)
    pivot = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]) @ np.array([a, 0, -a])
    centre = -pivot + [0, 0, 1e-9]
    w_vec = np.array([0.0, omega, 0.0])
    w.set_body_state('body', centre, [np.cos(tilt / 2), 0, np.sin(tilt / 2), 0],
                     np.cross(w_vec, -pivot), w_vec)
    poses, om = [w.poses()[0].copy()], []
    for _ in range(40):
        for _ in range(STEPS):
            w.step()
            om.append(w.velocities()[0][4])
        poses.append(w.poses()[0].copy())
    k = int(np.argmax(np.abs(np.diff(om))))
    return np.array(poses), om[k + 1] / om[k]


@pytest.fixture(autouse=True)
def cube():
    impacts.HALF, impacts.MASS, impacts.INERTIA = impacts.read_cube(open(URDF).read())


def test_a_gripping_landing_edge_reads_housners_turn_and_no_slip():
    # Truth: the simulator's own ω just before and after the landing (Housner's ratio, to 0.003
    # in test_sysid_fit). The measure reads ω over whole sample intervals (6.8 ms) on either
    # side of the landing, where gravity turns the cube about its pivot at m g a / I_A ≈
    # 60 rad/s²: about 0.4 rad/s of the ~6 rad/s before, so each ratio to 0.07. The landing
    # edge held (μ 1) moves across itself by 0 after; read from poses, to 0.01 m/s.
    for e in (0.0, 0.3):
        poses, exact = rocking_poses(e, 1.0)
        found = rocking.rocking_impacts(poses[:, :3], poses[:, 3:])
        assert len(found) == 1
        r = found[0]
        assert r['kept'] == pytest.approx(exact, abs=0.07)
        assert abs(r['ub_slip_post']) < 0.01
        assert r['ub_n_pre'] < -0.3                # B came down onto the table
        assert r['ua_n_post'] > 0.1                # and A lifted: the cube rocks on over B


def test_a_slipping_landing_edge_reads_the_impact_friction_and_the_turn_back():
    # Truth: the landing edge slides through its impact, so its friction is the model's
    # μ k_i = 0.21 · 0.78; the measured impulse also holds the pivot edge's share of the weight
    # over the intervals (m g Δt ≈ 0.05 N s of ≈ 0.22 N s, with no friction across while it
    # rests): the ratio within [0.75, 1] μ k_i. The turn reverses (Newton's bounce at a slipping
    # edge): the simulator's ratio, to 0.07 as above.
    poses, exact = rocking_poses(0.3, 0.21, 0.78)
    found = rocking.rocking_impacts(poses[:, :3], poses[:, 3:])
    assert len(found) == 1
    r = found[0]
    assert exact < 0
    assert r['kept'] == pytest.approx(exact, abs=0.07)
    assert 0.75 * 0.21 * 0.78 <= r['ratio'] <= 0.21 * 0.78
    assert abs(r['ub_slip_post']) > 0.1


def test_predictability_finds_a_law_where_there_is_one_and_none_in_noise():
    # Truth: friction ratios exactly linear in the tilt are predicted held out to round-off
    # (R² 1 within 1e-9), and the bounce, independent noise, not at all (R² ≤ 0.1: with 80
    # samples and 9 coefficients, leave-one-out R² of pure noise is about −0.1 ± 0.1).
    rng = np.random.default_rng(0)
    rows = []
    for i in range(80):
        tilt = rng.uniform(10, 50)
        w = rng.normal(size=3) * 3
        rows.append({'data': {
            'kind': 'corner', 'tilt_deg': tilt, 'ut_pre': rng.uniform(0.5, 1),
            'un_pre': -rng.uniform(0.9, 1.3), 'w_pre': w, 'r': rng.normal(size=3) * 0.05,
            'v_pre': rng.normal(size=3), 'place': rng.normal(size=2),
            'Pt': 0.16 + 0.001 * (tilt - 30), 'Pn': 1.0,
            'un_post': 0.2 + 0.05 * rng.normal(), 'corner': i % 8}})
    for r in rows:                                  # bounce = -un_post / un_pre: noise
        r['data']['un_post'] *= -r['data']['un_pre']
    out = rocking.predictability(rows)
    assert out['friction ratio'][0] == pytest.approx(1.0, abs=1e-9)
    assert out['bounce'][0] <= 0.1


def test_each_run_at_its_own_best_grid_point_recovers_the_runs_it_came_from():
    # Truth: runs made by the simulator, two under μ 0.2 and two under μ 0.3, are each
    # reproduced exactly (errors 0 to round-off) at their own point of the grid {0.2, 0.3},
    # while one point for all leaves two of them off.
    from test_sysid_fit import synthetic_runs
    urdf, a = synthetic_runs({'mu': 0.2, 'restitution': 0.1}, n=2)
    _, b = synthetic_runs({'mu': 0.3, 'restitution': 0.1}, n=4)
    runs = a + b[2:]
    pos, rot, pos1, rot1 = impacts.per_run_best(urdf, runs, {'restitution': 0.1},
                                                {'mu': [0.2, 0.3]})
    assert pos < 1e-12 and rot < 1e-9
    assert pos1 > 0.01


def test_a_bad_grid_is_refused_by_name(capsys):
    # Truth: argparse's refusal (exit status 2) with the option, the field and the rule.
    data = os.path.dirname(URDF)
    for grid, message in (('mu=abc', "--grid 'mu=abc': expected NAME=V1/V2"),
                          ('mu=-0.1/0.2', '--grid: mu: -0.1 is not physical'),
                          ('foo=1', '--grid: foo: unknown parameter')):
        with pytest.raises(SystemExit) as e:
            impacts.main([data, '--sim', 'mu=0.2', '--grid', grid])
        assert e.value.code == 2
        assert message in capsys.readouterr().err
    with pytest.raises(SystemExit):
        impacts.main([data, '--grid', 'mu=0.2'])
    assert '--grid needs --sim' in capsys.readouterr().err
