"""`fit impacts --after-first` (sysid/restart.py): a run started again from poses after its
first impact."""
import math
import os

import numpy as np
import pytest

from cga_rigid_sim.sysid import impacts, model, restart, scoring, trajectories

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, 'data', 'cube_tosses')
URDF = open(os.path.join(DATA, 'cube.urdf')).read()
SIZE, RATE, STEPS = 0.1048, 148.0, 7
DT = 1.0 / (RATE * STEPS)
PARAMS = {'mu': 0.21, 'restitution': 0.2, 'height': -0.0012, 'box_edge_radius': 0.005,
          'impact_friction_ratio': 0.78, 'inertia_scale': 1.3}


def test_the_restart_state_of_a_free_flight_is_exact():
    # Truth: the flight's own velocity at the restart sample. A forward difference of a
    # parabola less half an interval of gravity is its velocity at the interval's start, and
    # the relative rotation of a constant spin over one interval is the spin times it: both to
    # round-off.
    n, a = 20, 6
    t = np.arange(n) / RATE
    v0, w = np.array([0.7, -0.2, 1.1]), np.array([3.0, -1.0, 5.0])
    p = np.outer(t, v0) + 0.5 * np.outer(t * t, restart.G)
    ang = np.outer(t, w)
    th = np.linalg.norm(ang, axis=1)
    s = np.where(th > 0, np.sin(th / 2) / np.where(th > 0, th, 1), 0.5)
    q = np.c_[np.cos(th / 2), ang * s[:, None]]
    start = scoring.Start(0, p[0], q[0], v0, w)
    run = model.Run('flight', start, np.full(n - 1, STEPS), p, q)
    r = restart.restarted(run, p, q, a, RATE)
    assert r.start.velocity == pytest.approx(v0 + restart.G * t[a], abs=1e-12)
    assert r.start.omega_world == pytest.approx(w, abs=1e-9)
    assert len(r.position) == n - a and len(r.increments) == n - 1 - a


def test_a_restart_from_the_simulation_gives_it_back():
    # The control the command prints: restarted from its own poses after the first impact, a
    # simulation is given back exactly where the cube flies over the restart's interval (the
    # state is then exact, as above: 1e-4 of the width and 0.01° bound round-off grown over a
    # second), and a little off where it touches the table over it (the velocities are
    # differences through contact: toss 0 here, 6.7 % and 11.7°; 0.14 % and 0.21° on average
    # over the 100 tosses). A state carried over wrongly would move every toss.
    trajs = trajectories.read_directory(DATA, RATE)
    runs = model.prepare_runs(trajs, RATE * STEPS, SIZE / 2 * math.sqrt(3), 0.0, horizon=1.0)
    nominal = model.simulate_runs(URDF, 'body', runs, PARAMS, DT, SIZE, keep_poses=True)
    impacts.HALF, impacts.MASS, impacts.INERTIA = impacts.read_cube(URDF)
    ks = [m['k'] if m else None for m in
          (impacts.measure(r.position, r.quaternion, r.start, -0.0012) for r in runs)]
    exact = 0
    for i in range(len(runs)):
        res = restart.after_first(URDF, 'body', runs[i:i + 1], nominal[i:i + 1], ks[i:i + 1],
                                  PARAMS, DT, SIZE, RATE)
        pos, rot, faces = res['control']
        assert faces == 0
        exact += pos < 1e-4 and rot < 0.01
        # The nominal's own score over the same samples is against the data.
        assert res['nominal'][0] > 0.01
    assert exact >= 6


def test_after_first_without_the_simulations_parameters_is_refused(capsys):
    with pytest.raises(SystemExit) as e:
        impacts.main([DATA, '--after-first'])
    assert e.value.code == 2
    assert '--after-first needs --sim' in capsys.readouterr().err
