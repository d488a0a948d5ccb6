"""The report's page and ParaView scene as a reader sees them: headless Chromium renders report.html
(every image loads, the first screen is not blank, the PDF prints), and a fresh pvpython loads the
saved bearing.pvsm: its colour bar is in MPa over [0, the largest von Mises maximum the run recorded
in the window] and its screenshot is not blank; --movie writes a movie. Slow: these start Chromium
and ParaView (`make test-all` installs them: Makefile, VIEWER_PACKAGES)."""
from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

from flexbearing.analysis import report
from flexbearing.analysis.paraview_state import pvpython_command
from flexbearing.analysis.pdf import _headless, print_pdf, require_chromium, screenshot

from test_field_export import fake_run
from test_report import write_run

pytestmark = pytest.mark.slow


def _drawn_share(png: Path, background=(1.0, 1.0, 1.0)) -> float:
    """Share of the pixels that differ from the background colour."""
    import matplotlib.image as mpimg
    img = mpimg.imread(png)[..., :3]
    return float(np.mean(np.any(np.abs(img - np.asarray(background)) > 0.02, axis=-1)))


def test_report_page_renders_in_chromium_with_every_image(tmp_path):
    out = report.write_report(write_run(tmp_path / "run.h5"), tmp_path / "rep")
    html = out["html"]
    n_img = html.read_text().count("<img ")
    assert n_img == len(out["plots"]) > 0
    # a copy of the page that writes, once loaded, how many of its images decoded into the DOM
    probe = html.with_name("probe.html")
    probe.write_text(html.read_text().replace("</body>", (
        "<script>window.addEventListener('load', () => document.body.setAttribute('data-images', "
        "[...document.images].filter(i => i.complete && i.naturalWidth > 0).length + '/' + "
        "document.images.length));</script></body>")))
    dom = _headless(require_chromium(), ["--virtual-time-budget=10000", "--dump-dom", probe.as_uri()], 120).stdout
    m = re.search(r'data-images="(\d+)/(\d+)"', dom)
    assert m, dom[:500]
    assert int(m.group(1)) == int(m.group(2)) == n_img
    assert "<h2>Summary</h2>" in dom
    png = screenshot(html, tmp_path / "first_screen.png")
    assert _drawn_share(png) > 0.05                   # text and the summary table, not a blank page
    pdf = print_pdf(html)
    assert pdf.read_bytes()[:5] == b"%PDF-" and pdf.stat().st_size > 10_000


def _pvpython_check(state: Path, png: Path) -> dict:
    """Load a saved state in a fresh pvpython; the colour map's range and bar title, a screenshot."""
    script = png.with_suffix(".py")
    script.write_text(f"""
import json, os
from paraview import simple as pv
pv.LoadState({str(state)!r})
view = pv.GetActiveView()
lut = pv.GetColorTransferFunction("von_mises_MPa")
xs = list(lut.RGBPoints[0::4])
bar = pv.GetScalarBar(lut, view)
pv.SaveScreenshot({str(png)!r}, view, ImageResolution=[800, 500])
print("CHECK " + json.dumps({{"range": [xs[0], xs[-1]], "title": bar.Title, "time": view.ViewTime}}))
os._exit(0)
""")
    for _ in range(3):      # pvpython under xvfb-run now and then aborts opening its window (paraview_state.ATTEMPTS)
        out = subprocess.run(pvpython_command() + [str(script)], capture_output=True, text=True, timeout=600)
        line = next((l for l in out.stdout.splitlines() if l.startswith("CHECK ")), None)
        if line:
            break
    assert line, out.stdout + out.stderr
    return json.loads(line[6:])


def test_paraview_state_shows_the_recorded_maximum_in_mpa(tmp_path):
    if pvpython_command() is None:
        pytest.fail("pvpython (and xvfb without a display) must be installed: make test-all installs them")
    run, *_ = fake_run(tmp_path, n=21)
    out = report.write_report(run, tmp_path / "rep", series="0:0.02:2", movie=True)
    pv = out["paraview"]
    state = Path(pv["state"])
    assert state.is_file() and Path(pv["movie"]).stat().st_size > 10_000
    meta = json.loads((tmp_path / "rep" / "series.json").read_text())
    recorded = max(f["recorded_von_mises_max"] for f in meta["cage"]["frames"])
    check = _pvpython_check(state, tmp_path / "state.png")
    assert check["title"] == "von Mises stress (MPa)"
    assert check["range"][0] == 0.0
    assert check["range"][1] == pytest.approx(recorded * 1e-6, rel=1e-12)
    assert _drawn_share(tmp_path / "state.png") > 0.02
    assert "bearing.pvsm" in out["report"].read_text()
