"""A user's mistake gives one clear line and a non-zero exit code, never a traceback, and no run
damages a file: the defects of issue 22 (item 2), each reproduced on the code before its fix.

The runs use the fake physics backend of tests/test_run.py (streaming and files are what is
tested); the command line is driven through flexbearing.cli.main.main, which is what `flexbearing` calls.
"""
import hashlib
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import h5py
import pytest

from flexbearing.common.validation import InputError
from flexbearing.cli import main as cli
from flexbearing.simulation.results import read_checkpoint
from flexbearing.simulation.run import RunInterrupted, run_scene
from flexbearing.simulation.scene import load_scene, loads_scene
from test_run import SCENE, fake_backend, fake_scene

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

TINY = """
name = "tiny"
[operation]
duration = 0.0002
[operation.speed]
phases = [{kind = "uniform", duration = 0.0002, rpm = 10000}]
[operation.load]
axial_load = 55e3
[output]
sample_interval = 1e-4
record = ["cage_speed"]
"""


def run_cli(argv, capsys):
    """(exit code, stderr) of `flexbearing argv`; a traceback would escape as an exception here."""
    code = cli.main([str(a) for a in argv])
    err = capsys.readouterr().err
    return code, err


def one_line(err: str) -> str:
    lines = [ln for ln in err.strip().splitlines() if ln.strip()]
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


@pytest.fixture
def tiny(tmp_path):
    p = tmp_path / "tiny.toml"
    p.write_text(TINY)
    return p


def digest(path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


# ---------------------------------------------------------------- the results file's lock

def test_second_force_run_refuses_a_file_another_process_writes(tmp_path, capsys):
    """Before: the second `run --force` truncated the file (0 bytes) and both runs died. Now it is
    refused before it touches the file, and the first run finishes a complete, valid file."""
    out = tmp_path / "run.h5"
    scene_file = tmp_path / "fake.toml"
    scene_file.write_text(SCENE)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(HERE), str(ROOT)]))
    # the first run holds at its checkpoint of >= 14 samples until the checks below are done (on a
    # loaded machine it could otherwise finish before them, and --resume would find a complete file)
    first = subprocess.Popen([sys.executable, str(HERE / "test_run.py"), str(out), "14"], stdout=subprocess.PIPE,
                             stdin=subprocess.PIPE, text=True, env=env)
    try:
        for line in first.stdout:                    # the first run is writing (a checkpoint is on disk)
            if line.startswith("CHECKPOINT") and int(line.split()[1]) >= 14:
                break
        else:
            pytest.fail(f"the first run ended early (rc {first.wait()})")
        size = out.stat().st_size
        assert size > 0
        # the library refuses ...
        with pytest.raises(InputError, match="being written by another flexbearing process"):
            run_scene(fake_scene(), out, force=True, quiet=True, backend=fake_backend())
        assert out.stat().st_size >= size            # not truncated (the first run may have grown it)
        # ... and so does the command line, with one line and exit code 2
        code, err = run_cli(["run", scene_file, "-o", out, "--force"], capsys)
        assert code == 2 and "being written by another flexbearing process" in one_line(err)
        code, err = run_cli(["run", scene_file, "-o", out, "--resume"], capsys)
        assert code == 2 and "being written by another flexbearing process" in one_line(err)
        first.stdin.write("go on\n")
        first.stdin.close()
        assert first.wait(timeout=120) == 0          # the first run was not disturbed
    finally:
        if first.poll() is None:
            first.kill()
    with h5py.File(out, "r") as f:
        assert f.attrs["status"] == "complete"
        assert f["outputs/time"].shape[0] == fake_scene().n_samples
        assert read_checkpoint(f)["n_samples"] == fake_scene().n_samples


def test_lock_is_released_after_a_run_and_a_failed_setup_leaves_no_empty_file(tmp_path):
    out = tmp_path / "run.h5"
    run_scene(fake_scene(), out, quiet=True, backend=fake_backend())
    run_scene(fake_scene(), out, force=True, quiet=True, backend=fake_backend())   # the claim was released

    def broken(*a, **k):
        raise RuntimeError("model cannot be built")
    fresh = tmp_path / "fresh.h5"
    with pytest.raises(RuntimeError):
        run_scene(fake_scene(), fresh, quiet=True, backend=fake_backend(build_model=broken))
    assert not fresh.exists()


