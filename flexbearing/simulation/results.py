"""One HDF5 file per run, written while the run goes, plus the summary.json beside it.

Layout (SI units in the `unit` attribute of every dataset):

    /                      attrs: format, format_version, scene_name, scene_hash, status
                           ("running" | "interrupted" | "failed: ..." | "complete"), duration,
                           sample_interval, n_samples_expected, cage_model, program_version and
                           git_commit (flexbearing.common.provenance), summary (JSON, at the end)
    /scene                 the scene's TOML text, as loaded
    /outputs/time          (n,) s
    /outputs/<name>        (n, ...) one row per sample, e.g. contact_stress (n, Z, 3) Pa; attrs
                           unit, units (the same in CF/udunits spelling: "N m" for "N·m", "1" for
                           counts), dims (names of the axes, e.g. "time, ball, contact") and, for
                           labelled last axes, columns ("outer, inner_left, inner_right"), from
                           flexbearing.multibody.output_registry; chunks of a checkpoint interval of samples
                           (chunk_rows), deflate + shuffle (COMPRESSION) once the run is
                           complete, uncompressed while it runs ("Crash safety")
    /outputs/<dimension>   HDF5 dimension scales (format 2): time is /outputs/time itself; ball,
                           contact, axis, ... (output_registry.DIMENSIONS) hold their labels or
                           indices and are attached to every output's axes, so that
                           xarray.open_dataset(run.h5, group="outputs") gives named dimensions
                           with time as a coordinate (output_items() skips them)
    /checkpoint/slot0, slot1   y (state), dydt (the integrator's FSAL derivative at y, if any), attrs t,
                           h, n_samples, n_steps, n_rejected, wall_time, seq

Crash safety (issue 36). Samples are buffered in memory and written in blocks: each block is
appended to the chunked, resizable datasets, then a checkpoint describing the state at the block's
last sample is written. While a run goes, its datasets are stored *uncompressed*: a chunk then has
a fixed size and place in the file, and rewriting it (a block that ends inside a chunk, continued
by the next block or by a resume) writes the same bytes for the rows it already held. A compressed
chunk, rewritten, is a different deflate stream, possibly moved to a new place whose old place is
freed and reused: a SIGKILL between that rewrite and the next flush left the index on disk
pointing at the old size and place, and rows *below* the last checkpoint failed with "inflate()
failed" (3 of 6 killed studies before this change). The compressed form is written once, when the
run is complete (`finish`): a new file, written beside the run's, fsynced and renamed over it, so
that the run's file is at every instant either the uncompressed file or the whole compressed one.
Before each block, the block's space is reserved on the disk (fallocate, `reserve`), so that a
full disk stops the run before HDF5 writes anything (`DiskFull`, one line; the file holds its last
checkpoint and resumes) instead of inside HDF5's metadata writes. Each checkpoint is flushed and
fsynced before and after its sequence number is set, so that a power loss cannot leave a slot
whose sequence number is on disk and its state is not. Measured: benchmarks/fault_injection.py,
benchmarks/results/fault_injection.md.
`checkpoint_in_background` hands the block (and, from
flexbearing.simulation.run, the evaluation of its samples' outputs) and its checkpoint to one writer thread and
returns: that work then runs on a second core while the integration goes on (flexbearing.multibody.integrator's
compiled loop releases the GIL); the next checkpoint, `checkpoint`, `set_status` and `close` wait for
it, so blocks are written one at a time and in order, exactly as the synchronous path writes them.
The checkpoint is
double-buffered: the slot being written is first invalidated (seq = -1) and gets its sequence number
last, so a kill inside a checkpoint write leaves the other slot valid. On Ctrl-C or an exception the
run writes what it has and a checkpoint at its last sample before closing.

Resume. `open_for_resume` picks the valid checkpoint with the highest sequence number and truncates
every output dataset to the checkpoint's sample count; the run continues from the checkpoint's
(y, t, h) and the integrator's derivative there (dydt: the first stage of its next step, as in the
uninterrupted run). The integrator is deterministic, so the resumed file's datasets equal an
uninterrupted run's bit for bit (tests/test_resume.py).
"""
from __future__ import annotations

import errno
import json
import math
import os
import shutil
from contextlib import contextmanager
from pathlib import Path
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import h5py
from h5py import h5ds

from flexbearing.common.validation import InputError
from flexbearing.multibody import output_registry as R
from flexbearing.common.safe_files import (reserve_space, release_space, write_text_atomic, atomic_output)
from flexbearing.common.provenance import git_commit, program_version

