"""Measured pose trajectories: read from CSV files or a rosbag of tf, validated
(doc/fitting.md#input).

CSV (the format of the ContactNets cube tosses): a header line naming the columns
    [t,] qw, qx, qy, qz, x, y, z, wx, wy, wz, vx, vy, vz
(the attitude as a unit quaternion, w first, world from body; the centre in world axes, m; the
angular velocity in body axes, rad/s; the centre's velocity in world axes, m/s). Without a `t`
column row k is at t = k / rate. The velocities are read and checked but not needed: the fit
estimates the starting velocity from the poses (scoring.py).

Every refusal is a TrajectoryError (a ValueError) whose message names the file, the row (1 =
the first line after the header) or the field, and the rule broken.
"""
import csv
import math
import os
from dataclasses import dataclass, field

import numpy as np

COLUMNS = ('qw', 'qx', 'qy', 'qz', 'x', 'y', 'z', 'wx', 'wy', 'wz', 'vx', 'vy', 'vz')
# A quaternion is unit when |q| is within this of 1: the data's quaternions are unit to ~1e-15;
# 1e-3 takes rounding to 4 printed digits and refuses a scaled or garbled row.
UNIT_TOLERANCE = 1e-3


class TrajectoryError(ValueError):
    """Bad measured input: the message names file, row or field, and the rule."""


@dataclass
class Trajectory:
    """One measured run of one body: N samples at times t (s, from 0)."""
    name: str
    t: np.ndarray             # (N,)
    position: np.ndarray      # (N, 3) m, world
    quaternion: np.ndarray    # (N, 4) w, x, y, z (world from body), unit
    source: str = ''
    extra: dict = field(default_factory=dict)

    def __len__(self):
        return len(self.t)


def _fail(path, where, rule):
    raise TrajectoryError('%s: %s: %s' % (path, where, rule))


def read_csv(path, rate=148.0, min_samples=10):
    """One trajectory from a CSV file (module docstring)."""
    if not (isinstance(rate, (int, float)) and math.isfinite(rate) and rate > 0):
        raise TrajectoryError('rate: must be a finite number > 0 (got %r)' % (rate,))
    name = os.path.splitext(os.path.basename(path))[0]
    try:
        with open(path, newline='') as f:
            rows = list(csv.reader(f))
    except OSError as e:
        raise TrajectoryError('%s: cannot read (%s)' % (path, e.strerror or e)) from None
    except UnicodeDecodeError:
        raise TrajectoryError('%s: not a text file (UTF-8 expected)' % path) from None
    if not any(c.strip() for row in rows for c in row):
        _fail(path, 'header', 'the file is empty; expected the columns ' + ','.join(COLUMNS))
    header = [h.strip() for h in rows[0]]
    has_t = bool(header) and header[0] == 't'
    expected = (('t',) if has_t else ()) + COLUMNS
    if tuple(header) != expected:
        missing = [c for c in expected if c not in header]
        unknown = [c for c in header if c not in expected]
        detail = []
        if missing:
            detail.append('missing ' + ','.join(missing))
        if unknown:
            detail.append('unknown ' + ','.join(unknown))
        if not detail:
            detail.append('in another order')
        _fail(path, 'header', 'columns must be %s (%s)' % (','.join(expected), '; '.join(detail)))
    data = []
    for k, row in enumerate(rows[1:], start=1):
        if not row or all(not c.strip() for c in row):
            _fail(path, 'row %d' % k, 'empty line (every row holds %d values)' % len(expected))
        if len(row) != len(expected):
            _fail(path, 'row %d' % k,
                  'has %d values, the header names %d' % (len(row), len(expected)))
        values = []
        for name_c, cell in zip(expected, row):
            try:
                v = float(cell)
            except ValueError:
                _fail(path, 'row %d, field %s' % (k, name_c), 'not a number (%r)' % cell)
            if not math.isfinite(v):
                _fail(path, 'row %d, field %s' % (k, name_c), 'not finite (%s)' % cell.strip())
            values.append(v)
        data.append(values)
    if len(data) < min_samples:
        _fail(path, 'rows', 'has %d samples, at least %d needed' % (len(data), min_samples))
    a = np.array(data)
    off = 1 if has_t else 0
    q = a[:, off:off + 4]
    norms = np.linalg.norm(q, axis=1)
    bad = np.nonzero(np.abs(norms - 1.0) > UNIT_TOLERANCE)[0]
    if bad.size:
        k = int(bad[0])
        _fail(path, 'row %d, fields qw,qx,qy,qz' % (k + 1),
              'not a unit quaternion (|q| = %.6g, 1 within %g expected)'
              % (norms[k], UNIT_TOLERANCE))
    if has_t:
        t = a[:, 0]
        steps = np.diff(t)
        back = np.nonzero(steps <= 0)[0]
        if back.size:
            k = int(back[0]) + 1
            _fail(path, 'row %d, field t' % (k + 1),
                  'time must increase (t = %.9g after %.9g)' % (t[k], t[k - 1]))
        t = t - t[0]
    else:
        t = np.arange(len(a)) / float(rate)
    return Trajectory(name=name, t=t, position=a[:, off + 4:off + 7].copy(),
                      quaternion=q / norms[:, None], source=path,
                      extra={'omega_body': a[:, off + 7:off + 10].copy(),
                             'velocity': a[:, off + 10:off + 13].copy()})