# ---------------------------------------------------------------- the scene's name

@pytest.mark.parametrize("name", ["../x", "a/b", "/tmp/evil", "..", "a\\b", "x\ny", " "])
def test_scene_name_cannot_leave_the_output_folder(name):
    """Before: name = "../x" wrote out/../x.h5 (and an absolute name anywhere)."""
    text = TINY.replace('name = "tiny"', f"name = {json.dumps(name)}")   # a TOML basic string
    with pytest.raises(InputError, match="name"):
        loads_scene(text, "s.toml")


def test_plain_scene_names_are_accepted():
    for name in ("paper_steady", "case 1", "run-2.b", "café"):
        assert loads_scene(TINY.replace('"tiny"', f'"{name}"')).name == name


# ---------------------------------------------------------------- one line instead of a traceback

@pytest.mark.parametrize("content", [b'name = "caf\xe9"\n', bytes(range(256)) * 4],
                         ids=["latin-1", "binary"])
def test_scene_file_that_is_not_utf8(tmp_path, capsys, content):
    """Before: UnicodeDecodeError traceback, exit 1."""
    p = tmp_path / "s.toml"
    p.write_bytes(content)
    code, err = run_cli(["run", p, "-o", tmp_path / "r.h5"], capsys)
    assert code == 2 and "is not UTF-8 text" in one_line(err) and str(p) in err


# a zero-byte file is what a run killed before HDF5 wrote its first byte leaves under its claim:
# since issue 36 --resume starts it over (tests/test_fault_injection.py)
@pytest.mark.parametrize("content", [b"hello\n", b"\x89HDF\r\n\x1a\n" + b"\0" * 50,
                                     bytes(range(256)) * 20], ids=["text", "truncated", "garbage"])
def test_resume_of_a_file_that_is_not_a_results_file(tmp_path, capsys, tiny, content):
    """Before: OSError traceback (text, garbage, truncated). Now: one line, exit 2, the file byte
    for byte unchanged."""
    out = tmp_path / "r.h5"
    out.write_bytes(content)
    code, err = run_cli(["run", tiny, "-o", out, "--resume"], capsys)
    line = one_line(err)
    assert code == 2 and str(out) in line and "cannot be resumed" in line
    assert out.read_bytes() == content


