"""Issue 43 §6: what gave a traceback (or was accepted and ignored) now gives one line and a
non-zero exit, and Ctrl-C stops within seconds, SLEPc's eigen-solve and Dask's workers included."""
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import h5py
import numpy as np
import pytest
import scipy.linalg

from flexbearing.cli.main import main
import flexbearing.simulation.run as simulation_run
import flexbearing.simulation.results as results
from test_run import SCENE, fake_backend, fake_scene


def _one_line(capsys, argv, *fragments, code=2) -> str:
    assert main([str(a) for a in argv]) == code
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    for f in fragments:
        assert f in err, err
    return err


def test_a_deeply_nested_scene_is_one_line(tmp_path, capsys):
    """Before: RecursionError traceback from the TOML parser (exit 1)."""
    deep = tmp_path / "deep.toml"
    deep.write_text("a = " + "[" * 5000 + "]" * 5000 + "\n")
    _one_line(capsys, ["run", deep, "-o", tmp_path / "r.h5"], "deep.toml", "nested too deeply")
    deep.write_text("a = " + "{b = " * 3000 + "1" + "}" * 3000 + "\n")
    _one_line(capsys, ["run", deep, "-o", tmp_path / "r.h5"], "nested too deeply")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["deep.toml"]


def test_a_scene_path_with_a_byte_that_is_not_utf8_runs_and_its_results_file_is_whole(tmp_path, fake_runs, capsys):
    """Before: UnicodeEncodeError storing the scene path in the results file, which was left
    behind half-created. Now the path is stored with the byte escaped and the run finishes."""
    folder = os.fsdecode(os.fsencode(str(tmp_path)) + b"/sc\xffene")
    os.mkdir(folder)
    scene = os.path.join(folder, "fake.toml")
    Path(scene).write_text(SCENE)
    out = tmp_path / "r.h5"
    assert main(["run", scene, "-o", str(out), "--quiet"]) == 0
    with h5py.File(out, "r") as f:
        assert f.attrs["status"] == "complete" and "sc\\xffene" in f.attrs["scene_path"]


def test_a_failure_while_the_results_file_is_created_leaves_no_file(tmp_path, monkeypatch):
    def broken(cls, f, scene, units):
        f.attrs["format"] = "half"
        raise OSError(5, "Input/output error")
    monkeypatch.setattr(results.ResultsWriter, "_created", classmethod(broken))
    with pytest.raises(OSError, match="cannot be created"):
        results.ResultsWriter.create(tmp_path / "r.h5", fake_scene())
    assert list(tmp_path.iterdir()) == []


def test_a_full_disk_at_file_creation_is_one_line_naming_the_file(tmp_path, fake_runs, capsys, monkeypatch):
    """Before: HDF5's own paragraph ("Unable to create file (unable to open file: name = ..., errno
    = 28, error message = 'No space left on device', flags = 13, o_flags = 242)")."""
    def full(path, mode="r", *a, **k):
        if mode == "w":
            raise OSError(f"[Errno 28] Unable to create file (unable to open file: name = '{path}', errno = 28, "
                          f"error message = 'No space left on device', flags = 13, o_flags = 242)")
        return real(path, mode, *a, **k)
    real = h5py.File
    monkeypatch.setattr(results.h5py, "File", full)
    scene = tmp_path / "fake.toml"
    scene.write_text(SCENE)
    out = tmp_path / "r.h5"
    err = _one_line(capsys, ["run", scene, "-o", out, "--quiet"], str(out), "disk full", code=1)
    assert "o_flags" not in err and not out.exists()


def test_hdf5_errors_reach_the_user_as_the_file_and_the_reason():
    """h5py's OSError text is a paragraph of flags; the command prints the file and the cause."""
    from flexbearing.cli.main import os_error_line
    hdf5 = ("Unable to create file (unable to open file: name = '/data/r.h5', errno = {}, error message = "
            "'{}', flags = 13, o_flags = 242)")
    line = os_error_line(OSError(hdf5.format(28, "No space left on device")))
    assert line.startswith("/data/r.h5: disk full") and "flags" not in line
    assert os_error_line(OSError(hdf5.format(13, "Permission denied"))) == "/data/r.h5: Permission denied"


