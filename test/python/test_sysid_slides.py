"""`fit impacts --slides` (sysid/slides.py, doc/fitting.md#the-slides-and-the-impacts): a flat
slide simulated again from its sampled poses ends where it ended, and the error's growth is
split by the final face."""
import math
import os

import numpy as np
import pytest

import cga_rigid_sim as cs
from cga_rigid_sim.sysid import impacts, model, scoring, slides

HERE = os.path.dirname(os.path.abspath(__file__))
URDF = os.path.join(HERE, 'data', 'cube_tosses', 'cube.urdf')
SIZE, RATE, STEPS = 0.1048, 148.0, 7
PARAMS = {'mu': 0.21, 'restitution': 0.2, 'height': -0.0012, 'box_edge_radius': 0.005,
          'inertia_scale': 1.26}


def sampled_slide(params, v=(0.6, -0.2, 0.0), spin=3.0, samples=90):
    """A cube set flat on the plane, sliding at v and spinning about the vertical, its poses
    sampled at 148 Hz: a Run whose data is the simulation."""
    urdf = model.scale_inertia(open(URDF).read(), params['inertia_scale'])
    w = cs.World(cs.load_urdf_string(urdf, 'cube'),
                 **model.world_options(params, 1.0 / (RATE * STEPS)))
    yaw = 0.4
    w.set_body_state('body', [0.1, -0.05, params['height'] + SIZE / 2],
                     [math.cos(yaw / 2), 0, 0, math.sin(yaw / 2)], list(v), [0, 0, spin])
    poses, ok = cs.rollout_worlds([w], [STEPS] * samples, 1)
    assert ok[0]
    p = poses[0, :, 0, :]
    start = scoring.Start(0, p[0, :3], p[0, 3:], np.array(v, float), np.array([0, 0, spin]))
    return model.Run('slide', start, np.full(samples, STEPS), p[:, :3].copy(), p[:, 3:].copy())


def test_a_replayed_slide_ends_where_the_simulation_ended():
    # Truth: the simulation the poses were sampled from. The replay starts MARGIN (5) samples
    # in, from velocities fitted to five poses by quadratics, exact for a constant deceleration;
    # the slide's deceleration shifts a little between slip and spin as they trade over the
    # 27 ms of the fit, so the end (after ~75 % of the width of travel) agrees to 0.1 mm
    # (1e-3 of the width) and 0.1° (measured: 8e-5 and 0.03°).
    run = sampled_slide(PARAMS)
    rep = slides.replay(open(URDF).read(), 'body', [run], PARAMS, 1.0 / (RATE * STEPS), SIZE,
                        SIZE / 2)[0]
    assert rep['start'] == slides.MARGIN
    assert rep['travel'] > 0.5
    assert rep['position'] < 1e-3
    assert math.degrees(rep['rotation']) < 0.1
    # And the replay sees the slide's law: with μ 10 % higher the same start ends more than
    # 5 % of the width short (a slide of v²/(2 μ g), 0.8 widths from the start at 0.6 m/s,
    # shortens by a tenth of itself: ~7 %).
    other = slides.replay(open(URDF).read(), 'body', [run], dict(PARAMS, mu=0.231),
                          1.0 / (RATE * STEPS), SIZE, SIZE / 2)[0]
    assert other['position'] > 0.05


def test_a_slide_start_is_level_and_keeps_the_yaw():
    # A yawed pose tilted by 0.8° about a world horizontal axis is levelled by the turn about
    # that axis that undoes the tilt: it gives back the yawed pose itself, to round-off (the
    # quaternions' products: 1e-12 rad).
    yaw, tilt = 0.7, math.radians(0.8)
    q_yaw = np.array([math.cos(yaw / 2), 0, 0, math.sin(yaw / 2)])
    q_tilt = np.array([math.cos(tilt / 2), math.sin(tilt / 2), 0, 0])
    q = slides.level(scoring.quat_mul(q_tilt, q_yaw))
    up = scoring.quat_rotate(q, np.array([0.0, 0.0, 1.0]))
    assert up == pytest.approx([0, 0, 1], abs=1e-12)
    assert scoring.rotation_angle(q, q_yaw) < 1e-12


def test_growth_splits_the_runs_by_their_final_face():
    # Two runs with known errors: one ending 10° about the vertical from the real cube (same
    # face), one 60° (another face).
    n = 12
    runs, sims = [], []
    for final in (10.0, 60.0):
        ramp = np.linspace(0.0, math.radians(final), n)
        q_data = np.tile([1.0, 0, 0, 0], (n, 1))
        q_sim = np.stack([[math.cos(a / 2), 0, 0, math.sin(a / 2)] for a in ramp])
        pos = np.linspace(0.0, 0.2, n)
        runs.append(model.Run('r', None, np.full(n - 1, STEPS), np.zeros((n, 3)), q_data))
        sims.append({'ok': True, 'position': pos.mean(), 'rotation': ramp.mean(),
                     'position_series': pos, 'rotation_series': ramp,
                     'poses': np.hstack([np.zeros((n, 3)), q_sim])})
    g = slides.growth(runs, sims, samples=(5, 11))
    assert g['same']['runs'] == 1 and g['other']['runs'] == 1
    assert g['same']['final_deg'] == pytest.approx(10.0, abs=1e-9)
    assert g['same']['final_yaw_deg'] == pytest.approx(10.0, abs=1e-9)
    s, count, p, r = g['other']['at'][1]
    assert (s, count) == (11, 1)
    assert r == pytest.approx(60.0, abs=1e-9) and p == pytest.approx(0.2, abs=1e-12)
    assert g['same']['mean'][1] == pytest.approx(5.0, abs=1e-9)


def test_slides_without_the_simulations_parameters_are_refused(capsys):
    data = os.path.join(HERE, 'data', 'cube_tosses')
    with pytest.raises(SystemExit) as e:
        impacts.main([data, '--slides'])
    assert e.value.code == 2
    assert '--slides needs --sim' in capsys.readouterr().err


def test_fit_impacts_slides_prints_the_replay(capsys):
    # The command end to end on the eight tosses of the test data: the two groups hold the
    # eight runs between them, and the replay reports the runs with a last flat slide.
    import re
    data = os.path.join(HERE, 'data', 'cube_tosses')
    assert impacts.main([data, '--slides', '--sim',
                         ','.join('%s=%r' % kv for kv in PARAMS.items())]) == 0
    out = capsys.readouterr().out
    same = int(re.search(r'runs ending on the real face: (\d+)', out).group(1))
    other = int(re.search(r'runs ending on another: (\d+)', out).group(1))
    assert same + other == 8
    replayed = int(re.search(r'from the real state at its start \((\d+) runs\)', out).group(1))
    assert 1 <= replayed <= 8