def test_truncated_results_file(tmp_path, capsys, tiny):
    """A real results file cut in half (a full disk, a copy stopped): refused, untouched."""
    out = tmp_path / "r.h5"
    run_scene(fake_scene(), out, quiet=True, backend=fake_backend())
    data = out.read_bytes()[: out.stat().st_size // 2]
    out.write_bytes(data)
    code, err = run_cli(["run", tiny, "-o", out, "--resume"], capsys)
    assert code == 2 and "cannot be resumed" in one_line(err)
    assert out.read_bytes() == data


def test_output_paths_that_cannot_be_written(tmp_path, capsys, tiny):
    """Before: FileExistsError / FileNotFoundError / IsADirectoryError tracebacks."""
    a_file = tmp_path / "plain.txt"
    a_file.write_text("x")
    code, err = run_cli(["run", tiny, "-o", a_file / "sub" / "r.h5"], capsys)
    assert code == 2 and f"{a_file} is a file, not a folder" in one_line(err)
    code, err = run_cli(["run", tiny, "-o", "/proc/flexbearing_test.h5"], capsys)
    assert code == 2 and "/proc/flexbearing_test.h5 cannot be written" in one_line(err)
    folder = tmp_path / "folder.h5"
    folder.mkdir()
    code, err = run_cli(["run", tiny, "-o", folder, "--force"], capsys)
    assert code == 2 and "is a directory" in one_line(err)
    assert folder.is_dir()


def test_read_only_folder(tmp_path, capsys, tiny):
    """A folder the user may not write to (as root, whom permissions do not stop: sysfs, which
    refuses new files to everyone)."""
    if os.geteuid() == 0:
        target = Path("/sys/flexbearing_test.h5")
    else:
        ro = tmp_path / "ro"
        ro.mkdir()
        ro.chmod(0o555)
        target = ro / "r.h5"
    code, err = run_cli(["run", tiny, "-o", target], capsys)
    assert code == 2 and f"{target} cannot be written: Permission denied" in one_line(err)
    assert not target.exists()


def test_ctrl_c_during_setup(tmp_path, capsys, tiny, monkeypatch):
    """Before: a KeyboardInterrupt traceback from the model build. Now: one line and exit 130
    (the run's own Ctrl-C code), no empty file left."""
    import flexbearing.simulation.run

    def interrupted(scene):
        raise KeyboardInterrupt
    monkeypatch.setattr(flexbearing.simulation.run, "default_backend", interrupted)
    out = tmp_path / "r.h5"
    code, err = run_cli(["run", tiny, "-o", out], capsys)
    assert code == 130 and "interrupted during setup" in err and "Traceback" not in err
    assert not out.exists()
    with pytest.raises(RunInterrupted, match="during setup"):
        run_scene(load_scene(tiny), out, quiet=True)


def test_real_ctrl_c_during_setup(tmp_path):
    """The same with a real SIGINT to a `flexbearing run` process while it is inside its setup:
    exit 130, one line, no traceback, no file. The process announces that it has entered the
    setup (the initial-state solve, wrapped to print SETUP and wait) and the signal is sent then,
    so the test does not depend on how long the setup takes on a loaded or a quiet machine (a
    fixed 1 s delay let a fast setup finish first)."""
    import signal
    scene = tmp_path / "tiny.toml"
    scene.write_text(TINY)
    out = tmp_path / "tiny.h5"
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    # SIGINT back to Python's handler: a child of a background shell (nohup, CI) inherits it ignored
    code = ("import signal, sys, time; signal.signal(signal.SIGINT, signal.default_int_handler)\n"
            "from flexbearing.cli import main as cli; from flexbearing.multibody import initial; "
            "solve = initial.initial_state\n"
            "def slow_initial_state(*a, **k):\n"
            "    print('SETUP', flush=True); time.sleep(60); return solve(*a, **k)\n"
            "initial.initial_state = slow_initial_state\n"
            f"sys.exit(cli.main(['run', {str(scene)!r}, '-o', {str(out)!r}, '--quiet']))")
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env=env)
    assert proc.stdout.readline().strip() == "SETUP"
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "Traceback" not in err and "interrupted" in one_line(err)
    assert not out.exists()


# ---------------------------------------------------------------- the load, --resume/--force, --frames

def test_missing_load_is_refused_and_zero_load_is_explicit():
    """Before: a scene without [operation.load] ran with zero load without a word."""
    no_load = TINY.replace("[operation.load]\naxial_load = 55e3\n", "")
    with pytest.raises(InputError, match="operation.load is missing"):
        loads_scene(no_load)
    only_impact = TINY.replace("axial_load = 55e3", "[[operation.load.impacts]]\nt_start = 0.0\n"
                                                    "duration = 1e-4\nmagnitude = 1e3")
    with pytest.raises(InputError, match="no static load"):
        loads_scene(only_impact)
    zero = loads_scene(TINY.replace("axial_load = 55e3", "axial_load = 0"))
    assert zero.load_table[:, 1:].max() == 0.0


def test_resume_and_force_together_are_refused(tmp_path, capsys, tiny):
    """Before: accepted silently (and the run restarted from t = 0)."""
    out = tmp_path / "r.h5"
    run_scene(fake_scene(), out, quiet=True, backend=fake_backend())
    before = digest(out)
    code, err = run_cli(["run", tiny, "-o", out, "--resume", "--force"], capsys)
    assert code == 2 and "exclude each other" in one_line(err)
    assert digest(out) == before


def test_report_frames_that_are_not_times(tmp_path, capsys):
    """Before: `report --frames abc` exited 0 having written no von Mises frames."""
    run = tmp_path / "r.h5"
    run_scene(fake_scene(), run, quiet=True, backend=fake_backend())
    out = tmp_path / "rep"
    code, err = run_cli(["report", run, "-o", out, "--frames", "abc"], capsys)
    assert code == 2 and "--frames = 'abc'" in one_line(err)
    assert not out.exists()                            # refused before anything was written
    code, err = run_cli(["report", run, "-o", out, "--frames", "0.01"], capsys)
    assert code == 2 and "no flexible-cage field" in one_line(err)