def test_report_with_a_results_file_as_its_reduced_cage_is_one_line(run_file, tmp_path, capsys):
    _one_line(capsys, ["report", run_file, "--reduced-cage", run_file, "-o", tmp_path / "rep"],
              "--reduced-cage", "results file of a run", "not a reduced cage file")
    other = tmp_path / "x.h5"
    other.write_bytes(b"not hdf5")
    _one_line(capsys, ["report", run_file, "--reduced-cage", other, "-o", tmp_path / "rep"], "not a reduced cage file")
    _one_line(capsys, ["report", run_file, "--reduced-cage", tmp_path / "none.h5", "-o", tmp_path / "rep"],
              "no such file")
    assert not (tmp_path / "rep").exists()


@pytest.mark.parametrize("value", ["nan", "-5", "0", "inf", "ten"])
def test_max_wall_time_must_be_a_finite_positive_number(tmp_path, capsys, value):
    """Before: nan and -5 were accepted and ignored."""
    scene = tmp_path / "fake.toml"
    scene.write_text(SCENE)
    with pytest.raises(SystemExit) as exc:
        main(["run", str(scene), "--max-wall-time", value])
    err = capsys.readouterr().err
    assert exc.value.code == 2 and "Traceback" not in err
    assert "--max-wall-time" in err and (value in err)
    assert list(tmp_path.iterdir()) == [scene]


@pytest.mark.parametrize("value", [float("nan"), -5.0, 0.0, float("inf")])
def test_run_scene_refuses_a_wall_time_limit_that_would_be_ignored(tmp_path, value):
    from flexbearing.common.validation import InputError
    with pytest.raises(InputError, match="max-wall-time"):
        simulation_run.run_scene(fake_scene(), tmp_path / "r.h5", quiet=True, backend=fake_backend(),
                                 max_wall_time=value)
    assert list(tmp_path.iterdir()) == []


# ---------------------------------------------------------------- Ctrl-C

def _petsc(A):
    from petsc4py import PETSc
    A = A.tocsr()
    return PETSc.Mat().createAIJ(size=A.shape, csr=(A.indptr.astype(np.int32), A.indices.astype(np.int32), A.data))


def test_slepc_modes_through_the_interruptible_factor_match_dense_eigh(spring_chain):
    """The shift-invert factorisation applied through the Ctrl-C-aware PC gives the generalised
    eigenvalues of a free spring chain as LAPACK's dense solver (independent code)."""
    from flexbearing.fem_cage.modes import free_free_modes
    K, M = spring_chain(90, 3)
    K = K * 1e6              # springs of 0.5-1.5 MN/m: elastic modes of 2-80 Hz, near the solver's shift
    freqs, vecs = free_free_modes(_petsc(K), _petsc(M), n_modes=12)
    lam = scipy.linalg.eigh(K.toarray(), M.toarray(), eigvals_only=True)[:12]
    # SLEPc's tolerance 1e-9 bounds the relative residual of theta = 1/(omega^2 - sigma); the
    # eigenvalue error is then of order 1e-9 (omega^2 - sigma) times the conditioning (< 10 here)
    scale = lam.max() + (2 * np.pi * 10.0) ** 2
    omega2 = np.sign(freqs) * (2 * np.pi * freqs) ** 2
    assert np.allclose(omega2[3:], lam[3:], rtol=0, atol=1e-8 * scale)
    assert np.all(np.abs(omega2[:3]) < 1e-8 * scale)             # the three free translations


def test_ctrl_c_in_the_eigen_solve_stops_it_at_the_next_operator_application(spring_chain, monkeypatch):
    """SIGINT sent during SLEPc's solve (from inside it, at the 3rd shift-invert application):
    KeyboardInterrupt after at most one more application; before, the solve ran to its end."""
    import flexbearing.fem_cage.modes as modes
    K, M = spring_chain(300, 5)
    calls = []
    real = modes._InterruptibleFactor.apply

    def apply(self, pc, x, y):
        calls.append(len(self.pressed))
        if len(calls) == 3:
            os.kill(os.getpid(), signal.SIGINT)
        return real(self, pc, x, y)
    monkeypatch.setattr(modes._InterruptibleFactor, "apply", apply)
    # as in a terminal: a test runner started in the background (`cmd &` in a script) inherits SIGINT
    # ignored, and Python then installs no handler of its own
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            modes.free_free_modes(_petsc(K), _petsc(M), n_modes=40)
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler     # put back
    finally:
        signal.signal(signal.SIGINT, before)
    assert len(calls) <= 4                  # the 3rd application (signal handled at once) or the next


