"""A run of a scene: the scene file and its checks, the run driver and its backend, the streamed
results file, progress, the wall-time budget, the physical checks of a finished run, and the one
way to run independent jobs (Dask). Imports the physics core (common … coupling), never above."""
