"""The package travels: `pip install .` into a fresh virtual environment that sees Debian's packages
(--system-site-packages) installs nothing but flexbearing (every dependency it declares is there
already; --no-index makes a missing one an error instead of a download), puts one top-level name,
`flexbearing`, into site-packages, and the installed `flexbearing` command runs a 5 ms scene from a
folder outside the source tree (so nothing is imported from it)."""
import os
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _scene_5ms(folder: Path) -> Path:
    """The paper's steady rigid scene, 5 ms long (its duration and its one speed phase's)."""
    text = (ROOT / "scenes" / "paper_steady_rigid.toml").read_text()
    short = text.replace("duration = 0.6 ", "duration = 0.005 ").replace("duration = 0.6,", "duration = 0.005,")
    assert tomllib.loads(short)["operation"]["duration"] == 0.005
    p = folder / "steady_5ms.toml"
    p.write_text(short)
    return p


def installed_top_level(site: Path) -> set[str]:
    """Top-level names the flexbearing distribution installed (from its RECORD)."""
    record = next(site.glob("flexbearing-*.dist-info")) / "RECORD"
    names = set()
    for row in record.read_text().splitlines():
        top = row.split(",")[0].split("/")[0]
        if not top.endswith(".dist-info") and not top.startswith(".."):
            names.add(top)
    return names


@pytest.mark.slow
def test_pip_install_into_a_fresh_venv_gives_a_working_command(tmp_path):
    src = tmp_path / "src"          # a copy: a build writes build/ and *.egg-info beside the sources
    shutil.copytree(ROOT, src, ignore=shutil.ignore_patterns(".venv", ".git", "out", "cache", "build",
                                                             "*.egg-info", "__pycache__", "benchmarks", "tests"))
    venv = tmp_path / "venv"
    subprocess.run([sys.executable if "venv" not in sys.prefix else "/usr/bin/python3", "-m", "venv",
                    "--system-site-packages", str(venv)], check=True)
    pip = subprocess.run([str(venv / "bin" / "python"), "-m", "pip", "install", "--no-index",
                          "--no-build-isolation", str(src)], capture_output=True, text=True)
    assert pip.returncode == 0, pip.stdout + pip.stderr
    # nothing but flexbearing was installed (every declared dependency came from Debian)
    assert "Successfully installed flexbearing-" in pip.stdout, pip.stdout
    assert pip.stdout.split("Successfully installed")[1].split() == [f"flexbearing-{_version()}"]
    site = next((venv / "lib").glob("python3*/site-packages"))
    assert installed_top_level(site) == {"flexbearing"}
    assert (site / "flexbearing" / "scenes" / "paper_unsteady.toml").is_file()
    run_dir = tmp_path / "elsewhere"
    run_dir.mkdir()
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba"), "PYTHONPATH": ""}
    exe = str(venv / "bin" / "flexbearing")
    v = subprocess.run([exe, "--version"], capture_output=True, text=True, cwd=run_dir, env=env)
    assert v.returncode == 0 and v.stdout.strip() == f"flexbearing {_version()}", v.stdout + v.stderr
    where = subprocess.run([str(venv / "bin" / "python"), "-c", "import flexbearing; print(flexbearing.__file__)"],
                           capture_output=True, text=True, cwd=run_dir, env=env)
    assert where.stdout.strip().startswith(str(site)), where.stdout
    scene = _scene_5ms(run_dir)
    r = subprocess.run([exe, "run", str(scene), "-o", "r.h5", "--quiet"], capture_output=True, text=True,
                       cwd=run_dir, env=env)
    assert r.returncode == 0, r.stdout + r.stderr
    import h5py
    with h5py.File(run_dir / "r.h5", "r") as f:
        assert f.attrs["status"] == "complete"
        assert f["outputs/time"].shape == (51,)       # t = 0, 0.1 ms, ..., 5 ms
        assert f.attrs["program_version"] == _version()


def _version() -> str:
    return tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
