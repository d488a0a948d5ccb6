"""Inputs that slipped through (issue 36, part 4), the listed cases and generated ones
(property-based, Hypothesis): every number bounded, every vector normalised with a finite norm, a
mistake one line with a non-zero exit and no traceback.

The scene checks run the parser only (flexbearing.simulation.scene.loads_scene); the command-line
ones go through flexbearing.cli.main.main as `flexbearing` does.
"""
import math

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from flexbearing.cli import main as cli
from flexbearing.common.validation import InputError, require_finite
from flexbearing.simulation.jobs import require_scheduler
from flexbearing.simulation.scene import loads_scene

BASE = """
name = "gen"
[operation]
duration = 0.01
[operation.speed]
phases = [{{kind = "uniform", duration = 0.01, rpm = 10000}}]
[operation.load]
axial_load = {axial}
radial_load = 4e3
radial_direction = {direction}
[output]
sample_interval = {dt}
record = ["cage_speed"]
"""

SETTINGS = settings(max_examples=60, deadline=None, database=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


def scene(axial="55e3", direction="[0.0, 0.0, -1.0]", dt="1e-4"):
    return loads_scene(BASE.format(axial=axial, direction=direction, dt=dt), "gen.toml")


def one_line(err: str) -> str:
    lines = [ln for ln in err.strip().splitlines() if ln.strip()]
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


# ---------------------------------------------------------------- directions

def test_a_direction_with_huge_components_keeps_the_radial_load():
    """[0, 1e200, 1e200]: its norm overflowed to inf and v / inf = 0 removed the radial load."""
    s = scene(direction="[0.0, 1e200, 1e200]")
    _, fy, fz = s.load_table[0, 1:4]
    assert math.hypot(fy, fz) == pytest.approx(4e3, rel=1e-15)
    assert fy == pytest.approx(fz, rel=1e-15) and fy > 0


finite = st.floats(allow_nan=False, allow_infinity=False, width=64)


@SETTINGS
@given(y=finite, z=finite)
def test_every_radial_direction_is_a_unit_vector_or_refused(y, z):
    """Any finite (y, z), subnormal to 1.8e308: the load keeps its magnitude along (y, z)/|(y, z)|,
    or the zero vector is refused with one message naming the field."""
    try:
        s = scene(direction=f"[0.0, {y!r}, {z!r}]")
    except InputError as exc:
        assert y == 0.0 and z == 0.0 and "operation.load.radial_direction" in str(exc)
        return
    _, fy, fz = s.load_table[0, 1:4]
    assert math.hypot(fy, fz) == pytest.approx(4e3, rel=1e-14)
    # the direction itself, compared in a scale-free way: fy·z == fz·y up to round-off
    big = max(abs(y), abs(z))
    assert abs(fy * (z / big) - fz * (y / big)) <= 1e-12 * 4e3


# ---------------------------------------------------------------- numbers

@pytest.mark.parametrize("text", ["1" + "0" * 400, "-" + "9" * 320])
def test_a_toml_integer_beyond_the_float_range_is_one_line(text):
    with pytest.raises(InputError, match=r"operation.load.axial_load = .*digits\) is beyond the range"):
        scene(axial=text)


@SETTINGS
@given(n=st.integers(min_value=-10**400, max_value=10**400))
def test_every_integer_is_a_number_or_one_message(n):
    try:
        v = require_finite("x", n)
    except InputError as exc:
        assert abs(n) > 1e308 and str(exc).startswith("x = ")
    else:
        assert math.isfinite(v)


@pytest.mark.parametrize("dt", ["1e-300", "5e-324", "0.0", "-1e-4", "1e-8"])
def test_a_sample_interval_below_the_bound_is_refused(dt):
    with pytest.raises(InputError, match=r"output.sample_interval = .* outside the allowed range \[1e-07, 0.01\] s"):
        scene(dt=dt)


@SETTINGS
@given(dt=st.floats(min_value=0.0, max_value=1.0, allow_subnormal=True, exclude_min=False))
def test_every_sample_interval_gives_a_bounded_number_of_samples_or_one_message(dt):
    try:
        s = scene(dt=repr(dt))
    except InputError as exc:
        assert "output.sample_interval" in str(exc)
        assert not 1e-7 <= dt <= 0.01
    else:
        assert 2 <= s.n_samples <= 10**5 + 1


# ---------------------------------------------------------------- the command line

@pytest.mark.parametrize("address", ["http://10.0.0.5:8787", "inproc://10.0.0.5/1/2", "tls://h:8786",
                                     "ws://h:8786", "wss://h:8786", "tcp://h", "tcp://:8786", "tcp://h:0",
                                     "tcp://h:99999", "10.0.0.5:8786", "tcp://"])
def test_scheduler_addresses_other_than_tcp_are_refused_at_once(address):
    with pytest.raises(InputError, match=r"--scheduler = .*tcp://HOST:PORT|--scheduler = .*only tcp://"):
        require_scheduler(address)


@SETTINGS
@given(text=st.text(max_size=40))
def test_every_scheduler_text_is_accepted_only_as_tcp_host_port(text):
    try:
        require_scheduler(text)
    except InputError as exc:
        assert "\n" not in str(exc)
    else:
        proto, _, rest = text.partition("://")
        host, _, port = rest.rpartition(":")
        assert proto == "tcp" and host and 1 <= int(port) <= 65535


def test_study_with_a_bad_scheduler_is_one_line_without_waiting(tmp_path, capsys):
    import time
    t0 = time.perf_counter()
    code = cli.main(["study", "scenes/study_axial_load.toml", "-o", str(tmp_path), "--scheduler",
                     "http://localhost:8787", "--quiet"])
    assert code == 2 and time.perf_counter() - t0 < 20
    assert "only tcp://" in one_line(capsys.readouterr().err)


@pytest.mark.parametrize("n", ["1000000000000", "100000", "0", "-3", "6"])
def test_modes_n_modes_out_of_range_is_one_line_before_any_work(n, capsys):
    assert cli.main(["modes", "--n-modes", n, "--quiet"]) == 2
    assert "modes.n_modes" in one_line(capsys.readouterr().err)


@pytest.mark.parametrize("command, suffix, content, fragment", [
    ("modes", ".msh", bytes(range(256)) * 8, "does not start with gmsh's $MeshFormat header"),
    ("modes", ".msh", b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2", "cannot be read as a mesh"),
    ("modes", ".xdmf", b"<?xml version='1.0'?><Xdmf><Domain><Grid><Topology", "reads gmsh .msh files"),
    ("check", ".xdmf", b"<?xml version='1.0'?><Xdmf><Domain><Grid><Topology", "cannot be read as a mesh"),
    ("check", ".xdmf", bytes(range(256)) * 8, "cannot be read as a mesh"),
])
def test_a_binary_or_malformed_mesh_file_is_one_line(tmp_path, capsys, command, suffix, content, fragment):
    f = tmp_path / f"bad{suffix}"
    f.write_bytes(content)
    argv = (["modes", "--mesh", str(f), "--quiet", "--no-classify"] if command == "modes"
            else ["mesh", "--check", str(f)])
    assert cli.main(argv) in (1, 2)
    err = capsys.readouterr().err
    line = one_line(err)
    assert str(f) in line and fragment in line


def test_modes_mesh_on_an_untagged_mesh_is_one_line(tmp_path, capsys):
    """A valid gmsh mesh without physical groups (a unit cube of tetrahedra)."""
    import gmsh
    f = tmp_path / "cube.msh"
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("cube")
        gmsh.model.occ.addBox(0, 0, 0, 0.01, 0.01, 0.01)
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.005)
        gmsh.model.mesh.generate(3)
        gmsh.option.setNumber("Mesh.SaveAll", 1)
        gmsh.write(str(f))
    finally:
        gmsh.finalize()
    assert cli.main(["modes", "--mesh", str(f), "--quiet", "--no-classify", "--degree", "1"]) == 2
    line = one_line(capsys.readouterr().err)
    assert "no physical volume group" in line and str(f) in line


def test_mesh_prints_its_sizes_in_metres(tmp_path, capsys, monkeypatch):
    """`flexbearing mesh --size 0.004` said "size 0.004 mm" for 0.004 m (the meshing itself is
    replaced by stand-ins here: what is checked is the printed line)."""
    import flexbearing.fem_cage.xdmf as X
    import flexbearing.mesh.cage_mesh as CM
    monkeypatch.setattr(CM, "build_cage_mesh", lambda *a, **k: None)
    monkeypatch.setattr(CM, "mesh_quality_of", lambda out: {"quality": {}, "repair": None})
    monkeypatch.setattr(X, "write_mesh_xdmf", lambda out: out.with_suffix(".xdmf"))
    import flexbearing.cli.mesh as M
    monkeypatch.setattr(M, "quality_line", lambda *a: "ok", raising=False)
    assert cli.main(["mesh", "--size", "0.004", "--pocket-size", "0.003", "-o", str(tmp_path / "c.msh")]) == 0
    out = capsys.readouterr().out
    assert "size 0.004 m, pocket size 0.003 m" in out and "mm" not in out.split("(")[1].split(")")[0]


# ---------------------------------------------------------------- the output-size estimate

def test_a_run_that_would_write_more_than_the_limit_stops_before_writing(tmp_path):
    from flexbearing.simulation.results import OutputTooLarge
    from flexbearing.simulation.run import run_scene
    from test_run import fake_backend, fake_scene
    out = tmp_path / "r.h5"
    with pytest.raises(OutputTooLarge, match=r"would write about .* GB .* more than the limit of 1e-06 GB "
                                             r"\(--max-output-size BYTES raises it\)"):
        run_scene(fake_scene(), out, quiet=True, backend=fake_backend(), max_output_bytes=1000)
    assert not out.exists()
    run_scene(fake_scene(), out, quiet=True, backend=fake_backend(), max_output_bytes=1e9)
    assert out.exists()


def test_output_size_estimate_against_free_space(tmp_path, monkeypatch):
    import shutil as sh
    from collections import namedtuple

    from flexbearing.simulation import results
    from flexbearing.simulation.run import run_scene
    from test_run import fake_backend, fake_scene
    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(results.shutil, "disk_usage", lambda p: usage(10**6, 10**6 - 100, 100))
    with pytest.raises(results.OutputTooLarge, match=r"more than the .* GB free in"):
        run_scene(fake_scene(), tmp_path / "r.h5", quiet=True, backend=fake_backend())
    assert sh is not None
