"""report.pdf: the report's page printed by headless Chromium (its print CSS: A4, figures and
table rows not split across pages; flexbearing.analysis.html_page).

Chromium is not a flexbearing dependency (Debian: apt-get install chromium); `flexbearing report
--pdf` asks for it. `chromium --headless` prints the page as the browser's own print dialog
would, with the page's embedded plots, so the PDF is the page a reader sees.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
from pathlib import Path

from flexbearing.common.validation import InputError

BROWSERS = ("chromium", "chromium-browser", "google-chrome")
NEEDS = "headless Chromium (Debian: apt-get install chromium)"


def chromium() -> str | None:
    """The Chromium executable on PATH, or None."""
    return next((p for p in map(shutil.which, BROWSERS) if p), None)


def require_chromium() -> str:
    exe = chromium()
    if exe is None:
        raise InputError(f"--pdf needs {NEEDS}; report.html prints to PDF from any browser")
    return exe


def _headless(exe: str, args: list[str], timeout: float) -> subprocess.CompletedProcess:
    """Chromium headless in a throw-away profile (root needs --no-sandbox; no GPU on a server)."""
    with tempfile.TemporaryDirectory(prefix="flexbearing-chromium-") as profile:
        cmd = [exe, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
               "--no-first-run", "--no-pdf-header-footer", "--print-to-pdf-no-header",
               f"--user-data-dir={profile}"] + args
        return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout,
                              env={**os.environ, "HOME": profile})


def print_pdf(html, pdf=None, timeout: float = 300.0) -> Path:
    """<html>.pdf (or `pdf`) of a report page; returns its path."""
    exe = require_chromium()
    html = Path(html).resolve()
    pdf = Path(pdf).resolve() if pdf else html.with_suffix(".pdf")
    out = _headless(exe, [f"--print-to-pdf={pdf}", html.as_uri()], timeout)
    if not pdf.is_file() or pdf.stat().st_size == 0:
        raise RuntimeError(f"chromium did not print {html} (exit status {out.returncode}): {out.stderr[-500:]}")
    return pdf


def screenshot(html, png, size=(1280, 900), timeout: float = 300.0) -> Path:
    """A PNG of the page's first screen (window `size` in CSS pixels)."""
    exe = require_chromium()
    png = Path(png).resolve()
    out = _headless(exe, [f"--screenshot={png}", f"--window-size={size[0]},{size[1]}", Path(html).resolve().as_uri()],
                    timeout)
    if not png.is_file() or png.stat().st_size == 0:
        raise RuntimeError(f"chromium took no screenshot of {html} (exit status {out.returncode}): {out.stderr[-500:]}")
    return png