def _terminal_sigint() -> None:
    """In the child before exec: SIGINT at its default, as a terminal's foreground job has it (a test
    runner started in the background inherits it ignored, and so would the command under test)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _stop_after(cmd, ready: str, delay: float, cwd, timeout: float = 300.0):
    """Start cmd in its own session; when `ready` appears on its stderr wait `delay` s, send SIGINT
    to its process group (as a terminal's Ctrl-C) and return (exit code, seconds to stop, stderr)."""
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, cwd=cwd,
                         start_new_session=True, preexec_fn=_terminal_sigint)
    seen, t_end = b"", time.monotonic() + timeout
    os.set_blocking(p.stderr.fileno(), False)
    while ready.encode() not in seen and time.monotonic() < t_end and p.poll() is None:
        seen += p.stderr.read() or b""
        time.sleep(0.05)
    assert ready.encode() in seen, seen.decode(errors="replace")[-2000:]
    time.sleep(delay)
    t0 = time.monotonic()
    os.killpg(p.pid, signal.SIGINT)
    os.set_blocking(p.stderr.fileno(), True)
    rest = p.communicate(timeout=120)[1]
    return p.returncode, time.monotonic() - t0, (seen + rest).decode(errors="replace")


JOBS_SCRIPT = textwrap.dedent("""
    import sys, time
    from flexbearing.simulation.jobs import run_jobs

    def slow(k):
        time.sleep(120)

    if __name__ == "__main__":
        print("starting", file=sys.stderr, flush=True)
        try:
            run_jobs(slow, [(k,) for k in range(4)], lambda k, r: None, workers=2, progress=False)
        except KeyboardInterrupt:
            print("interrupted", file=sys.stderr)
            sys.exit(130)
    """)


@pytest.mark.parametrize("delay", [1.0, 8.0])
def test_ctrl_c_on_a_local_dask_cluster_stops_it_without_worker_tracebacks(tmp_path, delay):
    """Ctrl-C while the cluster starts (1 s) and while its jobs run (8 s): exit 130 within 20 s
    (cluster start and close on 2 shared cores), one line, no worker traceback (before: each
    worker's KeyboardInterrupt and an AssertionError of the half-started cluster at exit)."""
    (tmp_path / "jobs.py").write_text(JOBS_SCRIPT)
    code, took, err = _stop_after([sys.executable, "jobs.py"], "starting", delay, tmp_path)
    assert code == 130 and "Traceback" not in err and "KeyboardInterrupt" not in err, err
    print(f"\nDask, Ctrl-C {delay:g} s after the start: exit {code} {took:.1f} s later")
    assert took < 20.0, took


@pytest.mark.slow
def test_ctrl_c_during_modes_stops_within_seconds(tmp_path):
    """`flexbearing modes` on a coarse P2 cage with 300 modes, Ctrl-C 2 s into the eigen-solve:
    exit 130 in a few seconds (before: the solve ran to its end, 130-140 s on the paper cage)."""
    exe = str(Path(sys.executable).with_name("flexbearing"))
    assert subprocess.run([exe, "mesh", "-o", str(tmp_path / "c.msh"), "--size", "0.01", "--pocket-size",
                           "0.006", "--quiet"], capture_output=True).returncode == 0
    code, took, err = _stop_after([exe, "modes", "--mesh", str(tmp_path / "c.msh"), "--degree", "2",
                                   "--n-modes", "300", "--no-classify"], "eigensolve", 2.0, tmp_path)
    assert code == 130 and "Traceback" not in err and "interrupted (Ctrl-C)" in err, err[-2000:]
    print(f"\nmodes --n-modes 300, Ctrl-C 2 s into the eigensolve: exit {code} {took:.1f} s later")
    assert took < 10.0, took
