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
"""
from __future__ import annotations

import contextlib
import ctypes
import errno
import os
import shutil
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


@contextlib.contextmanager
def atomic_output(target, suffix: str = ".tmp", reserve: int = 0):
    """Yield the path of a new, empty temporary file beside `target` (unique name, created
    exclusively); when the body returns, fsync it, give it the umask's permissions and rename it
    over `target`. On any exception (ENOSPC, Ctrl-C, ...) the temporary is removed and the
    exception goes on; `target` is then untouched. reserve: bytes to reserve for the temporary
    before the body writes it (reserve_space: ENOSPC then, before anything is written)."""
    target = Path(target)
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
        fd = os.open(tmp, os.O_RDONLY | os.O_NOFOLLOW)
        try:
            os.fsync(fd)
            os.fchmod(fd, 0o666 & ~_umask())
        finally:
            os.close(fd)
        os.replace(tmp, target)
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
