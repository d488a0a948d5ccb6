"""The ParaView scene of a report's series: bearing.pvsm (and on request a movie), through pvpython.

`write_paraview_scene` runs flexbearing/analysis/paraview_scene.py, which builds the scene from
the series files (that module's doc says what it shows), with ParaView's own Python; under
`xvfb-run` when there is no display. ParaView is not a flexbearing dependency (Debian: apt-get
install paraview xvfb): without pvpython the series files are still written and open in any
ParaView, and only the state file and the movie are missing.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

from flexbearing.common.validation import InputError

SCENE_SCRIPT = Path(__file__).with_name("paraview_scene.py")
STATE = "bearing.pvsm"
MOVIE = "bearing.avi"            # FFMPEG (ParaView 5.11 of Debian 12 has it); .ogv: Ogg Theora
SETTINGS = "paraview_scene.json"
# pvpython under xvfb-run now and then aborts creating its window (vtkXOpenGLRenderWindow, SIGABRT;
# once in the seven starts while this was written): a second start succeeds
ATTEMPTS = 3
NEEDS = "ParaView's pvpython (Debian: apt-get install paraview xvfb)"


def pvpython_command() -> list[str] | None:
    """How to start pvpython here: itself with a display, under `xvfb-run -a` without one; None
    when ParaView (or, without a display, xvfb) is not installed."""
    pv = shutil.which("pvpython")
    if pv is None:
        return None
    if os.environ.get("DISPLAY"):
        return [pv]
    xvfb = shutil.which("xvfb-run")
    return [xvfb, "-a", pv] if xvfb else None


def write_paraview_scene(folder, movie: bool = False, png=None, time: float | None = None,
                         size=(1600, 1000), timeout: float = 3600.0, out=None) -> dict:
    """<out>/bearing.pvsm (and bearing.avi with `movie`, a screenshot `png`) of the series in
    `folder` (flexbearing.analysis.field_export.write_series); out: where the state, the movie and
    their settings (paraview_scene.json) are written, default `folder` (the report writes them in
    its staging folder, flexbearing.common.safe_files.OutputPlan, the state naming the series
    files where they stay). Returns the scene's facts: "time" shown (s), "colour_range_mpa",
    "recorded_max_mpa", "state", "png", "movie" (paths)."""
    cmd = pvpython_command()
    if cmd is None:
        raise InputError(f"the ParaView state and movie need {NEEDS}; the series files are written "
                         f"and open in ParaView without it")
    folder = Path(folder).resolve()
    dest = folder if out is None else Path(out).resolve()
    settings = {"folder": str(folder), "state": str(dest / STATE),
                "png": None if png is None else str(Path(png).resolve()),
                "movie": str(dest / MOVIE) if movie else None, "time": time, "size": list(size)}
    (dest / SETTINGS).write_text(json.dumps(settings, indent=1) + "\n")
    for attempt in range(ATTEMPTS):
        out = subprocess.run(cmd + [str(SCENE_SCRIPT), str(dest / SETTINGS)], capture_output=True,
                             text=True, timeout=timeout)
        line = next((l for l in out.stdout.splitlines() if l.startswith("FLEXBEARING_PARAVIEW ")), None)
        if line is not None:
            break
    if line is None:
        tail = "\n".join((out.stdout + out.stderr).strip().splitlines()[-8:])
        raise RuntimeError(f"pvpython did not build the scene in {ATTEMPTS} starts (exit status "
                           f"{out.returncode}):\n{tail}")
    return json.loads(line.split(" ", 1)[1])
