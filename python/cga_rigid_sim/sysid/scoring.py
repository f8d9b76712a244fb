"""Where a measured run is simulated from, and how far a simulation is from it: the protocol of
Acosta, Yang and Posa, "Validating robotics simulators on real-world impacts" (IEEE RA-L 2022),
written out in doc/fitting.md#scoring.

- Start: 3 samples before the centre first comes within the body's bounding radius of the
  surface (before that the body flies free and the simulator has nothing to show).
- Starting state: the measured pose there; its linear velocity from a parabola under gravity
  fitted through the free-flight samples before contact (the differenced velocities of the
  data are noisy), its angular velocity the mean of the free-flight samples' relative rotations
  (exact for a body torque-free with equal principal moments, such as a cube).
- Error per sample: position |p_data − p_sim| over the body's size, and rotation the angle of
  R_data R_simᵀ; each averaged over the run from the start; then mean and standard deviation
  over runs.
"""
from dataclasses import dataclass

import numpy as np

START_BEFORE_CONTACT = 3      # samples, as the paper
FREE_FLIGHT_WINDOW = 12       # free-flight samples used for the starting velocity at most


def quat_mul(a, b):
    """Hamilton products of (..., 4) quaternions w, x, y, z."""
    aw, ax, ay, az = np.moveaxis(a, -1, 0)
    bw, bx, by, bz = np.moveaxis(b, -1, 0)
    return np.stack([aw * bw - ax * bx - ay * by - az * bz,
                     aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw], axis=-1)


def quat_conj(q):
    return q * np.array([1.0, -1.0, -1.0, -1.0])


def quat_rotate(q, v):
    """Rotates (..., 3) vectors by unit quaternions (..., 4)."""
    qv = np.concatenate([np.zeros(v.shape[:-1] + (1,)), v], axis=-1)
    return quat_mul(quat_mul(q, qv), quat_conj(q))[..., 1:]


def rotation_angle(qa, qb):
    """The angle of qa qb⁻¹ (rad), up to the quaternions' sign: 2 atan2(|vec|, |w|) (atan2,
    not acos: acos loses half the digits near 0)."""
    d = quat_mul(qa, quat_conj(qb))
    return 2.0 * np.arctan2(np.linalg.norm(d[..., 1:], axis=-1), np.abs(d[..., 0]))


def rotation_vector(q):
    """log of unit quaternions (..., 4) as rotation vectors (angle × axis), w made ≥ 0."""
    q = np.where(q[..., :1] < 0, -q, q)
    s = np.linalg.norm(q[..., 1:], axis=-1)
    angle = 2.0 * np.arctan2(s, q[..., 0])
    # angle / s → 2 as s → 0 (sin(θ/2) ≈ θ/2)
    scale = np.where(s > 1e-12, angle / np.where(s > 1e-12, s, 1.0), 2.0)
    return q[..., 1:] * scale[..., None]


@dataclass
class Start:
    index: int                 # the sample the simulation starts from
    position: np.ndarray       # (3,) m
    quaternion: np.ndarray     # (4,) w, x, y, z
    velocity: np.ndarray       # (3,) centre, world, m/s
    omega_world: np.ndarray    # (3,) rad/s, world axes


def find_start(traj, bounding_radius, surface_height=0.0, gravity=(0.0, 0.0, -9.81)):
    """The starting sample and state of a run (module docstring)."""
    z = traj.position[:, 2] - surface_height
    below = np.nonzero(z < bounding_radius)[0]
    first = int(below[0]) if below.size else len(z) - 1
    s = max(first - START_BEFORE_CONTACT, 0)
    lo = max(first - FREE_FLIGHT_WINDOW, 0)
    idx = np.arange(lo, max(first, s + 1))
    if len(idx) < 3:  # too few free samples: differences at the start
        idx = np.arange(s, min(s + 3, len(z)))
    t = traj.t[idx]
    ts = traj.t[s]
    g = np.asarray(gravity, dtype=float)
    # x(t) = a + b (t − ts) + ½ g (t − ts)²: least squares for a, b per axis.
    A = np.stack([np.ones_like(t), t - ts], axis=1)
    rhs = traj.position[idx] - 0.5 * np.outer((t - ts) ** 2, g)
    coef, *_ = np.linalg.lstsq(A, rhs, rcond=None)
    velocity = coef[1]
    # ω in body axes from consecutive rotations q_k⁻¹ q_{k+1}, averaged; then to world axes.
    q = traj.quaternion[idx]
    rel = quat_mul(quat_conj(q[:-1]), q[1:])
    dt = np.diff(t)
    omega_body = (rotation_vector(rel) / dt[:, None]).mean(axis=0)
    qs = traj.quaternion[s]
    return Start(index=s, position=traj.position[s].copy(), quaternion=qs.copy(),
                 velocity=velocity, omega_world=quat_rotate(qs, omega_body))


def run_errors(traj, start, sim_positions, sim_quaternions, size):
    """Per-sample position errors (fraction of `size`) and rotation errors (rad) from the start
    on, for simulated root-link poses at the samples start.index … N−1."""
    p = traj.position[start.index:]
    q = traj.quaternion[start.index:]
    n = min(len(p), len(sim_positions))
    pos = np.linalg.norm(p[:n] - sim_positions[:n], axis=1) / size
    rot = rotation_angle(q[:n], sim_quaternions[:n])
    return pos, rot


def turn_vectors(quats):
    """The rotation vectors (world axes) of each sample's attitude from the one before,
    q[k+1] q[k]⁻¹: the turn over each interval, rad (times the rate: ω)."""
    return rotation_vector(quat_mul(quats[1:], quat_conj(quats[:-1])))


def pose_errors(a, b, size):
    """The two mean errors of poses b (n, 7: x, y, z, qw, qx, qy, qz) against poses a: position
    as a fraction of `size`, and the rotation angle (rad)."""
    pos = np.linalg.norm(a[:, :3] - b[:, :3], axis=1).mean() / size
    return float(pos), float(rotation_angle(a[:, 3:], b[:, 3:]).mean())


def summarize(per_run_pos, per_run_rot):
    """Mean and standard deviation over runs of the per-run mean errors (position as a fraction
    of size, rotation in degrees)."""
    pos = np.asarray(per_run_pos, dtype=float)
    rot = np.degrees(np.asarray(per_run_rot, dtype=float))
    return {'runs': int(pos.size), 'position_mean': float(pos.mean()),
            'position_std': float(pos.std()), 'rotation_mean_deg': float(rot.mean()),
            'rotation_std_deg': float(rot.std())}
