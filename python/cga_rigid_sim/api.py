"""The Python front of the bindings: URDF from text or a file, worlds with keyword options, and a
batch of independent worlds stepped in parallel (doc/python.md)."""
import os

import numpy as np

from ._core import World, load_urdf_file, load_urdf_string, rollout_worlds, step_worlds


def load_urdf(urdf, gravity=None, initial_state=None, lambda_=1.0, relax_inertia=False):
    """A Scene from URDF text (anything whose first non-blank character is '<') or a file path.

    Raises ValueError naming the file (or 'urdf_string'), the link or joint and the rule."""
    text = os.fspath(urdf)
    if text.lstrip().startswith('<'):
        return load_urdf_string(text, 'urdf_string', gravity=gravity,
                                initial_state=initial_state, lambda_=lambda_,
                                relax_inertia=relax_inertia)
    return load_urdf_file(text, gravity=gravity, initial_state=initial_state, lambda_=lambda_,
                          relax_inertia=relax_inertia)


def world_from_urdf(urdf, gravity=None, initial_state=None, lambda_=1.0, relax_inertia=False,
                    **options):
    """A World of a URDF (text or path) with the core's options as keywords: dt, integrator,
    gravity, ground_plane, contact_mu, contact_restitution, contact_sleeping, contact_model,
    threads, world_frame, max_force, max_impulse; initial_state as in doc/initial_state.md."""
    scene = load_urdf(urdf, gravity=gravity, initial_state=initial_state, lambda_=lambda_,
                      relax_inertia=relax_inertia)
    return World(scene, **options)


class Batch:
    """Independent worlds stepped together, in parallel on `threads` threads (0: every core),
    with the GIL released. Each world is stepped by one thread from start to end, so its states
    are bit-identical to stepping it alone."""

    def __init__(self, worlds, threads=0):
        self.worlds = list(worlds)
        self.threads = int(threads)

    def __len__(self):
        return len(self.worlds)

    def __getitem__(self, k):
        return self.worlds[k]

    def step(self, n=1):
        """n steps of every world."""
        step_worlds(self.worlds, n, self.threads)

    def poses(self):
        """(worlds, bodies, 7): every world's root-link poses (worlds with fewer bodies padded
        with NaN)."""
        rows = max((w.poses().shape[0] for w in self.worlds), default=0)
        out = np.full((len(self.worlds), rows, 7), np.nan)
        for k, w in enumerate(self.worlds):
            p = w.poses()
            out[k, :p.shape[0]] = p
        return out

    def rollout(self, samples, steps_per_sample):
        """Steps every world samples × steps_per_sample steps, recording the root-link poses
        before and every steps_per_sample steps: (poses (worlds, samples + 1, bodies, 7),
        ok (worlds,)); a world whose state went non-finite has ok False and NaN from there."""
        return rollout_worlds(self.worlds, [int(steps_per_sample)] * int(samples), self.threads)


World.from_urdf = staticmethod(world_from_urdf)