# ---------------------------------------------------------------- README and --help

def _readme_commands() -> dict[str, set[str]]:
    """{command: options} from the usage lines of the command reference, docs/commands.md (moved
    there from README's "## Commands" table): every `flexbearing <command> ...` line of its plain
    code blocks, the options being the -x / --xyz words."""
    text = (ROOT / "docs" / "commands.md").read_text()
    found: dict[str, set[str]] = {}
    for block in re.findall(r"^```\n(.*?)^```", text, re.S | re.M):
        for usage in block.splitlines():
            words = usage.split()
            cmd = " ".join(words[1:3]) if words[1] == "validate" else words[1]
            found.setdefault(cmd, set()).update(re.findall(r"(?<![\w-])(--?[a-z][a-z0-9-]*)", usage))
    return found


def _parser_options() -> dict[str, list[set[str]]]:
    """{command: [option strings of each of its options]} from the argparse parsers (a nested
    command such as `validate slip-rate` by its two words)."""
    import argparse
    out = {}
    for name, p in _subparsers(cli.build_parser()).items():
        nested = [a for a in p._actions if isinstance(a, argparse._SubParsersAction)]
        for cmd, sp in ([(f"{name} {n}", s) for n, s in nested[0].choices.items()] if nested else [(name, p)]):
            out[cmd] = [set(a.option_strings) for a in sp._actions
                        if a.option_strings and not {"-h", "--help"} & set(a.option_strings)]
    return out


def test_readme_and_help_list_the_same_options():
    """Every option of every command's --help is in README's Commands table (by one of its names,
    e.g. -o for -o/--output), and README names no option --help does not have (before: run --force,
    report -o/--settle/..., quasi-static --friction-share/--no-gyroscopic, validate's options and
    the demo command were missing)."""
    readme, parser = _readme_commands(), _parser_options()
    assert sorted(readme) == sorted(parser), "commands in README vs --help"
    for cmd, actions in parser.items():
        missing = [sorted(a) for a in actions if not a & readme[cmd]]
        unknown = sorted(readme[cmd] - set().union(*actions)) if actions else sorted(readme[cmd])
        assert not missing and not unknown, (cmd, "not in README:", missing, "not in --help:", unknown)


def test_every_size_option_is_in_metres(capsys):
    """Before: `mesh --size` and `modes --size` took mm, `reduce --size` m."""
    parser = cli.build_parser()
    for argv in (["mesh", "--size", "4"], ["modes", "--size", "4"], ["reduce", "--size", "4"],
                 ["calibrate-cage", "--pocket-size", "8"]):
        with pytest.raises(SystemExit) as e:
            parser.parse_args(argv)
        assert e.value.code == 2 and "sizes are in metres" in capsys.readouterr().err
    for cmd in ("mesh", "modes", "reduce", "calibrate-cage"):
        args = parser.parse_args([cmd, "--size", "4e-3", "--pocket-size", "2e-3"])
        assert (args.size, args.pocket_size) == (4e-3, 2e-3)
    from flexbearing.cli.modes import _level           # mesh-study --levels: metres in, mm to fem_cage.mesh_study
    with pytest.raises(InputError, match="sizes are in metres"):
        _level("4,2,2,3")
    assert _level("4e-3,2e-3,2,3") == (4.0, 2.0, 2, 3)
    help_text = "\n".join(p.format_help() for p in _subparsers(parser).values())
    sizes = re.findall(r"--(?:pocket-)?size \S+\s+(.*?element size[^,]*, (\w+))", help_text)
    assert sizes and {unit for _, unit in sizes} == {"m"}


def _subparsers(parser) -> dict:
    import argparse
    return next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices


# ---------------------------------------------------------------- loads beyond the contacts (item 2 of issue 22)