def read_directory(path, rate=148.0):
    """Every *.csv of a directory, sorted by name."""
    if not os.path.isdir(path):
        raise TrajectoryError('%s: not a directory' % path)
    names = sorted(n for n in os.listdir(path) if n.endswith('.csv'))
    if not names:
        raise TrajectoryError('%s: holds no *.csv trajectory' % path)
    return [read_csv(os.path.join(path, n), rate=rate) for n in names]


def read_bag(path, frame, parent='world', topics=('/tf',), split_gap=0.5, min_samples=10):
    """Trajectories of `frame` relative to `parent` from the tf messages of a rosbag: one
    trajectory per run of samples without a gap longer than `split_gap` s (each toss recorded
    in one bag). Only direct transforms parent → frame are read (a chain is not composed)."""
    try:
        import rosbag  # Debian's python3-rosbag
    except ImportError:  # pragma: no cover - the package depends on it
        raise TrajectoryError('%s: reading bags needs python3-rosbag' % path) from None
    if not os.path.isfile(path):
        raise TrajectoryError('%s: no such file' % path)
    times, poses = [], []
    seen = set()
    try:
        with rosbag.Bag(path) as bag:
            for _, msg, _ in bag.read_messages(topics=list(topics)):
                for tr in getattr(msg, 'transforms', []):
                    child = tr.child_frame_id.lstrip('/')
                    seen.add(child)
                    if child != frame or tr.header.frame_id.lstrip('/') != parent:
                        continue
                    r, p = tr.transform.rotation, tr.transform.translation
                    times.append(tr.header.stamp.to_sec())
                    poses.append([p.x, p.y, p.z, r.w, r.x, r.y, r.z])
    except TrajectoryError:
        raise
    except Exception as e:  # rosbag raises its own ROSBagException types
        raise TrajectoryError('%s: cannot read the bag (%s)' % (path, e)) from None
    if not times:
        raise TrajectoryError(
            '%s: frame %r: no transform %s -> %s on %s (frames in the bag: %s)'
            % (path, frame, parent, frame, ','.join(topics), ', '.join(sorted(seen)) or 'none'))
    t = np.array(times)
    a = np.array(poses)
    for k in range(len(a)):
        if not np.all(np.isfinite(a[k])):
            _fail(path, 'sample %d of frame %s' % (k + 1, frame), 'not finite')
        n = np.linalg.norm(a[k, 3:])
        if abs(n - 1.0) > UNIT_TOLERANCE:
            _fail(path, 'sample %d of frame %s, rotation' % (k + 1, frame),
                  'not a unit quaternion (|q| = %.6g)' % n)
        if k and t[k] <= t[k - 1]:
            _fail(path, 'sample %d of frame %s, stamp' % (k + 1, frame),
                  'time must increase (t = %.9f after %.9f)' % (t[k], t[k - 1]))
    cuts = [0] + [k for k in range(1, len(t)) if t[k] - t[k - 1] > split_gap] + [len(t)]
    out = []
    base = os.path.splitext(os.path.basename(path))[0]
    for i in range(len(cuts) - 1):
        s, e = cuts[i], cuts[i + 1]
        if e - s < min_samples:
            continue
        q = a[s:e, 3:]
        out.append(Trajectory(name='%s_%s_%03d' % (base, frame, i), t=t[s:e] - t[s],
                              position=a[s:e, :3].copy(),
                              quaternion=q / np.linalg.norm(q, axis=1)[:, None], source=path))
    if not out:
        _fail(path, 'frame %s' % frame, 'no run of at least %d samples' % min_samples)
    return out
