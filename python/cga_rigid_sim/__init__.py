"""cga_rigid_sim from Python: the core's worlds (loaded from URDF, stepped, read as numpy arrays)
and batches of independent worlds stepped in parallel (doc/python.md).

    import cga_rigid_sim as cs
    world = cs.world_from_urdf('cube.urdf', dt=1e-3, ground_plane={'height': 0.0})
    world.step(1000)
    world.poses()      # (bodies, 7): x, y, z, qw, qx, qy, qz of each root link

The fitting tools are in cga_rigid_sim.sysid (the `fit` command, doc/fitting.md).
"""
from pkgutil import extend_path

# The package lives in two folders: python/cga_rigid_sim (these sources) and the devel space's
# (the compiled _core, the messages); a process that finds the sources first (a Dask worker
# started with this process's sys.path) must still find the other.
__path__ = extend_path(__path__, __name__)  # noqa: F821 (set by the import system)

from ._core import Scene, World, load_urdf_file, load_urdf_string, rollout_worlds, step_worlds
from .api import Batch, load_urdf, world_from_urdf

__all__ = ['Scene', 'World', 'Batch', 'load_urdf', 'load_urdf_file', 'load_urdf_string',
           'world_from_urdf', 'step_worlds', 'rollout_worlds']
