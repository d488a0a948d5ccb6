"""Files written so that a crash, a full disk or a planted symlink cannot damage anything.

Every file flexbearing writes whole (a cache entry, a summary, an export, a report) goes through
`atomic_output(target)`: the content is written to a temporary of a unique, unpredictable name in
the target's own folder, created exclusively (`tempfile.mkstemp`: O_CREAT | O_EXCL, so a symlink
or a file planted at that name is never opened, let alone followed), flushed to the disk (fsync),
then renamed over the target (`os.replace`, atomic on one file system; a symlink at the target's
name is replaced itself, its target is never written) and the folder fsynced, so that after a
SIGKILL or a power loss the target is either the old file or the whole new one. On every exit
path that does not reach the rename (an exception, ENOSPC, Ctrl-C) the temporary is removed.

Permissions: mkstemp creates 0600; a finished file gets 0666 minus the process's umask instead,
as an ordinary `open()` would (a shared cache needs files its group can read: run with umask 002
or 022 and a group-owned, setgid cache folder; see README "Studies and validations on a Dask
cluster").

`refuse_overwriting_inputs(output, inputs)` refuses an output that is one of the command's inputs
(the same path, or the same file under another name: st_dev and st_ino) or a symlink.

`OutputPlan`: every file one command writes, declared before any work and checked by one rule
(not an input, not a link or through one, not over something of another kind, no two outputs at
one name), then written into staging folders and renamed into place (see the section below).
Each command declares its plan in one function (`planned_outputs` of its command module,
flexbearing.analysis.report.report_outputs, flexbearing.studies.study.study_outputs);
tests/test_output_paths.py checks what each command writes against it.
"""
from __future__ import annotations

import contextlib
import ctypes
import errno
import os
import shutil
import socket
import stat
import tempfile
from pathlib import Path
from fnmatch import fnmatch

from flexbearing.common.validation import InputError


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def fsync_folder(folder) -> None:
    """fsync a folder so that a rename in it survives a power loss (no-op where unsupported)."""
    try:
        fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


_FALLOC_FL_KEEP_SIZE = 1
_FALLOC_FL_PUNCH_HOLE = 2
_libc = None


def _fallocate(fd: int, mode: int, offset: int, length: int) -> int:
    """Linux fallocate(2); 0 or the errno."""
    global _libc
    if _libc is None:
        _libc = ctypes.CDLL(None, use_errno=True)
        _libc.fallocate.argtypes = (ctypes.c_int, ctypes.c_int, ctypes.c_longlong, ctypes.c_longlong)
    return 0 if _libc.fallocate(fd, mode, offset, length) == 0 else ctypes.get_errno()


def no_space(path, nbytes: int) -> OSError:
    """The one-line ENOSPC error for `path`, with what is needed and what is free."""
    free = shutil.disk_usage(Path(path).parent).free
    return OSError(errno.ENOSPC, f"no space left: {nbytes / 1e6:.1f} MB needed, {free / 1e6:.1f} MB free; "
                   f"nothing was written: free space and run again", str(path))


def reserve_space(fd: int, nbytes: int, path) -> None:
    """Allocate nbytes past the end of the open file fd without changing its size (fallocate
    KEEP_SIZE), so that writes into that range cannot fail for lack of space (a library such as
    HDF5 does not survive ENOSPC in the middle of its metadata writes: the issue's segmentation
    fault). Where the file system cannot, the free space is checked instead. OSError ENOSPC
    (no_space) if there is not enough."""
    size = os.fstat(fd).st_size
    err = _fallocate(fd, _FALLOC_FL_KEEP_SIZE, size, int(nbytes))
    if err in (errno.ENOSPC, errno.EDQUOT) or (err and shutil.disk_usage(Path(path).parent).free < nbytes):
        _fallocate(fd, _FALLOC_FL_PUNCH_HOLE | _FALLOC_FL_KEEP_SIZE, size, 1 << 40)
        raise no_space(path, nbytes)


def release_space(path) -> None:
    """Give back what reserve_space allocated past the end of `path` (a hole punched there)."""
    try:
        fd = os.open(path, os.O_WRONLY | os.O_NOFOLLOW)
    except OSError:
        return
    try:
        _fallocate(fd, _FALLOC_FL_PUNCH_HOLE | _FALLOC_FL_KEEP_SIZE, os.fstat(fd).st_size, 1 << 40)
    finally:
        os.close(fd)


