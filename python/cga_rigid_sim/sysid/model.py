"""The parameters a fit can choose, their physical ranges, and the simulation of measured runs
under one choice of them (doc/fitting.md#parameters).

Everything here is plain data and functions of it, so that a Dask worker can run
`simulate_runs` from what it is sent (the URDF text, the runs' starts, the parameters).
"""
import hashlib
import math
import re
from dataclasses import dataclass

import numpy as np

from . import scoring

# name: (lowest physical value, highest, default, where it goes, what it is)
PARAMETERS = {
    'mu': (0.0, math.inf, 0.5, 'surface',
           'Coulomb friction coefficient (kinetic), body and surface'),
    'restitution': (0.0, 1.0, 0.0, 'surface', "Newton's coefficient of restitution"),
    'height': (-math.inf, math.inf, 0.0, 'plane', 'height of the supporting plane, m'),
    'static_friction_ratio': (1.0, math.inf, 1.0, 'model', 'static over kinetic friction, >= 1'),
    'stribeck_speed': (0.0, math.inf, 0.05, 'model',
                       'slip speed of the passage from static to kinetic friction, m/s, > 0'),
    'rolling_resistance': (0.0, math.inf, 0.0, 'model', 'lever of the rolling couple, m'),
    'torsional_resistance': (0.0, math.inf, 0.0, 'model', 'lever of the torsional couple, m'),
    'restitution_speed_exponent': (0.0, math.inf, 0.0, 'model',
                                   'p of e(v) = e (v_ref/v)^p, >= 0 (Johnson: 1/4)'),
    'restitution_reference_speed': (0.0, math.inf, 1.0, 'model',
                                    'v_ref of e(v), the speed at which e holds, m/s, > 0'),
    'box_edge_radius': (0.0, math.inf, 0.0, 'model',
                        'radius of the rounded edges of boxes on the plane, m'),
    'normal_stiffness': (0.0, math.inf, 0.0, 'model',
                         'Hunt-Crossley stiffness per contact point, N/m (0: rigid)'),
    'normal_dissipation': (0.0, math.inf, 0.0, 'model', 'Hunt-Crossley dissipation, s/m'),
    'tangential_restitution': (0.0, 1.0, 0.0, 'model', 'slip reversal at impacts, in [0, 1]'),
    'face_friction_ratio': (0.0, math.inf, 1.0, 'model',
                            'friction of a face over that of an edge or corner, > 0'),
    'impact_friction_ratio': (0.0, math.inf, 1.0, 'model',
                              'friction in an impact over that of a resting or sliding one, > 0'),
    'face_restitution_ratio': (0.0, 1.0, 1.0, 'model',
                               'restitution of a face landing flat over that of a corner or edge'),
    'inertia_scale': (0.0, math.inf, 1.0, 'body',
                      "the body's moments of inertia over the URDF's, > 0"),
}
# Parameters whose lowest value is excluded (a speed of 0 divides, a body needs inertia).
OPEN_BELOW = {'stribeck_speed', 'restitution_reference_speed', 'face_friction_ratio',
              'impact_friction_ratio', 'inertia_scale'}


class ParameterError(ValueError):
    """A parameter, a range or a value that is not physical: names it and the rule."""


def check_value(name, value):
    if name not in PARAMETERS:
        raise ParameterError('%s: unknown parameter (known: %s)' % (name, ', '.join(PARAMETERS)))
    lo, hi = PARAMETERS[name][:2]
    if not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ParameterError('%s: must be a finite number (got %r)' % (name, value))
    if value < lo or value > hi or (name in OPEN_BELOW and value <= lo):
        raise ParameterError('%s: %g is not physical (%s; allowed %s%g … %g)'
                             % (name, value, PARAMETERS[name][4],
                                '>' if name in OPEN_BELOW else '', lo, hi))