def test_axial_load_beyond_the_contacts_is_refused_before_the_run(tmp_path, capsys, monkeypatch):
    """Before: axial_load = 1e7 N (the top of the scene's range) was accepted, failed at t = 1.8e-8 s
    (ball 0, outer race: approach 498.9 um > 0.01·Dw) and advised --resume, which failed the same
    way. Cause: the quasi-static equilibrium the run starts from already puts the contacts 2.3x
    deeper than the dynamics' plausibility limit DELTA_MAX_FRAC·Dw = 220 um (Hertz pressure
    9.6 GPa). Now the setup refuses the load (exit 2, no file left), naming the contact, the
    approach and the largest load of that direction the model carries."""
    import numpy as np

    import flexbearing.multibody.initial as I
    from flexbearing.multibody import model as M
    from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL
    from flexbearing.multibody.dynamics import DELTA_MAX_FRAC
    from flexbearing.multibody.outputs import evaluate_outputs
    scene = tmp_path / "big.toml"
    scene.write_text(TINY.replace("axial_load = 55e3", "axial_load = 1e7"))
    out = tmp_path / "big.h5"
    code, err = run_cli(["run", scene, "-o", out], capsys)
    line = one_line(err)
    assert code == 2 and "beyond what the model's contacts carry" in line and "--resume" not in line
    assert not out.exists()
    limit = float(re.search(r"up to about ([0-9.e+]+) N", line).group(1))
    assert 2.0e6 < limit < 2.6e6          # the paper bearing: 202 um at 2 MN, 257 um at 3 MN
    # the limit against another path: the dynamics' own recorded approach (flexbearing.multibody.outputs, not
    # initial.deepest_contact) at the equilibria of 0.97x and 1.03x that load; the bisection stops
    # within 1 % and the limit is printed to 3 digits, hence the 3 % margins
    model = M.build_model(PAPER_BEARING, PAPER_OIL, {})
    monkeypatch.setattr(I, "check_contact_range", lambda *a, **k: None)
    w = 10000 * np.pi / 30
    deepest = []
    for f in (0.97 * limit, 1.03 * limit):
        y = I.initial_state(model, w, f, 0.0, load=np.array([f, 0.0, 0.0]))
        o = evaluate_outputs(model, 0.0, y, np.array([[0.0, w]]), np.array([[0.0, f, 0.0, 0.0]]), np.zeros((0, 6)))
        deepest.append(float(o["approach"].max()))
    dmax = DELTA_MAX_FRAC * PAPER_BEARING.ball_diameter
    assert deepest[0] <= dmax < deepest[1], (deepest, dmax)


def test_a_run_the_physics_stops_does_not_advise_resume(tmp_path, capsys):
    """A SimulationUnstable stop comes back from the checkpoint the same way (the integrator is
    deterministic): the message says so instead of advising --resume."""
    from flexbearing.multibody.integrator import SimulationUnstable
    calls = {"n": 0}

    def unstable(*a, **k):
        calls["n"] += 1
        if calls["n"] == 5:
            raise SimulationUnstable("simulation unstable at t = 1e-3 s: ball 3, outer race: ...", 1e-3, 3,
                                     "outer race")
        from test_run import fake_advance
        return fake_advance(*a, **k)
    with pytest.raises(RunInterrupted) as exc:
        run_scene(fake_scene(), tmp_path / "r.h5", quiet=True, backend=fake_backend(advance=unstable))
    assert not exc.value.resumable and "resuming would repeat it" in str(exc.value)
    assert "continue with --resume" not in str(exc.value)
    with pytest.raises(RunInterrupted) as exc:         # Ctrl-C stays resumable
        run_scene(fake_scene(), tmp_path / "k.h5", quiet=True,
                  backend=fake_backend(advance=lambda *a, **k: (_ for _ in ()).throw(KeyboardInterrupt())))
    assert exc.value.resumable and "continue with --resume" in str(exc.value)


def test_tolerance_below_the_rounding_level_is_refused():
    """integrator.tolerance = 1e-14 was accepted and the step collapsed to 1e-12 s at t = 0.28 ms of
    the 14,000 rpm impact case (1e-13: at 0.56 ms); the range now ends at 1e-12, which finishes
    (benchmarks/stress_test.py, case tol_1e-12)."""
    from flexbearing.simulation.scene import MIN_TOLERANCE
    assert MIN_TOLERANCE == 1e-12
    with pytest.raises(InputError, match=r"integrator.tolerance .*1e-12"):
        loads_scene(TINY + "[integrator]\ntolerance = 1e-14\n")
    assert loads_scene(TINY + "[integrator]\ntolerance = 1e-12\n").tolerance == 1e-12