def _put_in_place(written, target) -> None:
    """A finished file onto its destination: flushed to disk, given the umask's permissions (it was
    created 0600), then renamed over `target` (atomic on one file system)."""
    fd = os.open(written, os.O_RDONLY | os.O_NOFOLLOW)
    try:
        os.fsync(fd)
        os.fchmod(fd, 0o666 & ~_umask())
    finally:
        os.close(fd)
    os.replace(written, target)


@contextlib.contextmanager
def atomic_output(target, suffix: str = ".tmp", reserve: int = 0):
    """Yield the path of a new, empty temporary file beside `target` (unique name, created
    exclusively); when the body returns, fsync it, give it the umask's permissions and rename it
    over `target`. On any exception (ENOSPC, Ctrl-C, ...) the temporary is removed and the
    exception goes on; `target` is then untouched. reserve: bytes to reserve for the temporary
    before the body writes it (reserve_space: ENOSPC then, before anything is written)."""
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=suffix, dir=target.parent)
    try:
        if reserve:
            reserve_space(fd, reserve, target)     # the message names the file the user asked for
    except BaseException:
        os.close(fd)
        os.unlink(tmp)
        raise
    os.close(fd)
    try:
        yield Path(tmp)
        if reserve:
            release_space(tmp)
        _put_in_place(tmp, target)
        fsync_folder(target.parent)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def write_text_atomic(target, text: str) -> Path:
    """`target` holding `text` (UTF-8), written by atomic_output."""
    with atomic_output(target) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(target)


def write_bytes_atomic(target, data: bytes) -> Path:
    with atomic_output(target) as tmp:
        tmp.write_bytes(data)
    return Path(target)


def same_file(a, b) -> bool:
    """True if a and b are the same file: the same path once resolved, or the same inode on the
    same device (a hard link)."""
    try:
        sa, sb = os.stat(a), os.stat(b)
    except OSError:
        return Path(a).resolve() == Path(b).resolve()
    return (sa.st_dev, sa.st_ino) == (sb.st_dev, sb.st_ino)


def refuse_overwriting_inputs(output, inputs, option: str = "-o") -> None:
    """InputError if `output` is a symlink or is (the same file as) one of `inputs`; nothing is
    written or changed. The names are the user's, so that the message says which."""
    output = Path(output)
    if output.is_symlink():
        raise InputError(f"{option} {output} is a symbolic link (to {os.readlink(output)}): flexbearing "
                         f"does not write through links in its output folders; give the real path or "
                         f"remove the link")
    if not output.exists():
        return
    for inp in inputs:
        if inp is not None and Path(inp).exists() and same_file(output, inp):
            raise InputError(f"{option} {output} is the input file {inp}: writing there would replace "
                             f"the input; choose another output name")


def refuse_link_folder(folder, option: str = "-o") -> None:
    """InputError if `folder` (an output folder) is itself a symbolic link or not a folder."""
    folder = Path(folder)
    if folder.is_symlink():
        raise InputError(f"{option} {folder} is a symbolic link (to {os.readlink(folder)}): give the "
                         f"real folder")
    if folder.exists() and not folder.is_dir():
        raise InputError(f"{option} {folder} is a file, not a folder: give a folder name")


def open_new_exclusive(path, mode: int = 0o666) -> int:
    """An fd of `path` opened for writing without following a symlink at that name
    (O_NOFOLLOW); an existing regular file is truncated, anything else refused (OSError ELOOP
    for a link)."""
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_NOFOLLOW | os.O_CLOEXEC, mode)
    if not stat.S_ISREG(os.fstat(fd).st_mode):
        os.close(fd)
        raise OSError(errno.EINVAL, "not a regular file", str(path))
    os.ftruncate(fd, 0)
    return fd