FORMAT = "flexbearing-results"
FORMAT_VERSION = 2        # 2: dimension scales, CF `units`, compressed chunks (1 is still read)
CHUNK_ROWS = 256          # rows per HDF5 chunk along time when the block size is not known


def chunk_rows(checkpoint_every: int) -> int:
    """Rows per chunk of a run's datasets: its checkpoint interval, i.e. one block (within 64 ... 1024).

    A block then fills its own chunks, each compressed once; with 256-row chunks and the default
    200-sample blocks every chunk was compressed twice (once partly filled at a checkpoint's flush)
    and the writer thread took 4.1 instead of 2.6 s on the paper's steady rigid run (issue 21)."""
    return int(min(max(int(checkpoint_every), 64), 1024))


# Every output dataset's filters (HDF5 deflate + byte shuffle: readable by any HDF5 or netCDF-4
# reader, no plugin). Measured on the paper's steady flexible run: benchmarks/bench_results_file.py.
COMPRESSION = {"compression": "gzip", "compression_opts": 1, "shuffle": True}

# Units, dimension names and column labels of the recorded quantities: flexbearing.multibody.output_registry
# (a backend's output_units dict wins; name fragments are the last resort for names it does not
# know, ordered: the more specific fragment first).
_UNIT_RULES = (("ratio", "1"), ("angular_velocity", "rad/s"), ("angle", "rad"), ("tilt", "rad"),
               ("von_mises", "Pa"), ("stress", "Pa"), ("pressure", "Pa"), ("film", "m"),
               ("thickness", "m"), ("torque", "N·m"), ("force", "N"), ("load", "N"), ("drag", "N"),
               ("slip", "1"), ("speed", "rad/s"), ("omega", "rad/s"), ("velocity", "m/s"),
               ("orbit", "m"), ("position", "m"), ("centre", "m"), ("offset", "m"),
               ("displacement", "m"), ("approach", "m"))


def unit_for(name: str, known: dict | None = None) -> str:
    if known and name in known:
        return known[name]
    if name in R.OUTPUT:
        return R.OUTPUT[name].unit
    if name == "time":
        return "s"
    for frag, unit in _UNIT_RULES:
        if frag in name:
            return unit
    return "unknown"


def printable_path(path) -> str:
    """`path` as UTF-8 text HDF5 can store: a byte of the file name that is not UTF-8 (Python's
    surrogate escape) written as \\xNN."""
    return os.fsencode(str(path)).decode("utf-8", "backslashreplace") if path else (path or "")


def creation_error(path, exc: OSError) -> OSError:
    """The one-line error of a results file that could not be created: a full disk named as
    such (HDF5's own text is a paragraph of flags), else the system's reason."""
    text = str(exc)
    if exc.errno in (errno.ENOSPC, errno.EDQUOT) or "errno = 28" in text or "No space left" in text:
        return OSError(errno.ENOSPC, "disk full: the results file cannot be created; free space and run "
                       "again", str(path))
    reason = exc.strerror or text.split("(")[-1].rstrip(")") or text
    return OSError(exc.errno or errno.EIO, f"the results file cannot be created: {reason}", str(path))


def summary_path(results_path) -> Path:
    """run.h5 -> run.summary.json (beside the results; one per run, so runs in one folder coexist)."""
    p = Path(results_path)
    return p.with_name(p.stem + ".summary.json")


def _attach_dimensions(out, name: str, ds, dims) -> None:
    """Make /outputs/time the `time` dimension scale, and attach to a new dataset's axes the scales of
    its dimensions (time first, then flexbearing.multibody.output_registry's dims, each a scale dataset in
    /outputs created at its first use: the labels of its columns, or the index 0..n-1), so that
    `xarray.open_dataset(run.h5, group="outputs")` names them. The axes of a dataset the registry
    does not know (a test's backend) are `<name>_dim1`, ... ."""
    if name == "time":
        ds.make_scale("time")
        return
    ds.dims[0].attach_scale(out["time"])
    if dims is None:           # not in the registry: its own dimensions (netCDF needs every axis named)
        dims = tuple(f"{name}_dim{i}" for i in range(1, ds.ndim))
    for axis, dim in enumerate(dims, start=1):
        n = ds.shape[axis]
        if dim not in out:
            labels = R.DIMENSION_LABELS.get(dim)
            if labels is not None and len(labels) == n:
                scale = out.create_dataset(dim, data=np.array(labels, dtype=object), dtype=h5py.string_dtype())
            else:
                scale = out.create_dataset(dim, data=np.arange(n, dtype=np.int64))
            scale.make_scale(dim)
        scale = out[dim]
        if scale.shape != (n,):
            raise RuntimeError(f"output {name!r}: dimension {dim!r} has {n} entries, {scale.shape[0]} elsewhere")
        ds.dims[axis].attach_scale(scale)


