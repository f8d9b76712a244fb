"""System identification from measured motion: read pose trajectories (CSV, rosbag of tf), score
simulations against them as the literature does, fit parameters with cross-validation, on Dask
(doc/fitting.md). The command is `fit` (scripts/fit; python3 -m cga_rigid_sim.sysid)."""
