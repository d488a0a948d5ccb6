"""An exclusive claim on an output file, taken before the file is touched.

A results file is written by one process at a time. `exclusive_file(path)` opens the file without
truncating it (creating it empty if it does not exist) and takes an open-file-description lock
(Linux `F_OFD_SETLK`, a write lock on the whole file) on that descriptor, held until the context
ends or the process dies (the kernel drops it with the descriptor, even after SIGKILL). A second
process asking for the same file is refused at once, before it truncates or writes anything.

Why an OFD lock and not flock(): HDF5 (>= 1.10) flock()s the files it opens, and two flock()s on
two descriptors of one file conflict even inside one process, so a flock held here would stop our
own h5py from opening the file. OFD locks live in the POSIX-lock namespace, which Linux keeps apart
from flock(), and unlike classic POSIX locks they are not dropped when another descriptor of the
file (h5py's) is closed. A process that holds the file through HDF5 only (a report reading it,
a foreign h5py writer) is detected by probing HDF5's own flock once, and released at once.
"""
from __future__ import annotations

import errno
import fcntl
import os
import struct
from contextlib import contextmanager
from pathlib import Path

from flexbearing.common.validation import InputError

_BUSY = (errno.EAGAIN, errno.EACCES, errno.EWOULDBLOCK)


def _what_to_do(path: Path) -> str:
    return f"wait until it finishes, or write to another file with -o (e.g. {path.with_stem(path.stem + '_2')})"


@contextmanager
def exclusive_file(path, what: str = "results file"):
    """Hold an exclusive claim on `path` for the body of the `with`; yields True if the file was
    created here. InputError (naming the file and what to do) if another process holds it, if it
    is a directory or if it cannot be opened for writing. A file created here that is still empty
    when the body fails (nothing was written) is removed again."""
    path = Path(path)
    if path.is_dir():
        raise InputError(f"{what} {path} is a directory: give a file name (e.g. {path / 'run.h5'})")
    created = not path.exists()
    try:
        fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW, 0o666)   # never through a planted link
    except OSError as exc:
        raise InputError(f"{what} {path} cannot be written: {exc.strerror}; choose a file in a "
                         f"writable folder with -o") from None
    try:
        try:   # struct flock: l_type, l_whence, l_start, l_len (0 = to the end), l_pid (0 for OFD)
            fcntl.fcntl(fd, fcntl.F_OFD_SETLK, struct.pack("hhqqii", fcntl.F_WRLCK, os.SEEK_SET, 0, 0, 0, 0))
        except OSError as exc:
            if exc.errno in _BUSY:
                raise InputError(f"{what} {path} is being written by another flexbearing process; "
                                 f"it was left untouched: {_what_to_do(path)}") from None
            raise
        try:   # HDF5's own lock: another process has the file open through h5py
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            fcntl.flock(fd, fcntl.LOCK_UN)
        except OSError as exc:
            if exc.errno in _BUSY:
                raise InputError(f"{what} {path} is open in another process (HDF5 lock held); it was "
                                 f"left untouched: {_what_to_do(path)}") from None
            raise
        try:
            yield created
        except BaseException:
            if created and os.fstat(fd).st_size == 0:
                path.unlink(missing_ok=True)          # nothing written: leave no empty file behind
            raise
    finally:
        os.close(fd)
