"""flexbearing.simulation.jobs.run_jobs: independent jobs in this process, on a LocalCluster and on a cluster of
separate `dask scheduler` / `dask worker` processes. The jobs are standard-library functions
(operator.truediv, time.sleep), importable on any worker, with results known exactly."""
import operator
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from flexbearing.simulation import jobs as J
from flexbearing.common.validation import InputError

ROOT = Path(__file__).resolve().parents[1]
JOBS = [(1.0, 2.0), (1.0, 0.0), (3.0, 4.0), (5.0, 8.0)]       # the second divides by zero
EXPECTED = {0: 0.5, 2: 0.75, 3: 0.625}


def _run(**kw):
    got = {}
    failures = J.run_jobs(operator.truediv, JOBS, got.__setitem__, names=[f"q{k}" for k in range(4)],
                          progress=False, **kw)
    return got, failures


def _check(got, failures):
    assert got == EXPECTED
    assert failures == [J.JobFailure(1, "q1", "ZeroDivisionError: float division by zero")]


def test_in_process_reports_the_failed_job_and_runs_the_others():
    order = []
    failures = J.run_jobs(operator.truediv, JOBS, lambda k, r: order.append(k), workers=1, progress=False)
    assert order == [0, 2, 3]                        # in job order, in this process
    assert [f.index for f in failures] == [1] and failures[0].name == "jobs 1"
    _check(*_run(workers=1))


def test_local_cluster_of_two_workers():
    """Two worker processes, other than this one: the same results, the failure reported."""
    J.run_jobs(time.sleep, [(0.5,)] * 4, lambda k, r: None, workers=2, progress=False)   # warm start
    pids = {}
    J.run_jobs(os.getpid, [()] * 2, pids.__setitem__, workers=2, progress=False)
    assert os.getpid() not in pids.values()
    _check(*_run(workers=2))


@pytest.mark.parametrize("kw, message", [
    ({"workers": 0}, "workers = 0"), ({"workers": 1.5}, "workers = 1.5"), ({"workers": True}, "workers = True"),
    ({"scheduler": "localhost"}, "--scheduler = 'localhost'"), ({"names": ["a"]}, "names has 1"),
])
def test_bad_arguments_are_refused(kw, message):
    with pytest.raises(InputError, match=message.replace("(", r"\(").replace(".", r"\.")):
        J.run_jobs(operator.truediv, JOBS, lambda k, r: None, **kw)


def test_no_scheduler_at_the_address_is_a_clear_error(monkeypatch):
    monkeypatch.setattr(J, "CONNECT_TIMEOUT", "2s")
    with pytest.raises(InputError, match="no Dask scheduler answers there"):
        J.run_jobs(operator.truediv, JOBS, lambda k, r: None, scheduler="tcp://127.0.0.1:9")


def test_ctrl_c_cancels_and_closes_the_cluster():
    """A real SIGINT to the process group (what a terminal's Ctrl-C sends) while two workers sleep
    through 30 s jobs: the script's KeyboardInterrupt arrives within seconds, and the cluster's
    worker processes are gone."""
    psutil = pytest.importorskip("psutil")
    code = textwrap.dedent("""
        import signal, sys, time
        signal.signal(signal.SIGINT, signal.default_int_handler)   # a background shell ignores it
        from flexbearing.simulation.jobs import run_jobs
        if __name__ == "__main__":
            try:
                run_jobs(time.sleep, [(30.0,)] * 4, lambda k, r: None, workers=2, progress=False)
            except KeyboardInterrupt:
                print("INTERRUPTED", flush=True)
                sys.exit(130)
    """)
    script = ROOT / "tests" / "_ctrl_c_jobs.py"
    proc = None
    try:
        script.write_text(code)
        proc = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                text=True, start_new_session=True, env=dict(os.environ, PYTHONPATH=str(ROOT)))
        me = psutil.Process(proc.pid)
        deadline = time.monotonic() + 90
        workers = []
        while time.monotonic() < deadline:
            workers = [c for c in me.children(recursive=True) if "spawn_main" in " ".join(c.cmdline())]
            if len(workers) == 2:
                break
            time.sleep(0.2)
        assert len(workers) == 2, "the LocalCluster's two worker processes did not start"
        time.sleep(3.0)                               # the jobs are running
        t0 = time.monotonic()
        os.killpg(proc.pid, signal.SIGINT)
        out, err = proc.communicate(timeout=60)
        assert proc.returncode == 130 and "INTERRUPTED" in out, err
        assert time.monotonic() - t0 < 30             # not the 30 s of the jobs
        gone, alive = psutil.wait_procs(workers, timeout=10)
        assert not alive
    finally:
        if proc is not None and proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
        script.unlink(missing_ok=True)


def test_a_cluster_of_separate_processes(dask_cluster):
    """--scheduler: the jobs run on the cluster's two workers, the failure is reported."""
    _check(*_run(scheduler=dask_cluster.address))
    pids = {}
    J.run_jobs(os.getpid, [()] * 3, pids.__setitem__, scheduler=dask_cluster.address, progress=False)
    assert os.getpid() not in pids.values()


def test_a_scheduler_without_workers_is_a_clear_error(tmp_path, monkeypatch):
    """Jobs sent to a scheduler no worker has joined would wait for ever: refused, naming it."""
    from conftest import DaskCluster
    monkeypatch.setattr(J, "CONNECT_TIMEOUT", "2s")
    lonely = DaskCluster(tmp_path, n=0)
    try:
        with pytest.raises(InputError, match="the scheduler has no worker"):
            J.run_jobs(operator.truediv, JOBS, lambda k, r: None, scheduler=lonely.address)
    finally:
        lonely.close()