def parse_ranges(text_or_dict):
    """{'mu': (lo, hi), …} from 'mu=0.05:0.6,restitution=0:0.5' or a dict; a range lo:hi with
    lo < hi, or a single value (held fixed). Refuses unknown names, empty ranges (lo > hi, or
    nothing given) and values outside the physical range."""
    if isinstance(text_or_dict, dict):
        items = list(text_or_dict.items())
    else:
        items = []
        for part in [p.strip() for p in str(text_or_dict).split(',') if p.strip()]:
            if '=' not in part:
                raise ParameterError('%s: expected name=low:high or name=value' % part)
            name, rng = part.split('=', 1)
            bounds = rng.split(':')
            try:
                vals = tuple(float(b) for b in bounds)
            except ValueError:
                raise ParameterError('%s: %r is not a number or low:high' % (name, rng)) from None
            if len(vals) not in (1, 2):
                raise ParameterError('%s: expected low:high or one value, got %r' % (name, rng))
            items.append((name.strip(), vals))
    if not items:
        raise ParameterError('parameters: the range is empty (name at least one, e.g. mu=0.05:0.6)')
    out = {}
    for name, vals in items:
        vals = tuple(vals) if isinstance(vals, (tuple, list)) else (vals,)
        if len(vals) == 1:
            vals = (vals[0], vals[0])
        lo, hi = float(vals[0]), float(vals[1])
        check_value(name, lo)
        check_value(name, hi)
        if lo > hi:
            raise ParameterError('%s: empty range %g:%g (low must not exceed high)'
                                 % (name, lo, hi))
        if name in out:
            raise ParameterError('%s: given twice' % name)
        out[name] = (lo, hi)
    return out


def world_options(params, dt, integrator='auto'):
    """The World keywords for a choice of parameters (unset ones at their defaults)."""
    p = {name: spec[2] for name, spec in PARAMETERS.items()}
    for name, value in params.items():
        check_value(name, value)
        p[name] = float(value)
    model = {k: p[k] for k, spec in PARAMETERS.items() if spec[3] == 'model'}
    return {'dt': dt, 'integrator': integrator,
            'contact_mu': p['mu'], 'contact_restitution': p['restitution'],
            'ground_plane': {'height': p['height'], 'mu': p['mu'],
                             'restitution': p['restitution']},
            'contact_model': model}


def object_size(scene, body):
    """The size positions are divided by (the largest edge of the body's boxes, or its largest
    diameter), and its bounding radius about the root link; refuses a body without collision
    shapes (there is nothing to touch the surface with)."""
    shapes = scene.collision_shapes(body)
    if not shapes:
        raise ParameterError('%s: body %r has no <collision> shape: it cannot touch the surface, '
                             'there is nothing to fit' % (scene.source, body))
    size, radius = 0.0, 0.0
    for s in shapes:
        if s['kind'] == 'box':
            size = max(size, max(s['size']))
            radius = max(radius, 0.5 * float(np.linalg.norm(s['size'])))
        elif s['kind'] == 'sphere':
            size = max(size, 2 * s['radius'])
            radius = max(radius, s['radius'])
        elif s['kind'] == 'cylinder':
            size = max(size, 2 * s['radius'], s['length'])
            radius = max(radius, math.hypot(s['radius'], 0.5 * s['length']))
        else:  # a mesh: no extent reported; the caller gives --size
            pass
    if size <= 0:
        raise ParameterError('%s: body %r: the size of a mesh is not known; give --size'
                             % (scene.source, body))
    return size, radius


@dataclass
class Run:
    """What a simulation of one measured run needs, and the data it is compared with."""
    name: str
    start: scoring.Start
    increments: np.ndarray   # steps between consecutive samples from the start
    position: np.ndarray     # (n, 3) measured, from the start
    quaternion: np.ndarray   # (n, 4)