def different_scene(path, file_hash, scene):
    """The InputError for a results file that another scene wrote (resume, or a study's re-run)."""
    return InputError(f"--resume: {path} was written by a different scene (scene hash {file_hash} in the "
                      f"file, {scene.content_hash()} for {scene.path or scene.name}); resume needs the same "
                      f"scene, or write a new file")


def output_items(out):
    """(name, dataset) of the recorded outputs in a results file's /outputs group, time included:
    every dataset but the dimension scales (ball, contact, ...)."""
    return [(k, ds) for k, ds in out.items() if k == "time" or not h5ds.is_scale(ds.id)]


class ResultsWriter:
    """Append-only writer of one run's results, with checkpoints. Use `create` or `open_for_resume`."""

    def __init__(self, h5file, units: dict | None = None, rows_per_chunk: int = CHUNK_ROWS):
        self.f = h5file
        self.units = dict(units or {})
        self.buffer: dict[str, list] = {}
        self.n_written = int(self.f["outputs/time"].shape[0]) if "outputs/time" in self.f else 0
        self.previous_status = ""
        self.rows_per_chunk = int(rows_per_chunk)
        self._pool = None          # the writer thread of checkpoint_in_background (created on first use)
        self.n_samples_expected = int(self.f.attrs.get("n_samples_expected", 0))
        self.max_output_bytes = DEFAULT_MAX_OUTPUT_BYTES
        self._pending = None       # its block being written (a Future)

    # ---- opening
    @classmethod
    def create(cls, path, scene, units: dict | None = None) -> "ResultsWriter":
        """A new results file of `scene` at `path`. A failure while it is created (ENOSPC, ...)
        leaves no file: it is removed, and a full disk is one line naming the file."""
        try:
            f = h5py.File(path, "w")
        except OSError as exc:
            raise creation_error(path, exc) from None
        try:
            return cls._created(f, scene, units)
        except BaseException as exc:
            f.close()
            Path(path).unlink(missing_ok=True)
            if isinstance(exc, OSError):
                raise creation_error(path, exc) from None
            raise

    @classmethod
    def _created(cls, f, scene, units):
        f.attrs["format"] = FORMAT
        f.attrs["format_version"] = FORMAT_VERSION
        f.attrs["scene_name"] = scene.name
        f.attrs["scene_hash"] = scene.content_hash()
        f.attrs["scene_path"] = printable_path(scene.path)
        f.attrs["cage_model"] = scene.cage_model
        f.attrs["duration"] = scene.duration
        f.attrs["sample_interval"] = scene.sample_interval
        f.attrs["n_samples_expected"] = scene.n_samples
        f.attrs["status"] = "running"
        f.attrs["n_resumes"] = 0
        f.attrs["program_version"] = program_version()
        f.attrs["git_commit"] = git_commit()
        f.create_dataset("scene", data=scene.text or json.dumps(scene.data, default=repr))
        if scene.cad:             # what `report` rebuilds the CAD cage from (never the file the scene names)
            from flexbearing.simulation.scene import cad_record
            f.attrs["cad_cage"] = cad_record(scene)
        f.create_group("outputs")
        cp = f.create_group("checkpoint")
        for s in ("slot0", "slot1"):
            cp.create_group(s).attrs["seq"] = -1
        f.flush()
        return cls(f, units, chunk_rows(scene.checkpoint_every))

    @classmethod
    def open_for_resume(cls, path, scene, units: dict | None = None):
        """Open an existing run of `scene`; return (writer, checkpoint dict or None).

        None means no valid checkpoint (the run must start over; the file has been reset)."""

        # checked before HDF5 opens it for writing: h5py's "r+" writes a superblock into an empty file
        if not h5py.is_hdf5(path):
            raise InputError(f"--resume: {path} is not an HDF5 results file ({Path(path).stat().st_size} "
                             f"bytes); it cannot be resumed and was left untouched: start a new run with "
                             f"--force (overwrites it) or write to another file with -o")
        try:
            f = h5py.File(path, "r+")
        except OSError as exc:
            raise InputError(f"--resume: {path} is damaged ({exc}); it cannot be resumed and was left "
                             f"untouched: start a new run with --force or write to another file with -o") from None
        try:
            if f.attrs.get("format") != FORMAT:
                raise InputError(f"{path} is not a flexbearing results file (format attribute "
                                 f"{f.attrs.get('format')!r}, expected {FORMAT!r})")
            if f.attrs["scene_hash"] != scene.content_hash():
                raise different_scene(path, f.attrs["scene_hash"], scene)
            cp = read_checkpoint(f)
        except Exception:
            f.close()
            raise
        w = cls(f, units)
        w.previous_status = str(f.attrs.get("status", ""))
        w.n_written = 0 if cp is None else cp["n_samples"]
        if "outputs" in f:
            for name, ds in output_items(f["outputs"]):
                ds.resize(w.n_written, axis=0)      # drop samples written after the checkpoint
        f.attrs["status"] = "running"
        f.attrs["n_resumes"] = int(f.attrs.get("n_resumes", 0)) + 1
        f.flush()
        return w, cp

    # ---- writing
    def add_sample(self, t: float, values: dict) -> None:
        """Buffer one sample (written by the next `write_block`)."""
        _append(self.buffer, t, values)

    @property
    def n_buffered(self) -> int:
        return len(self.buffer.get("time", ()))

    def write_block(self, buffer: dict | None = None) -> None:
        """Append the buffered samples (or `buffer`, a detached buffer) to the datasets (created at
        the first block)."""
        if buffer is None:
            buffer, self.buffer = self.buffer, {}
        nb = len(buffer.get("time", ()))
        if nb == 0:
            return
        out = self.f["outputs"]
        n0 = self.n_written
        for k, rows in buffer.items():
            if len(rows) != nb:
                raise RuntimeError(f"output {k!r} has {len(rows)} samples in a block of {nb}")
            block = np.stack(rows)
            if k not in out:
                if n0 != 0:
                    raise RuntimeError(f"output {k!r} appeared after {n0} samples")
                ds = out.create_dataset(k, shape=(0,) + block.shape[1:], maxshape=(None,) + block.shape[1:],
                                        dtype=np.float64, chunks=(self.rows_per_chunk,) + block.shape[1:])
                ds.attrs["unit"] = unit = unit_for(k, self.units)
                ds.attrs["units"] = R.cf_units(unit)           # CF spelling, for xarray/netCDF tools
                entry = R.OUTPUT.get(k)
                dims = None
                if entry is not None and len(entry.dims) == block.ndim - 1:
                    dims = entry.dims
                    ds.attrs["dims"] = ", ".join(("time",) + entry.dims)
                cols = entry.columns if entry is not None else None
                if cols and block.ndim >= 2 and block.shape[-1] == len(cols):
                    ds.attrs["columns"] = ", ".join(cols)
                _attach_dimensions(out, k, ds, dims)
            ds = out[k]
            if ds.shape[1:] != block.shape[1:]:
                raise RuntimeError(f"output {k!r} changed shape from {ds.shape[1:]} to {block.shape[1:]}")
            ds.resize(n0 + nb, axis=0)
            ds[n0:n0 + nb] = block
        self.n_written = n0 + nb

    def checkpoint(self, y, t: float, h: float, n_steps: int, n_rejected: int, wall_time: float,
                   dydt=None) -> None:
        """Write buffered samples, then the state at the last written sample, then flush. `dydt`:
        the integrator's derivative at that state (its FSAL stage), so that a resumed run takes the
        same first step as the uninterrupted one; None when there is none."""
        self.wait()
        self._write_checkpoint(self.buffer, y, t, h, n_steps, n_rejected, wall_time, dydt)
        self.buffer = {}

    def checkpoint_in_background(self, y, t: float, h: float, n_steps: int, n_rejected: int,
                                 wall_time: float, dydt=None, samples=None) -> None:
        """`checkpoint` done by the writer thread (module docstring): waits for the previous block,
        detaches the buffer and returns. `y` must not change afterwards (pass a copy). `samples`: a
        function the thread calls first; its [(t, values)] are added to the block (flexbearing.simulation.run
        evaluates a checkpoint interval's outputs there). If the thread fails, its block is not in
        the file (n_written does not advance; a partly written block is overwritten by the next)
        and `wait` raises: the caller writes those samples again (flexbearing.simulation.run keeps them)."""
        self.wait()
        if self._pool is None:
            self._pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="results-writer")
        block, self.buffer = self.buffer, {}
        def job():
            if samples is not None:
                for t_s, values in samples():
                    _append(block, t_s, values)
            self._write_checkpoint(block, y, t, h, n_steps, n_rejected, wall_time, dydt)
        self._pending = self._pool.submit(job)

    def wait(self) -> None:
        """Wait for the block the writer thread is writing; re-raise its error (e.g. disk full)."""
        pending, self._pending = self._pending, None
        if pending is not None:
            pending.result()

    def reserve(self, block: dict) -> None:
        """Reserve on the disk the space the block and its checkpoint can take (DiskFull if there is
        none), before HDF5 writes any of it: whole chunks of every output for the block's rows, plus
        a margin for HDF5's metadata and the checkpoint. Blocks past the file's end are allocated
        without changing its size (fallocate KEEP_SIZE), so HDF5 then writes into space it has."""
        nb = len(block.get("time", ()))
        if nb == 0:
            return
        chunks = -(-nb // self.rows_per_chunk) + 1
        row_bytes = sum(np.asarray(rows[0]).size * 8 for rows in block.values())
        if self.n_written == 0:
            self._check_output_size(row_bytes)
        need = chunks * self.rows_per_chunk * row_bytes + RESERVE_MARGIN
        _reserve(self.f, need)

    def _check_output_size(self, row_bytes: int) -> None:
        """OutputTooLarge if the whole run (n_samples_expected rows of row_bytes, uncompressed as it
        is while running) would not fit in the free space or exceeds max_output_bytes."""
        estimate = self.n_samples_expected * row_bytes
        path = Path(self.f.filename)
        free = shutil.disk_usage(path.parent).free
        if estimate > self.max_output_bytes or estimate > free:
            why = (f"more than the limit of {self.max_output_bytes / 1e9:.3g} GB (--max-output-size BYTES "
                   f"raises it)" if estimate > self.max_output_bytes else
                   f"more than the {free / 1e9:.3g} GB free in {path.parent}")
            raise OutputTooLarge(f"{path}: this run would write about {estimate / 1e9:.3g} GB "
                                 f"({self.n_samples_expected} samples x {row_bytes} bytes), {why}: record "
                                 f"fewer outputs, a longer output.sample_interval or a shorter duration")

    def _write_checkpoint(self, block: dict, y, t, h, n_steps, n_rejected, wall_time, dydt) -> None:
        self.reserve(block)
        self.write_block(block)
        cp = self.f["checkpoint"]
        seqs = [int(cp[s].attrs["seq"]) for s in ("slot0", "slot1")]
        slot = cp["slot0"] if seqs[0] <= seqs[1] else cp["slot1"]   # overwrite the older slot
        slot.attrs["seq"] = -1
        _sync(self.f)
        y = np.asarray(y, dtype=np.float64)
        if "y" in slot and slot["y"].shape == y.shape:
            slot["y"][...] = y
        else:
            if "y" in slot:
                del slot["y"]
            slot.create_dataset("y", data=y)
        if "dydt" in slot and (dydt is None or slot["dydt"].shape != np.shape(dydt)):
            del slot["dydt"]
        if dydt is not None:
            if "dydt" in slot:
                slot["dydt"][...] = dydt
            else:
                slot.create_dataset("dydt", data=np.asarray(dydt, dtype=np.float64))
        slot.attrs.update({"t": float(t), "h": float(h), "n_samples": int(self.n_written),
                           "n_steps": int(n_steps), "n_rejected": int(n_rejected),
                           "wall_time": float(wall_time)})
        _sync(self.f)
        slot.attrs["seq"] = max(seqs) + 1
        _sync(self.f)

    def set_status(self, status: str) -> None:
        self.wait()
        self.f.attrs["status"] = status
        self.f.flush()

    def close(self) -> None:
        try:
            self.wait()
        finally:
            if self._pool is not None:
                self._pool.shutdown(wait=True)
                self._pool = None
            if self.f.id.valid:
                path = self.f.filename
                self.f.close()
                _release(path)


RESERVE_MARGIN = 256 << 10    # bytes reserved beyond a block's chunks: HDF5 metadata, the checkpoint


DEFAULT_MAX_OUTPUT_BYTES = 50e9    # the largest results file a run writes unless told otherwise


class OutputTooLarge(InputError):
    """The run's estimated results file exceeds the free space or the size limit (nothing written)."""


class DiskFull(OSError):
    """No space for the next block of a results file (raised before any of it is written)."""


def _sync(f) -> None:
    """Flush HDF5's buffers and fsync the file (a power loss keeps what the flush wrote)."""
    f.flush()
    os.fsync(f.id.get_vfd_handle())


def _reserve(f, nbytes: int) -> None:
    """Reserve nbytes past the end of the open results file `f` (flexbearing.common.safe_files.
    reserve_space); DiskFull if the disk has not got them."""
    try:
        reserve_space(f.id.get_vfd_handle(), nbytes, f.filename)
    except OSError as exc:
        if exc.errno not in (errno.ENOSPC, errno.EDQUOT):
            raise
        raise _disk_full(f.filename, nbytes) from None


def _release(path) -> None:
    release_space(path)


def _disk_full(path, nbytes) -> DiskFull:
    _release(path)                 # what this run reserved is not counted as taken
    free = shutil.disk_usage(Path(path).parent).free
    return DiskFull(errno.ENOSPC, f"disk full: the next block of results needs {nbytes / 1e6:.1f} MB, "
                    f"{free / 1e6:.1f} MB are free; nothing of it was written and the file holds its "
                    f"last checkpoint: free space, then continue with --resume", str(path))


def _append(buffer: dict, t: float, values: dict) -> None:
    """One sample into a block buffer {name: [rows]}."""
    buffer.setdefault("time", []).append(np.float64(t))
    for k, v in values.items():
        buffer.setdefault(k, []).append(np.array(v, dtype=np.float64, copy=True))


def read_checkpoint(f) -> dict | None:
    """The newest valid checkpoint of an open results file, or None."""
    best = None
    if "checkpoint" not in f:
        return None
    for s in ("slot0", "slot1"):
        g = f["checkpoint"][s]
        seq = int(g.attrs.get("seq", -1))
        if seq >= 0 and "y" in g and (best is None or seq > best["seq"]):
            best = {"seq": seq, "y": g["y"][...], "dydt": g["dydt"][...] if "dydt" in g else None,
                    **{k: g.attrs[k] for k in
                    ("t", "h", "n_samples", "n_steps", "n_rejected", "wall_time")}}
    if best is not None:
        for k in ("n_samples", "n_steps", "n_rejected", "seq"):
            best[k] = int(best[k])
        for k in ("t", "h", "wall_time"):
            best[k] = float(best[k])
    return best


class _Stats:
    """Running max/mean/min (and the time of the max) over blocks; non-finite entries skipped."""

    def __init__(self):
        self.vmax, self.vmin, self.total, self.count, self.nan, self.t_max = -math.inf, math.inf, 0.0, 0, 0, math.nan

    def add(self, a: np.ndarray, t: np.ndarray) -> None:
        a = a.reshape(a.shape[0], -1)
        ok = np.isfinite(a)
        n_ok = int(np.count_nonzero(ok))
        self.nan += int(a.size - n_ok)
        if n_ok == 0:
            return
        if n_ok == a.size:
            # every entry finite (most outputs): no masked copies. a.ravel() holds the entries in
            # the order of a[ok], so the sum is the same to the bit
            row_max, vmin, total = a.max(axis=1), a.min(), a.ravel().sum()
        else:
            row_max = np.where(ok, a, -np.inf).max(axis=1)
            vmin, total = np.where(ok, a, np.inf).min(), a[ok].sum()
        r = int(np.argmax(row_max))
        if row_max[r] > self.vmax:
            self.vmax, self.t_max = float(row_max[r]), float(t[r])
        self.vmin = min(self.vmin, float(vmin))
        self.total += float(total)
        self.count += n_ok

    def result(self) -> dict:
        c = self.count
        return {"max": self.vmax if c else None, "mean": self.total / c if c else None,
                "min": self.vmin if c else None, "t_max": self.t_max if c else None, "non_finite": self.nan}


def output_statistics(f, block_rows: int = 65536) -> dict:
    """max/mean/min (and the time of the max) of every recorded output over all samples and all its
    components, read block by block; for outputs with named columns (attribute `columns`, e.g.
    outer/inner_left/inner_right contacts) the same per column under "columns". NaN entries (a
    quantity that does not exist at that instant) are left out and counted."""
    out = f["outputs"]
    time = out["time"][...]
    stats = {}
    for name, ds in output_items(out):
        if name == "time" or ds.shape[0] == 0:
            continue
        cols = [c.strip() for c in str(ds.attrs.get("columns", "")).split(",") if c.strip()]
        whole = _Stats()
        per = {c: _Stats() for c in cols}
        for i0 in range(0, ds.shape[0], block_rows):
            a = ds[i0:i0 + block_rows]
            t = time[i0:i0 + a.shape[0]]
            whole.add(a, t)
            for j, c in enumerate(cols):
                per[c].add(a[..., j], t)
        stats[name] = {"unit": str(ds.attrs.get("unit", "unknown")), "shape": list(ds.shape[1:]),
                       **whole.result()}
        if cols:
            stats[name]["columns"] = {c: per[c].result() for c in cols}
    return stats


def write_summary(results_path, extra: dict) -> dict:
    """Compute the per-output statistics from the file, write the run's compressed file with them in
    its `summary` attribute (`finish`) and <stem>.summary.json beside it (each file replaced whole,
    atomically)."""

    with h5py.File(results_path, "r") as f:
        summary = dict(extra)
        summary["results_file"] = str(Path(results_path).name)
        summary["status"] = str(f.attrs["status"])
        summary["n_samples"] = int(f["outputs/time"].shape[0]) if "outputs/time" in f else 0
        summary["outputs"] = output_statistics(f) if "outputs/time" in f else {}
        text = json.dumps(summary, indent=2, allow_nan=False, default=float)
    finish(results_path, text)
    write_text_atomic(summary_path(results_path), text + "\n")
    return summary


# attributes of the HDF5 dimension-scale API: remade by attach_scale/make_scale, never copied
_SCALE_ATTRS = ("DIMENSION_LIST", "REFERENCE_LIST", "CLASS", "NAME", "DIMENSION_LABELS")


def finish(path, summary_text: str) -> None:
    """Replace a complete run's file by its compressed form (COMPRESSION on every output, the same
    chunks, attributes and dimension scales), with `summary_text` in its `summary` attribute. The
    new file is written beside it and renamed over it (flexbearing.common.safe_files.atomic_output):
    a kill at any instant leaves the uncompressed file or the compressed one, each whole. With too
    little free space for the copy, the uncompressed file is kept (the summary written into it)."""

    path = Path(path)
    # a compressed copy a SIGKILL interrupted: the caller holds the claim on this file
    # (flexbearing.common.file_lock), so no other process is finishing it (unlink never follows a link)
    for stale in path.parent.glob(f".{path.name}.*.finishing.h5"):
        stale.unlink(missing_ok=True)
    try:
        with atomic_output(path, suffix=".finishing.h5", reserve=path.stat().st_size + RESERVE_MARGIN) as tmp:
            with h5py.File(path, "r") as src, h5py.File(tmp, "w") as dst:
                for k, v in src.attrs.items():
                    dst.attrs[k] = v
                dst.attrs["summary"] = summary_text
                for name in src:
                    if name != "outputs":
                        src.copy(src[name], dst, name=name)
                if "outputs" not in src:
                    return
                sout, out = src["outputs"], dst.create_group("outputs")
                names = [k for k, _ in output_items(sout)]
                for k, ds in sout.items():          # the dimension scales (labels or indices)
                    if k not in names:
                        scale = out.create_dataset(k, data=ds[()], dtype=ds.dtype)
                        _copy_attrs(ds, scale)
                        scale.make_scale(k)
                for k in sorted(names, key=lambda k: k != "time"):
                    ds = sout[k]
                    new = out.create_dataset(k, shape=ds.shape, maxshape=ds.maxshape, dtype=ds.dtype,
                                             chunks=ds.chunks, **COMPRESSION)
                    rows = max(1, (64 << 20) // max(1, ds.dtype.itemsize * int(np.prod(ds.shape[1:]))))
                    for i0 in range(0, ds.shape[0], rows):
                        new[i0:i0 + rows] = ds[i0:i0 + rows]
                    _copy_attrs(ds, new)
                    if k == "time":
                        new.make_scale("time")
                for k in names:
                    ds, new = sout[k], out[k]
                    for axis in range(ds.ndim if k != "time" else 0):
                        for scale in ds.dims[axis].values():
                            new.dims[axis].attach_scale(out[scale.name.rsplit("/", 1)[-1]])
    except OSError as exc:
        if exc.errno not in (errno.ENOSPC, errno.EDQUOT) and "errno = 28" not in str(exc):
            raise
        _summary_in_place(path, summary_text)        # the disk filled while copying


def _copy_attrs(src, dst) -> None:
    for a, v in src.attrs.items():
        if a not in _SCALE_ATTRS:
            dst.attrs[a] = v


def _summary_in_place(path, summary_text: str) -> None:
    with h5py.File(path, "r+") as f:
        f.attrs["summary"] = summary_text
        _sync(f)


def read_outputs(path) -> dict[str, np.ndarray]:
    """All recorded outputs of a results file as arrays (small runs, tests, reports)."""
    with h5py.File(path, "r") as f:
        return {k: ds[...] for k, ds in output_items(f["outputs"])}


def check_run(path) -> Path:
    """`path` as a Path if it is a flexbearing results file (InputError naming it otherwise)."""
    path, f = _open_run(path)
    f.close()
    return path


def _open_run(path):
    """(Path, the file open for reading) of a flexbearing results file; InputError naming it otherwise."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"run file {str(path)!r} does not exist (a results file written by "
                         f"`flexbearing run`, .h5)")
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise InputError(f"run file {str(path)!r} is not an HDF5 file ({exc})") from None
    fmt = f.attrs.get("format")
    if fmt != "flexbearing-results" or "outputs/time" not in f:
        f.close()
        raise InputError(f"{path} is not a flexbearing results file (format attribute {fmt!r}, "
                         f"expected 'flexbearing-results' with /outputs/time)")
    return path, f


class Run:
    """One run's results file, opened once for reading and handed to every reader of it: the
    report's windows, plots, field export, stress picture, export and the report itself.

        with Run("run.h5") as run:
            run.t, run.scene, run.dt          # sample times (s), the Scene (or None), sample interval (s)
            run.outputs["contact_stress"]     # an h5py dataset (SI, its `unit` attribute)

    The file is opened and checked once (as `check_run` checks it); the sample times, the scene and the sample interval
    are read once, when first asked for. A reader given a path instead of a Run opens its own
    (`opened`), so each reader still works alone."""

    def __init__(self, path):
        self.path, self.file = _open_run(path)
        self._t = self._scene = None
        self._scene_read = False

    @property
    def outputs(self):
        """The /outputs group (h5py)."""
        return self.file["outputs"]

    @property
    def attrs(self):
        return self.file.attrs

    @property
    def t(self) -> np.ndarray:
        """Sample times, s."""
        if self._t is None:
            self._t = self.outputs["time"][...]
        return self._t

    @property
    def scene(self):
        """The Scene the run was made from (scene_of_run), or None."""
        if not self._scene_read:
            self._scene, self._scene_read = scene_of_run(self.file), True
        return self._scene

    @property
    def dt(self) -> float:
        """The sample interval, s (sample_interval)."""
        return sample_interval(self.file, self.t)

    @property
    def name(self) -> str:
        return str(self.attrs.get("scene_name", self.path.stem))

    @property
    def status(self) -> str:
        return str(self.attrs.get("status", ""))

    @property
    def cage_model(self) -> str:
        return str(self.attrs.get("cage_model", ""))

    @property
    def flexible(self) -> bool:
        """True when the run recorded the flexible cage's modal coordinates (its stress field)."""
        return "cage_modal_coordinates_full" in self.outputs

    def __contains__(self, name: str) -> bool:
        return name in self.outputs

    def close(self) -> None:
        if self.file.id.valid:
            self.file.close()

    def __enter__(self) -> "Run":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


@contextmanager
def opened(run):
    """`run` itself if it is an open Run (left open), else a Run of the path `run`, closed after."""
    if isinstance(run, Run):
        yield run
        return
    with Run(run) as r:
        yield r


def scene_of_run(f):
    """The Scene a run was made from (its stored TOML text; f an open results file), or None if it
    cannot be parsed."""
    from flexbearing.simulation.scene import cad_from_record, loads_scene, parse_scene
    if "scene" not in f:
        return None
    raw = f["scene"][()]
    text = raw.decode() if isinstance(raw, bytes) else str(raw)
    # a CAD cage from what the run recorded, never by reading the CAD file the stored scene names
    with cad_from_record(str(f.attrs.get("cad_cage", ""))):
        try:
            return loads_scene(text, str(f.attrs.get("scene_path", "")))
        except Exception:
            pass
        try:   # results.py stores the parsed scene as JSON when it has no TOML text (case sets)
            return parse_scene(json.loads(text), path=str(f.attrs.get("scene_path", "")))
        except Exception:
            return None


def sample_interval(f, t) -> float:
    """The run's sample interval, s: its attribute, else the mean spacing of the samples t."""
    return float(f.attrs.get("sample_interval", np.diff(t).mean() if len(t) > 1 else 1.0))
