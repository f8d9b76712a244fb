"""The Python API of the core (doc/python.md) against analytic truths and against itself:
free flight, impulses, momentum, contacts, refusals, and the batch (parallel = one by one)."""
import os
import threading

import numpy as np
import pytest

import cga_rigid_sim as cs

HERE = os.path.dirname(os.path.abspath(__file__))
CUBE_URDF = os.path.join(HERE, 'data', 'cube_tosses', 'cube.urdf')

BALL = """<?xml version="1.0"?>
<robot name="ball">
  <link name="ball">
    <inertial><mass value="2.0"/>
      <inertia ixx="0.008" ixy="0" ixz="0" iyy="0.008" iyz="0" izz="0.008"/></inertial>
    <collision><geometry><sphere radius="0.1"/></geometry></collision>
  </link>
</robot>"""

RACKET = """<?xml version="1.0"?>
<robot name="racket">
  <link name="racket">
    <inertial><mass value="0.4"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.004" iyz="0" izz="0.005"/></inertial>
  </link>
</robot>"""


def test_free_flight_is_the_parabola():
    # Truth: x(t) = x0 + v0 t + ½ g t². `auto` evaluates the parabola in closed form from the
    # elapsed time: round-off only (1e-12 m over 1 s).
    w = cs.world_from_urdf(BALL, dt=1e-3, initial_state={
        'ball': {'position': [0, 0, 10], 'linear_velocity': [1, 2, 3]}})
    w.step(1000)
    x = w.poses()[0, :3]
    expected = np.array([0, 0, 10]) + np.array([1, 2, 3]) * 1.0 + 0.5 * np.array([0, 0, -9.81])
    assert np.allclose(x, expected, atol=1e-12, rtol=0)
    assert w.time == pytest.approx(1.0, abs=1e-15)
    assert w.step_count == 1000


def test_arrays_are_one_per_world_with_documented_shapes():
    w = cs.world_from_urdf(BALL)
    assert w.body_names == ['ball']
    assert w.poses().shape == (1, 7)
    assert w.com().shape == (1, 3)
    assert w.velocities().shape == (1, 6)
    assert w.motors().shape == (1, 8)
    assert w.bivelocities().shape == (1, 6)
    # identity attitude, w first
    assert np.array_equal(w.poses()[0, 3:], [1.0, 0.0, 0.0, 0.0])


def test_torque_free_spin_keeps_its_angular_momentum():
    # Truth: without torque, L about the centre is constant in the world (the tennis racket
    # flips, L does not move); `auto` keeps it to round-off (1e-14 relative over 2 s).
    w = cs.world_from_urdf(RACKET, gravity=[0, 0, 0], initial_state={
        'racket': {'angular_velocity': [0.1, 10.0, 0.1]}})
    L0 = w.momentum()['angular'][0].copy()
    w.step(2000)
    m = w.momentum()
    assert m['names'] == ['racket', 'total']
    assert np.allclose(m['angular'][0], L0, rtol=0, atol=1e-14 * np.linalg.norm(L0))
    assert not np.allclose(w.velocities()[0, 3:], [0.1, 10.0, 0.1])  # ω itself turns


def test_impulse_changes_velocity_by_j_over_m():
    # Truth: an impulse J through the centre of a body of mass m changes v by J/m, ω not at
    # all; off the centre by p × J / I as well (I = 0.008 kg m², isotropic).
    w = cs.world_from_urdf(BALL, gravity=[0, 0, 0])
    w.apply_impulse('ball', [0.0, 0.0, 4.0], point=[0.1, 0.0, 0.0])
    w.step()
    v = w.velocities()[0]
    assert np.allclose(v[:3], [0, 0, 2.0], atol=1e-15)
    assert np.allclose(v[3:], np.cross([0.1, 0, 0], [0, 0, 4.0]) / 0.008, atol=1e-12)


def test_wrench_for_a_duration_gives_f_t_over_m():
    # Truth: a constant force F for T seconds gives Δv = F T / m (0.1 s of 10 N on 2 kg).
    w = cs.world_from_urdf(BALL, gravity=[0, 0, 0])
    w.apply_wrench('ball', [10.0, 0.0, 0.0], duration=0.1)
    w.step(200)
    assert w.velocities()[0, 0] == pytest.approx(0.5, abs=1e-12)


def test_resting_ball_reports_its_contact_carrying_its_weight():
    # Truth: a ball resting on the plane has one contact, normal +z, whose impulse per step
    # carries its weight: λ_n = m g dt (to the solver's tolerance, 1e-12 relative).
    w = cs.world_from_urdf(BALL, dt=1e-3, ground_plane={'height': 0.0},
                           initial_state={'ball': {'position': [0, 0, 0.1]}},
                           contact_sleeping=False)
    w.step(10)
    c = w.contacts()
    assert c['body_a'] == ['ball'] and c['body_b'] == ['ground_plane']
    assert np.allclose(c['normal'], [[0, 0, 1]])
    assert c['normal_impulse'][0] == pytest.approx(2.0 * 9.81 * 1e-3, rel=1e-12)
    assert np.allclose(c['point'], [[0, 0, 0]], atol=1e-12)


def test_set_body_state_and_reset():
    w = cs.world_from_urdf(BALL, gravity=[0, 0, 0])
    w.set_body_state('ball', [1, 2, 3], [0.0, 1.0, 0.0, 0.0], [1, 0, 0], [0, 0, 0])
    w.step(1000)
    assert np.allclose(w.poses()[0], [2, 2, 3, 0, 1, 0, 0], atol=1e-12)
    w.reset()
    assert np.allclose(w.poses()[0], [0, 0, 0, 1, 0, 0, 0])


