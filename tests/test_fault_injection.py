"""Crash consistency of the results file (issue 36, part 2), a sample of the fault injection of
benchmarks/fault_injection.py: SIGKILLs at random instants of a run, and a disk that fills up.
Nothing the last checkpoint covers is lost (every row below it reads back, bit for bit the
uninterrupted run's), and every resume equals the uninterrupted run bit for bit."""
import os
import random
import shutil
import subprocess
import time

import pytest

import fault_injection as FI
from flexbearing.simulation import results
from flexbearing.simulation.run import RunInterrupted


SLEEP = 0.004      # s per integrator call: a run of ~3 s, most of it integrating and writing


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    ref = tmp_path_factory.mktemp("ref") / "ref.h5"
    FI.run(ref)
    return ref, results.read_outputs(ref)


def _resume_and_compare(out, ref) -> bool:
    FI.run(out, resume=True)
    return FI.same_results(ref, out)


def test_sigkill_at_random_instants_loses_nothing_below_the_checkpoint(tmp_path, reference):
    """Four kills of the run's process at instants drawn uniformly over a run (seeded), each one
    then resumed. The full >= 100 across the commands: benchmarks/fault_injection.py."""
    ref, R = reference
    t0 = time.perf_counter()
    p = FI.start(tmp_path / "timing.h5", SLEEP)
    assert p.wait() == 0, p.stderr.read()
    duration = time.perf_counter() - t0
    rng = random.Random(36)
    for i in range(4):
        out = tmp_path / f"k{i}.h5"
        FI.kill_after(FI.start(out, SLEEP), rng.uniform(0.2, 1.0) * duration)
        c = FI.check_file(out, R)
        assert c.lost == 0 and c.n_checkpoint >= 0, c
        assert _resume_and_compare(out, ref), f"kill {i}: resume differs ({c})"


def test_a_full_disk_stops_the_run_with_one_line_and_a_resumable_file(tmp_path, reference, monkeypatch):
    """The reservation of the next block fails (as on a full disk): the run stops before writing
    any of it, the file holds its last checkpoint and resumes bit-identically."""
    import errno
    ref, R = reference
    calls = {"n": 0}
    real = results._reserve

    def filling(f, nbytes):
        calls["n"] += 1
        if calls["n"] == 9:
            raise results.DiskFull(errno.ENOSPC, "disk full: (test)", f.filename)
        return real(f, nbytes)
    monkeypatch.setattr(results, "_reserve", filling)
    out = tmp_path / "r.h5"
    with pytest.raises(RunInterrupted) as exc:
        FI.run(out)
    assert isinstance(exc.value.cause, results.DiskFull) and exc.value.resumable
    assert "\n" not in str(exc.value) and "disk full" in str(exc.value)
    c = FI.check_file(out, R)
    assert c.lost == 0 and c.n_checkpoint == 8 * 7 and c.status == "running", c
    monkeypatch.setattr(results, "_reserve", real)
    assert _resume_and_compare(out, ref)


def _tmpfs(path, size: str) -> bool:
    path.mkdir(exist_ok=True)
    if os.geteuid() != 0 or shutil.which("mount") is None:
        return False
    return subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(path)],
                          capture_output=True).returncode == 0


@pytest.mark.parametrize("size", ["300k", "450k", "600k", "1500k"])
def test_enospc_on_a_small_tmpfs(tmp_path, reference, size):
    """A real full disk (a tmpfs of `size`; root only, else skipped): stops at a checkpoint with
    one line or finishes; either way nothing below the checkpoint is lost and, moved to a disk
    with room, the file resumes bit-identically. No temporary is left on the small disk."""
    ref, R = reference
    disk = tmp_path / "small"
    if not _tmpfs(disk, size):
        pytest.skip("mounting a tmpfs needs root")
    try:
        out = disk / "r.h5"
        try:
            FI.run(out)
            stopped = False
        except RunInterrupted as exc:
            assert isinstance(exc.cause, results.DiskFull)
            assert "\n" not in str(exc)
            stopped = True
        c = FI.check_file(out, R)
        assert c.lost == 0 and (stopped or c.status == "complete"), c
        assert FI.leftover_temporaries(disk) == []
        moved = tmp_path / "r.h5"
        shutil.copy(out, moved)
    finally:
        subprocess.run(["umount", str(disk)], check=False)
    assert _resume_and_compare(moved, ref)


def test_a_run_killed_before_its_first_byte_resumes_from_the_start(tmp_path, reference):
    """A SIGKILL after the run claimed (created) its file and before HDF5 wrote anything leaves an
    empty file, which `--resume` refused as "not an HDF5 results file (0 bytes)" (7 of 20 kills of
    `flexbearing run` in benchmarks/fault_injection.py): under the run's claim an empty file is
    nothing computed, and the run starts over."""
    ref, _ = reference
    out = tmp_path / "r.h5"
    out.write_bytes(b"")
    FI.run(out, resume=True)
    assert FI.same_results(ref, out)


def test_a_compressed_copy_left_by_a_kill_is_removed_by_the_next_finish(tmp_path, reference):
    """A SIGKILL while the complete run's compressed copy is written leaves that temporary beside
    the run (the uncompressed file stays whole); the next `--resume` finishes the file again and
    removes it."""
    ref, _ = reference
    out = tmp_path / "r.h5"
    FI.run(out)
    stale = tmp_path / f".{out.name}.abcd1234.finishing.h5"
    stale.write_bytes(b"half a compressed copy")
    FI.run(out, resume=True)
    assert not stale.exists() and FI.same_results(ref, out)