def check_output_folder(folder, names, inputs, option: str = "-o", patterns=()) -> None:
    """Before a command writes the files `names` (and names matching the glob `patterns`) into
    `folder`: InputError if the folder is a link or a file, if one of those names there is a
    symbolic link (planted: writing would follow it), or is one of the command's `inputs` (the
    same file: writing would replace the input). Nothing is written or changed."""
    folder = Path(folder)
    refuse_link_folder(folder, option)
    if not folder.is_dir():
        return
    names = set(names)
    for entry in folder.iterdir():
        if entry.name not in names and not any(fnmatch(entry.name, p) for p in patterns):
            continue
        if entry.is_symlink():
            raise InputError(f"{option} {folder}: {entry.name} there is a symbolic link (to "
                             f"{os.readlink(entry)}), which flexbearing would write through: remove "
                             f"it or choose another folder")
        for inp in inputs:
            if inp is not None and Path(inp).exists() and same_file(entry, inp):
                raise InputError(f"{option} {folder}: {entry} is the input {inp}, and the output "
                                 f"{entry.name} would replace it: choose another folder")


# ---------------------------------------------------------------- every output of a command, one rule
#
# A command declares every file it will write before it starts any work (an OutputPlan: the files by
# name, and the folders it writes into with the names and glob patterns of what goes there), and
# `OutputPlan.check()` applies one rule to each: not an input of the run (the same path, or the
# same file under another name: st_dev/st_ino, so a hard link counts), not a symbolic link and not
# reached through one (the file itself, a declared folder, or a missing parent the command would
# create), not over something of another kind (a folder where a file goes, a file where a folder
# goes, a flexbearing results or reduced-cage HDF5 file where another file goes), and no two
# outputs at the same name. The command then writes into a staging folder (OutputPlan.staging:
# a new folder of unique name beside each destination, mode 0700) under the final names (an XDMF
# names its .h5 by its final name), and OutputPlan.commit() renames each staged file over its
# destination (atomic per file; fsynced) after checking that it was declared: a file that was not
# declared is a program error, raised, and nothing of it lands. On any exception the staging
# folders are removed and the destinations are untouched.
#
# A SIGKILL (or a power loss) skips that removal. So a staging folder's name carries its owner,
# ".flexbearing-staging-<host>-<pid>-<random>", and the next command that stages beside it removes
# the folders of owners on this host that are no longer alive (remove_stale_staging). A live
# owner's folder, another host's (its process table is not ours: a shared file system) and a name
# of another form are never touched; a reused pid only keeps a dead owner's folder a while longer.

_STAGE_PREFIX = ".flexbearing-staging-"


def _stage_owner(name: str) -> tuple[str, int] | None:
    """(host, pid) of a staging folder's name (the comment above), None for another name."""
    if not name.startswith(_STAGE_PREFIX):
        return None
    parts = name[len(_STAGE_PREFIX):].rsplit("-", 2)       # the random tail of mkdtemp has no "-"
    if len(parts) != 3 or not parts[1].isdigit():
        return None
    return parts[0], int(parts[1])


