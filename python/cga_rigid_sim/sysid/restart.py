"""The runs simulated again from the real state just after their first impact (`fit impacts
--after-first`, doc/fitting.md#the-floor-of-one-deterministic-model).

Where the model's error on a run is made before and after its first impact: each run is
started again OFFSET samples after the last sample before its first impact (2: the first whole
interval after it), from the measured pose there and the velocities over the next sample
interval (the centre's, less half an interval of gravity), and scored over the rest of the run
against the data, beside the nominal simulation over the same samples. The same restart made
from the nominal simulation's own poses must give the simulation back: what it leaves is the
restart's own error (its velocities are differences over one interval, through contact).
"""
import math

import numpy as np

from . import model, scoring

G = np.array([0.0, 0.0, -9.81])


def restarted(run, positions, quats, a, rate):
    """`run` started again at its sample a from positions/quats (the data's or a simulation's
    poses, from the run's start on)."""
    dt = 1.0 / rate
    v = (positions[a + 1] - positions[a]) / dt - G * dt / 2
    w = scoring.turn_vectors(quats[a:a + 2])[0] / dt
    start = scoring.Start(run.start.index + a, positions[a].copy(), quats[a].copy(), v, w)
    return model.Run(run.name, start, run.increments[a:], run.position[a:], run.quaternion[a:])


def scores(reference, sims, size):
    """Mean position (fraction of size) and rotation (deg) errors of the simulated poses against
    the reference poses, and the number of final attitudes more than 40° apart."""
    pos, rot = np.array([scoring.pose_errors(r, s, size) for s, r in zip(sims, reference)]).T
    faces = sum(math.degrees(scoring.rotation_angle(s[-1:, 3:], r[-1:, 3:])[0]) > 40
                for s, r in zip(sims, reference))
    return float(np.mean(pos)), math.degrees(np.mean(rot)), int(faces)


def after_first(urdf_text, body, runs, nominal, impact_samples, params, dt, size, rate,
                offset=2):
    """Restarts every run whose first impact was found (impact_samples[i]: the last sample
    before it, or None) and whose nominal simulation (keep_poses) succeeded, from the data and,
    as the control, from the nominal simulation: the errors of each against its source, and of
    the nominal against the data over the same samples."""
    chosen, from_data, from_sim = [], [], []
    for run, nom, k in zip(runs, nominal, impact_samples):
        if k is None or not nom['ok'] or k + offset + 2 >= len(run.position):
            continue
        a = k + offset
        chosen.append((run, nom, a))
        from_data.append(restarted(run, run.position, run.quaternion, a, rate))
        from_sim.append(restarted(run, nom['poses'][:, :3], nom['poses'][:, 3:], a, rate))
    if not chosen:
        return None
    data_runs = model.simulate_runs(urdf_text, body, from_data, params, dt, size, keep_poses=True)
    sim_runs = model.simulate_runs(urdf_text, body, from_sim, params, dt, size, keep_poses=True)
    ok = [i for i in range(len(chosen)) if data_runs[i]['ok'] and sim_runs[i]['ok']]
    data_ref = [np.c_[chosen[i][0].position, chosen[i][0].quaternion][chosen[i][2]:] for i in ok]
    return {'runs': len(ok), 'offset': offset,
            'restarted': scores(data_ref, [data_runs[i]['poses'] for i in ok], size),
            'nominal': scores(data_ref, [chosen[i][1]['poses'][chosen[i][2]:] for i in ok], size),
            'control': scores([chosen[i][1]['poses'][chosen[i][2]:] for i in ok],
                              [sim_runs[i]['poses'] for i in ok], size)}


def report(result):
    if result is None:
        print('after the first impact: no run to restart')
        return
    print('after the first impact (%d runs restarted %d samples after the last before it): '
          'from the real state %.1f %%, %.1f deg, another final face in %d; the nominal '
          'simulation over the same samples %.1f %%, %.1f deg, %d; the restart made from the '
          'nominal simulation gives it back to %.2f %%, %.2f deg, %d'
          % (result['runs'], result['offset'], 100 * result['restarted'][0],
             result['restarted'][1], result['restarted'][2], 100 * result['nominal'][0],
             result['nominal'][1], result['nominal'][2], 100 * result['control'][0],
             result['control'][1], result['control'][2]))