def test_refusals_name_the_input_field_and_rule():
    with pytest.raises(ValueError, match='urdf_string'):
        cs.load_urdf('<robot name="x"><link name="a"><inertial><mass value="-1"/>'
                     '</inertial></link></robot>')
    with pytest.raises(ValueError, match='no_such.urdf'):
        cs.load_urdf('/nonexistent/no_such.urdf')
    with pytest.raises(ValueError, match='unknown option'):
        cs.world_from_urdf(BALL, timestep=1e-3)
    with pytest.raises(ValueError, match=r'config\.dt: must be finite and > 0'):
        cs.world_from_urdf(BALL, dt=-1.0)
    with pytest.raises(ValueError, match='static_friction_ratio: must be finite and >= 1'):
        cs.world_from_urdf(BALL, contact_model={'static_friction_ratio': 0.5})
    with pytest.raises(ValueError, match='contact_model.sticky: unknown field'):
        cs.world_from_urdf(BALL, contact_model={'sticky': 1.0})
    w = cs.world_from_urdf(BALL)
    with pytest.raises(ValueError, match=r"apply_impulse\.body: unknown body 'nobody'"):
        w.apply_impulse('nobody', [1, 0, 0])
    with pytest.raises(ValueError, match='not finite'):
        w.apply_wrench('ball', [float('nan'), 0, 0])
    with pytest.raises(ValueError, match='unit quaternion'):
        w.set_body_state('ball', [0, 0, 0], [2, 0, 0, 0])
    assert w.step_count == 0  # nothing was applied


def _tosses(n, threads):
    worlds = []
    for k in range(n):
        w = cs.World(cs.load_urdf(CUBE_URDF), dt=1e-3,
                     ground_plane={'height': 0.0, 'mu': 0.3, 'restitution': 0.2})
        q = np.array([np.cos(0.3 * k), np.sin(0.3 * k), 0.2 * np.sin(0.3 * k), 0.0])
        w.set_body_state('body', [0, 0, 0.3], q / np.linalg.norm(q),
                         [0.5 + 0.1 * k, 0.2, -1.0], [3.0, -2.0 + k, 5.0])
        worlds.append(w)
    return cs.Batch(worlds, threads=threads)


def test_batch_in_parallel_is_bit_identical_to_one_by_one():
    # Truth: each world is stepped by one thread from start to end, so parallel stepping gives
    # the states of stepping each world alone, to the bit (tosses with contacts, 0.8 s).
    parallel = _tosses(6, threads=2)
    parallel.step(800)
    alone = _tosses(6, threads=1)
    for w in alone.worlds:
        for _ in range(8):
            w.step(100)
    assert np.array_equal(parallel.poses(), alone.poses())
    for a, b in zip(parallel.worlds, alone.worlds):
        assert np.array_equal(a.velocities(), b.velocities())
    rolled, ok = _tosses(6, threads=2).rollout(8, 100)
    assert ok.all()
    assert rolled.shape == (6, 9, 1, 7)
    assert np.array_equal(rolled[:, -1], parallel.poses())


def test_batch_releases_the_gil():
    # While a batch steps in another thread, this thread runs Python: with the GIL held it
    # could not until the batch returned.
    batch = _tosses(2, threads=2)
    done = threading.Event()
    counts = []

    def run():
        batch.step(20000)
        done.set()

    t = threading.Thread(target=run)
    t.start()
    n = 0
    while not done.is_set():
        n += 1
        if n == 50:
            counts.append(done.is_set())
    t.join()
    assert counts == [False], 'the main thread ran only %d times while the batch stepped' % n


def test_contact_model_options_reach_the_core():
    # Truth: a cube sliding flat at v0 stops after v0²/(2 μ g); with face_friction_ratio f its
    # face slides with f μ: after v0²/(2 f μ g) (to the last step's travel, 1e-5 m).
    def slide(**model):
        w = cs.World(cs.load_urdf(CUBE_URDF), dt=1e-3, contact_mu=0.2,
                     ground_plane={'height': 0.0, 'mu': 0.2}, contact_model=model)
        w.set_body_state('body', [0, 0, 0.0524], [1, 0, 0, 0], [1.0, 0, 0], [0, 0, 0])
        w.step(1000)
        return w.poses()[0, 0]
    assert slide() == pytest.approx(1.0 / (2 * 0.2 * 9.81), abs=1e-5)
    assert slide(face_friction_ratio=1.25) == pytest.approx(1.0 / (2 * 0.25 * 9.81), abs=1e-5)


def test_impact_friction_ratio_reaches_the_core():
    # Truth: a ball (no spin) hitting at 2 m/s down and 1 m/s across with e = 0.5 slides through
    # the impact (its slip needs 2/7 m v_t to stop, more than the friction μ_i (1 + e) m v_n):
    # it leaves with v_x = v_t − μ_i (1 + e) v_n, μ_i = 0.1 · 0.5 (solver tolerance, 1e-9).
    w = cs.world_from_urdf(BALL, gravity=[0, 0, 0], dt=1e-3, contact_mu=0.1,
                           contact_restitution=0.5,
                           ground_plane={'height': 0.0, 'mu': 0.1, 'restitution': 0.5},
                           contact_model={'impact_friction_ratio': 0.5})
    w.set_body_state('ball', [0, 0, 0.1105], [1, 0, 0, 0], [1.0, 0, -2.0], [0, 0, 0])
    w.step(20)
    v = w.velocities()[0]
    assert v[2] == pytest.approx(1.0, abs=1e-9)
    assert v[0] == pytest.approx(1.0 - 0.05 * 1.5 * 2.0, abs=1e-9)