def _alive(pid: int) -> bool:
    """Whether process pid exists on this host (signal 0 checks without sending anything)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:                 # it exists, owned by another user
        return True
    return True


def remove_stale_staging(folder) -> list[Path]:
    """Remove the staging folders in `folder` whose owner (this host, a pid) is no longer alive:
    what a SIGKILLed command left (the comment above). Returns the folders removed."""
    host = socket.gethostname()
    removed = []
    try:
        entries = list(Path(folder).iterdir())
    except OSError:
        return removed
    for entry in entries:
        owner = _stage_owner(entry.name)
        if owner is None or owner[0] != host or _alive(owner[1]) or entry.is_symlink() or not entry.is_dir():
            continue
        shutil.rmtree(entry, ignore_errors=True)
        removed.append(entry)
    return removed

# HDF5 files of flexbearing whose kind is recognised by their root attributes: writing another
# kind of file over one would destroy a run or a cache entry
_H5_KINDS = (("format", "results file of a run"), ("schema", "reduced cage file"))


def h5_file_kind(path) -> str | None:
    """'results file of a run' / 'reduced cage file' for such a flexbearing HDF5 file, else None."""
    try:
        with open(path, "rb") as fh:
            if fh.read(8) != b"\x89HDF\r\n\x1a\n":
                return None
        import h5py
        with h5py.File(path, "r") as f:
            for attr, kind in _H5_KINDS:
                if attr in f.attrs:
                    return kind
    except (OSError, ValueError):
        return None
    return None


class OutputPlan:
    """The files one command run will write, declared before any work; see the comment above.

        plan = OutputPlan("flexbearing mesh", inputs=[cad_file])
        plan.file(out, "-o", kind="mesh")                 # X.msh
        plan.file(out.with_suffix(".h5"), "-o", kind="XDMF heavy data")
        plan.check()                                       # InputError, nothing written
        with plan.writing():                               # staging; commit on success
            build(plan.staged(out))
    """

    def __init__(self, command: str, inputs=(), comm=None):
        self.command = command
        # an MPI communicator when every rank writes a part (dolfinx's XDMF): the staging folders
        # are made on rank 0 and shared, commit and discard run on rank 0 after a barrier
        self.comm = comm if comm is not None and comm.size > 1 else None
        self.inputs = [Path(p) for p in inputs if p is not None]
        self.files: dict[Path, tuple[str, str | None]] = {}        # path -> (option, kind of h5)
        self.folders: dict[Path, tuple[str, tuple[str, ...]]] = {}  # folder -> (option, patterns)
        self._stages: dict[Path, Path] = {}

    # -- declaring
    def file(self, path, option: str, h5_kind: str | None = None) -> Path:
        """Declare the file `path` (named by `option`); h5_kind: what an HDF5 file of this output
        is, when it is one of _H5_KINDS (it may then replace a file of that kind)."""
        path = Path(path)
        key = Path(os.path.abspath(path))
        if key in self.files:
            raise InputError(f"{option} {path}: {self.command} would write two of its outputs to this "
                             f"one name (also {self.files[key][0]}); give them different names")
        self.files[key] = (option, h5_kind)
        return path

    def folder(self, path, option: str, names=(), patterns=()) -> Path:
        """Declare the folder `path` and the files it will hold: `names` exactly, and files of
        data-dependent names matching the glob `patterns`."""
        path = Path(path)
        key = Path(os.path.abspath(path))
        old = self.folders.get(key, (option, ()))
        self.folders[key] = (old[0], tuple(old[1]) + tuple(patterns))
        for n in names:
            self.file(path / n, option)
        return path

    def include(self, other: "OutputPlan") -> "OutputPlan":
        """Add the outputs and inputs of another plan (a command that runs another's work)."""
        self.inputs += [p for p in other.inputs if p not in self.inputs]
        for path, (option, kind) in other.files.items():
            self.file(path, option, kind)
        for folder, (option, patterns) in other.folders.items():
            self.folder(folder, option, patterns=patterns)
        return self

    def names(self) -> list[str]:
        """Every declared file (absolute) and pattern (folder/glob), sorted: what the command writes."""
        return sorted([str(p) for p in self.files]
                      + [str(f / pat) for f, (_, pats) in self.folders.items() for pat in pats])

    def covers(self, path) -> bool:
        """True if `path` is a declared file or matches a declared folder's pattern."""
        key = Path(os.path.abspath(path))
        if key in self.files:
            return True
        opt_pats = self.folders.get(key.parent)
        return bool(opt_pats) and any(fnmatch(key.name, p) for p in opt_pats[1])

    # -- the rule
    def _refuse(self, option: str, path, why: str):
        raise InputError(f"{option} {path}: {why}; nothing was written")

    def _check_parents(self, option: str, path: Path) -> None:
        """The parents the command would create (missing ones) must not be dangling links; a
        declared folder must not be a link nor a file."""
        for parent in path.parents:
            if parent.exists():
                if not parent.is_dir():
                    self._refuse(option, path, f"{parent} is a file, not a folder")
                break
            if parent.is_symlink():
                self._refuse(option, path, f"{parent} is a symbolic link (to {os.readlink(parent)}) "
                                           f"to a missing folder: flexbearing does not write through links")

    def _check_file(self, option: str, path: Path, h5_kind: str | None) -> None:
        if path.is_symlink():
            self._refuse(option, path, f"it is a symbolic link (to {os.readlink(path)}): flexbearing "
                                       f"does not write through links; give the real path or remove the link")
        for inp in self.inputs:
            if os.path.abspath(inp) == os.path.abspath(path) or (
                    path.exists() and inp.exists() and same_file(path, inp)):
                self._refuse(option, path, f"it is the input file {inp} of this run: writing "
                                           f"there would replace it; choose another output name")
        if not path.exists():
            return
        if path.is_dir():
            self._refuse(option, path, "it is a directory, and this output is a file; give a file name")
        if not path.is_file():
            self._refuse(option, path, "it is not a regular file (a device, a pipe or a socket)")
        if path.suffix == ".h5":
            kind = h5_file_kind(path)
            if kind is not None and kind != h5_kind:
                self._refuse(option, path, f"it is a {kind}, which this output ("
                                           f"{h5_kind or 'another kind of file'}) would replace; "
                                           f"choose another name")

    def check(self) -> "OutputPlan":
        """InputError (one line naming the option and the path) if an output breaks the rule;
        nothing is written or changed."""
        for folder, (option, patterns) in self.folders.items():
            if folder.is_symlink():
                self._refuse(option, folder, f"it is a symbolic link (to {os.readlink(folder)}): give "
                                             f"the real folder")
            if folder.exists() and not folder.is_dir():
                self._refuse(option, folder, "it is a file, and this output is a folder; give a folder name")
            self._check_parents(option, folder / "x")
            if folder.is_dir() and patterns:
                for entry in folder.iterdir():
                    if any(fnmatch(entry.name, p) for p in patterns) and entry not in self.files:
                        self._check_file(option, entry, None)
        for path, (option, h5_kind) in self.files.items():
            if path.parent not in self.folders:
                self._check_parents(option, path)
            self._check_file(option, path, h5_kind)
        return self

    # -- writing
    def staged(self, path) -> Path:
        """Where to write the declared `path` now: the same name in the staging folder beside it."""
        key = Path(os.path.abspath(path))
        if not self.covers(key):
            raise RuntimeError(f"{self.command}: output {path} was not declared in its OutputPlan")
        return self._stage_of(key.parent) / key.name

    def _stage_of(self, dest: Path) -> Path:
        stage = self._stages.get(dest)
        if stage is None:
            if self.comm is None or self.comm.rank == 0:
                dest.mkdir(parents=True, exist_ok=True)
                remove_stale_staging(dest)
                stage = tempfile.mkdtemp(prefix=f"{_STAGE_PREFIX}{socket.gethostname()}-{os.getpid()}-", dir=dest)
            if self.comm is not None:
                stage = self.comm.bcast(stage, root=0)
            stage = self._stages[dest] = Path(stage)
        return stage

    def staging(self, folder) -> Path:
        """The staging folder of the declared output folder `folder` (created now): write there
        the files of the names and patterns declared for `folder`."""
        key = Path(os.path.abspath(folder))
        if key not in self.folders:
            raise RuntimeError(f"{self.command}: output folder {folder} was not declared in its OutputPlan")
        return self._stage_of(key)

    def final(self, staged_path) -> Path:
        """The destination of a staged path (the inverse of staged)."""
        staged_path = Path(os.path.abspath(staged_path))
        for dest, stage in self._stages.items():
            if staged_path.parent == stage:
                return dest / staged_path.name
        return staged_path

    def commit(self) -> list[Path]:
        """Rename every staged file over its destination; RuntimeError (nothing of it renamed) for
        one that was not declared. Returns the destinations written."""
        if self.comm is not None:
            self.comm.barrier()
            if self.comm.rank != 0:
                self._stages.clear()
                self.comm.barrier()
                return []
        moves = []
        for dest, stage in self._stages.items():
            for entry in sorted(stage.iterdir()):
                target = dest / entry.name
                if entry.is_dir() or not self.covers(target):
                    raise RuntimeError(f"{self.command} wrote {target}, which it did not declare in its "
                                       f"OutputPlan (a program error: declare every output)")
                moves.append((entry, target))
        for entry, target in moves:
            _put_in_place(entry, target)
        for dest, stage in list(self._stages.items()):
            shutil.rmtree(stage, ignore_errors=True)
            fsync_folder(dest)
        self._stages.clear()
        if self.comm is not None:
            self.comm.barrier()
        return [t for _, t in moves]

    def discard(self) -> None:
        """Remove the staging folders and what is in them (the destinations are untouched)."""
        for stage in self._stages.values():
            shutil.rmtree(stage, ignore_errors=True)
        self._stages.clear()

    @contextlib.contextmanager
    def writing(self):
        """Stage the outputs in the body; commit when it returns, discard on any exception."""
        try:
            yield self
            self.commit()
        except BaseException:
            self.discard()
            raise
