#!/usr/bin/env python3
"""Measured cube tosses through the Python batch against MuJoCo: wall time and accuracy
(doc/fitting.md#speed-against-mujoco). A benchmark, not a test.

    bench/tosses_vs_mujoco.py DATA_DIR --mujoco build/peers/peer_tosses_mujoco \
        --ours mu=…,restitution=…,height=…[,static_friction_ratio=…] --count 450 --seconds 1

Each of `count` tosses starts from a measured start (scoring.find_start) of the data's runs,
taken in turn (with 100 runs, 450 tosses use each start 4 or 5 times), and is simulated for
`seconds`; the poses at the data's samples are scored against the measured ones where the data
lasts. Ours: one World per toss from the loaded URDF, stepped by cga_rigid_sim.rollout_worlds
on `threads` threads (construction and stepping timed together). MuJoCo: peer_tosses_mujoco
with the same threads, dt and steps per sample given, its stepping timed by itself; its μ,
damping ratio and plane height are tuned by a grid on the runs first (`--tune`), as ours were
fitted.
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

import cga_rigid_sim as cs
from cga_rigid_sim.sysid import impacts, model, scoring, trajectories

RATE = 148.0


def score(runs, poses_by_toss, size):
    """Mean position (fraction of size) and rotation (deg) over the distinct runs."""
    pos, rot = [], []
    for k, run in enumerate(runs):
        sim = poses_by_toss[k]
        n = min(len(run.position), len(sim))
        if not np.all(np.isfinite(sim[:n])):
            pos.append(1.0)
            rot.append(math.pi / 2)
            continue
        pos.append(float(np.mean(np.linalg.norm(run.position[:n] - sim[:n, :3], axis=1) / size)))
        rot.append(float(np.mean(scoring.rotation_angle(run.quaternion[:n], sim[:n, 3:]))))
    return float(np.mean(pos)), float(np.degrees(np.mean(rot)))


def run_ours(urdf, runs, count, samples, steps, params, threads):
    with open(urdf) as f:
        text = model.scale_inertia(f.read(), float(params.get('inertia_scale', 1.0)))
    scene = cs.load_urdf_string(text, urdf)
    opts = model.world_options(params, 1.0 / (RATE * steps))
    t0 = time.perf_counter()
    worlds = []
    for k in range(count):
        st = runs[k % len(runs)].start
        w = cs.World(scene, **opts)
        w.set_body_state('body', st.position, st.quaternion, st.velocity, st.omega_world)
        worlds.append(w)
    t1 = time.perf_counter()
    poses, ok = cs.rollout_worlds(worlds, [steps] * samples, threads)
    t2 = time.perf_counter()
    return poses[:, :, 0, :], t2 - t0, t2 - t1, int((~ok).sum())


def run_mujoco(exe, runs, count, samples, steps, dt, mu, damp, height, threads, tmp, cube):
    """cube: (half-width, mass, moment of inertia) of the body MuJoCo simulates."""
    starts = os.path.join(tmp, 'starts.txt')
    with open(starts, 'w') as f:
        for k in range(count):
            st = runs[k % len(runs)].start
            s = np.concatenate([st.position, st.quaternion, st.velocity, st.omega_world])
            f.write('%d %d %.17g %.17g %.17g ' % (samples, steps, *cube) +
                    ' '.join('%.17g' % v for v in s) + '\n')
    out = os.path.join(tmp, 'mj.csv')
    t0 = time.perf_counter()
    res = subprocess.run([exe, starts, out, '--dt', repr(dt), '--mu', repr(mu), '--dampratio',
                          repr(damp), '--height', repr(height), '--threads', str(threads)],
                         check=True, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    stepping = float(res.stdout.split()[-1])
    a = np.loadtxt(out, delimiter=',')
    poses = a[:, 2:].reshape(count, samples + 1, 7)
    return poses, wall, stepping


def damp_for(e):
    if e <= 0:
        return 1.0
    l = math.log(e)
    return -l / math.sqrt(math.pi ** 2 + l * l)


def main():
    p = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    p.add_argument('data')
    p.add_argument('--urdf', help='default: DATA/cube.urdf')
    p.add_argument('--mujoco', required=True, help='the peer_tosses_mujoco executable')
    p.add_argument('--ours', required=True, help='our parameters, name=value,…')
    p.add_argument('--count', type=int, default=450)
    p.add_argument('--seconds', type=float, default=1.0)
    p.add_argument('--steps-per-sample', default='7,3',
                   help='our steps per sample, comma-separated (7: dt 0.965 ms, 3: 2.25 ms)')
    p.add_argument('--mujoco-steps-per-sample', type=int, default=3,
                   help='MuJoCo steps per sample (3: dt = 2.25 ms, near its default 2 ms)')
    p.add_argument('--threads', type=int, default=2)
    p.add_argument('--tune', default='mu=0.1:0.5:9,restitution=0:0.4:5,height=-0.003:0:4',
                   help='MuJoCo grid: name=low:high:count')
    p.add_argument('--repeat', type=int, default=3, help='timings: best of this many')
    a = p.parse_args()
    urdf = a.urdf or os.path.join(a.data, 'cube.urdf')
    trajs = trajectories.read_directory(a.data)
    samples = int(round(a.seconds * RATE))
    ours_steps = [int(x) for x in str(a.steps_per_sample).split(',')]
    with open(urdf) as f:
        half, mass, inertia = impacts.read_cube(f.read())
    runs = model.prepare_runs(trajs, RATE * ours_steps[0], half * math.sqrt(3))
    ours = {k: v[0] for k, v in model.parse_ranges(a.ours).items()}
    size = 2 * half
    # The cube's moments as ours are given them (inertia_scale, a property of the body measured
    # from the first impacts, doc/fitting.md): MuJoCo simulates the same body.
    cube = (half, mass, inertia * ours.get('inertia_scale', 1.0))
    print('tosses: %d starts of %s, %d simulated, %d samples (%.3f s) each, %d threads'
          % (len(runs), a.data, a.count, samples, samples / RATE, a.threads))

    best = None
    with tempfile.TemporaryDirectory() as tmp:
        grid = {}
        for part in a.tune.split(','):
            name, rng = part.split('=')
            lo, hi, n = rng.split(':')
            grid[name] = np.linspace(float(lo), float(hi), int(n))
        ms = a.mujoco_steps_per_sample
        dt_mj = 1.0 / (RATE * ms)
        for mu in grid['mu']:
            for e in grid['restitution']:
                for h in grid['height']:
                    poses, _, _ = run_mujoco(a.mujoco, runs, len(runs), samples, ms, dt_mj, mu,
                                             damp_for(e), h, a.threads, tmp, cube)
                    pe, re = score(runs, poses, size)
                    J = pe / 0.1 + re / 15
                    if best is None or J < best[0]:
                        best = (J, mu, e, h, pe, re)
        print('MuJoCo tuned on the %d runs: mu %.3f, e %.2f (dampratio %.3f), height %.4f: '
              'position %.1f %%, rotation %.1f deg' % (len(runs), best[1], best[2],
                                                       damp_for(best[2]), best[3],
                                                       100 * best[4], best[5]))
        rows = []
        for label, steps in (('ours', st) for st in ours_steps):
            times = []
            for _ in range(a.repeat):
                poses, total, stepping, failed = run_ours(urdf, runs, a.count, samples, steps,
                                                          ours, a.threads)
                times.append((total, stepping))
            pe, re = score(runs, poses[:len(runs)], size)
            total, stepping = min(times)
            rows.append((label + ' (dt %.3f ms)' % (1e3 / (RATE * steps)), total, stepping, pe,
                         re, failed))
        for ms in sorted({a.mujoco_steps_per_sample, ours_steps[0]}):
            times = []
            for _ in range(a.repeat):
                poses, wall, stepping = run_mujoco(a.mujoco, runs, a.count, samples, ms,
                                                   1.0 / (RATE * ms), best[1], damp_for(best[2]),
                                                   best[3], a.threads, tmp, cube)
                times.append((wall, stepping))
            pe, re = score(runs, poses[:len(runs)], size)
            wall, stepping = min(times)
            rows.append(('MuJoCo (dt %.3f ms)' % (1e3 / (RATE * ms)), wall, stepping, pe, re, 0))
    print('\n| engine | wall time, s (all) | stepping, s | position error | rotation error |')
    print('|---|---|---|---|---|')
    for label, total, stepping, pe, re, failed in rows:
        print('| %s | %.3f | %.3f | %.1f %% | %.1f° |' % (label, total, stepping, 100 * pe, re))
    return 0


if __name__ == '__main__':
    sys.exit(main())
