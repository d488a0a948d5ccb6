"""Where cached meshes and reduced cages live, and the content hash that keys them."""
from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path
from flexbearing.common.safe_files import write_text_atomic as _atomic
from flexbearing.common.validation import InputError


def cache_dir() -> Path:
    """$FLEXBEARING_CACHE, else ~/.cache/flexbearing. Created on first use (mode 0777 minus the
    umask). A cache shared by a group of users (a cluster's workers) needs a folder its group
    owns with the setgid bit and a umask of 002 (files rw for the group) or 022 (readable): the
    cache's files are created with the umask's permissions (flexbearing.common.safe_files)."""
    root = Path(os.environ.get("FLEXBEARING_CACHE", Path.home() / ".cache" / "flexbearing"))
    if root.exists() and not root.is_dir():
        raise InputError(f"cache folder {root} (FLEXBEARING_CACHE) is a file, not a folder: point "
                         f"FLEXBEARING_CACHE at a folder, or move the file away")
    try:
        root.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cache folder {root} (FLEXBEARING_CACHE) cannot be created ({exc.strerror}): "
                         f"point FLEXBEARING_CACHE at a writable folder") from None
    return root


def content_hash(obj) -> str:
    """SHA-256 (first 16 hex digits) of the canonical JSON of obj (dicts sorted, floats repr'd)."""
    text = json.dumps(obj, sort_keys=True, separators=(",", ":"), default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def file_sha256(path) -> str:
    """SHA-256 of a file's bytes (an input known by its content, not its name)."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def write_text_atomic(path, text: str) -> Path:
    """Write text to path through a temporary file and a rename (flexbearing.common.safe_files:
    created exclusively, fsynced, a link at the name replaced, never followed; permissions those
    of the umask, as every cache file): a concurrent reader never sees half a file."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    return _atomic(path, text)


# the sections a gmsh 4.1 .msh file can end with (its last line; the mesh's elements or what
# follows them): a file cut short ends elsewhere, or mid-line
_MSH_LAST = (b"$EndElements", b"$EndPeriodic", b"$EndGhostElements", b"$EndParametrizations",
             b"$EndNodeData", b"$EndElementData", b"$EndElementNodeData", b"$EndInterpolationScheme")


def msh_is_whole(path) -> bool:
    """True when a gmsh .msh file ends as gmsh ends one: a newline after the end of its elements
    or of a section that follows them (_MSH_LAST): a file a full disk cut short does not."""
    try:
        with open(path, "rb") as f:
            f.seek(0, os.SEEK_END)
            n = f.tell()
            f.seek(max(0, n - 256))
            tail = f.read()
    except OSError:
        return False
    return tail.endswith(b"\n") and tail.rstrip().rsplit(b"\n", 1)[-1].strip() in _MSH_LAST