def prepare_runs(trajectories, steps_per_second, bounding_radius, surface_height=0.0,
                 gravity=(0.0, 0.0, -9.81), horizon=None):
    """Runs from trajectories: start found, the sample times turned into step counts (each
    sample at the step nearest to its time); `horizon` (s) cuts each run after that long."""
    runs = []
    for tr in trajectories:
        st = scoring.find_start(tr, bounding_radius, surface_height, gravity)
        t = tr.t[st.index:] - tr.t[st.index]
        if horizon is not None:
            t = t[t <= horizon + 1e-9]
        steps = np.rint(t * steps_per_second).astype(np.int64)
        n = len(t)
        runs.append(Run(name=tr.name, start=st, increments=np.diff(steps),
                        position=tr.position[st.index:st.index + n],
                        quaternion=tr.quaternion[st.index:st.index + n]))
    return runs


_SCENES = {}
_INERTIA = re.compile(r'(<inertia\b[^>]*>)', re.S)
_MOMENT = re.compile(r'\b(i(?:xx|xy|xz|yy|yz|zz))\s*=\s*"([^"]*)"')


def scale_inertia(urdf_text, scale):
    """The URDF with every link's inertia tensor (ixx … izz of each <inertia>) times `scale`:
    the fit's inertia_scale, for a body whose URDF has the mass right but not its distribution
    (a hollow object given a solid one's moments; doc/fitting.md#the-first-impact-measured)."""
    if scale == 1.0:
        return urdf_text

    def moments(m):
        return _MOMENT.sub(lambda a: '%s="%r"' % (a.group(1), float(a.group(2)) * scale),
                           m.group(1))
    return _INERTIA.sub(moments, urdf_text)


def scene_of(urdf_text):
    """The Scene of a URDF text, loaded once per process (workers keep it between tasks)."""
    import cga_rigid_sim
    key = hashlib.sha1(urdf_text.encode()).hexdigest()
    if key not in _SCENES:
        _SCENES[key] = cga_rigid_sim.load_urdf_string(urdf_text, 'urdf')
    return _SCENES[key]


def simulate_runs(urdf_text, body, runs, params, dt, size, integrator='auto', threads=1,
                  keep_poses=False):
    """Simulates every run under `params`; returns per run a dict with the mean position error
    (fraction of size), mean rotation error (rad), ok, an error message if the simulation
    failed, and with keep_poses the simulated poses. A run that cannot be simulated (refused
    state, non-finite result) is reported, not raised: the other runs keep their results."""
    import cga_rigid_sim
    options = world_options(params, dt, integrator)
    scene = scene_of(scale_inertia(urdf_text, float(params.get('inertia_scale', 1.0))))
    worlds, made, out = [], [], [None] * len(runs)
    for k, run in enumerate(runs):
        try:
            w = cga_rigid_sim.World(scene, **options)
            st = run.start
            w.set_body_state(body, st.position, st.quaternion, st.velocity, st.omega_world)
        except ValueError as e:
            out[k] = {'run': run.name, 'ok': False, 'error': str(e), 'position': math.nan,
                      'rotation': math.nan}
            continue
        worlds.append(w)
        made.append(k)
    # Runs of different lengths: each batch shares its increments, so group equal schedules.
    groups = {}
    for k in made:
        groups.setdefault(runs[k].increments.tobytes(), []).append(k)
    index = {k: i for i, k in enumerate(made)}
    for ks in groups.values():
        ws = [worlds[index[k]] for k in ks]
        poses, ok = cga_rigid_sim.rollout_worlds(ws, [int(x) for x in runs[ks[0]].increments],
                                                 threads)
        for j, k in enumerate(ks):
            run = runs[k]
            sim = poses[j, :, 0, :]
            if not ok[j]:
                bad = int(np.argmax(~np.isfinite(sim[:, 0])))
                out[k] = {'run': run.name, 'ok': False, 'position': math.nan, 'rotation': math.nan,
                          'error': 'the state became non-finite before sample %d' % bad}
                continue
            pos = np.linalg.norm(run.position - sim[:, :3], axis=1) / size
            rot = scoring.rotation_angle(run.quaternion, sim[:, 3:])
            out[k] = {'run': run.name, 'ok': True, 'error': '', 'position': float(pos.mean()),
                      'rotation': float(rot.mean())}
            if keep_poses:
                out[k]['poses'] = sim
                out[k]['position_series'] = pos
                out[k]['rotation_series'] = rot
    return out
