"""A cache that cannot lie (issue 36, part 3): the reduced cage's content checked against the digest
stored with it, a damaged stress-search file rebuilt, temporaries that cannot be hijacked and do
not outlive a failure, and permissions a shared cache can use."""
import errno
import os
import shutil

import h5py
import numpy as np
import pytest

from flexbearing.common.safe_files import atomic_output, write_text_atomic
from flexbearing.common.validation import InputError
from flexbearing.fem_cage import reduced_cage as rcf
from test_reduced_cage import _synthetic


def _cache_file(folder, key: str, seed: int = 0, parameters=None):
    return rcf.write(folder / f"{key}.h5", _synthetic(seed=seed),
                     {"content_hash": key, "parameters": parameters if parameters is not None else {"k": key}})


def _flip_bit(path, dataset: str, byte: int = 3):
    """Flip one bit of a dataset's stored bytes in the file itself (not through HDF5)."""
    with h5py.File(path, "r") as f:
        d = f[dataset]
        # a chunked (compressed) dataset has no single offset: its first chunk's
        offset = d.id.get_offset() if d.chunks is None else d.id.get_chunk_info(0).byte_offset
    with open(path, "r+b") as fh:
        fh.seek(offset + byte)
        b = fh.read(1)[0]
        fh.seek(offset + byte)
        fh.write(bytes([b ^ 0x10]))


def test_a_written_reduced_cage_verifies_and_its_digest_is_its_content(tmp_path):
    p = _cache_file(tmp_path, "aaaa")
    rcf.verify(p, expect_key="aaaa")
    with h5py.File(p, "r") as f:
        assert f.attrs["data_sha256"] == rcf.data_digest(f)
    # the same arrays give the same digest; other arrays another one
    q = _cache_file(tmp_path / "b", "aaaa") if (tmp_path / "b").mkdir() is None else None
    r = _cache_file(tmp_path, "cccc", seed=1)
    with h5py.File(p) as a, h5py.File(q) as b, h5py.File(r) as c:
        assert a.attrs["data_sha256"] == b.attrs["data_sha256"] != c.attrs["data_sha256"]


@pytest.mark.parametrize("dataset", ["modes/interface", "stress/modes", "modes/vertex_displacement",
                                     "modes/omega"])
def test_a_flipped_bit_in_the_modes_is_detected_and_named(tmp_path, dataset):
    p = _cache_file(tmp_path, "aaaa")
    _flip_bit(p, dataset)
    # in a compressed (schema 5 float32) table the flipped bit breaks the chunk's zlib checksum:
    # the file is named as damaged before any digest can be computed
    with pytest.raises(InputError, match=rf"{p}.*(does not match the digest|damaged or truncated).*delete {p}"):
        rcf.verify(p)


def test_another_cages_valid_file_copied_over_the_key_is_refused(tmp_path, monkeypatch):
    monkeypatch.setenv("FLEXBEARING_CACHE", str(tmp_path))
    key = {"cage": "mine"}
    target = rcf.cache_path(key)
    target.parent.mkdir(parents=True)
    other = _cache_file(tmp_path, "0123456789abcdef", seed=2)       # valid, of another key
    shutil.copyfile(other, target)
    with pytest.raises(InputError, match=rf"holds the cage of key 0123456789abcdef, not {target.stem}"):
        rcf.find_cached(key)
    # and with its key attribute edited to match, the digest no longer does
    with h5py.File(target, "r+") as f:
        f.attrs["content_hash"] = target.stem
    with pytest.raises(InputError, match="does not match the digest"):
        rcf.find_cached(key)


def test_truncated_non_hdf5_folder_and_undigested_cache_files_name_the_file_and_the_fix(tmp_path):
    p = _cache_file(tmp_path, "aaaa")
    data = p.read_bytes()
    p.write_bytes(data[: len(data) // 2])
    with pytest.raises(InputError, match=rf"{p} is damaged or truncated.*delete {p}"):
        rcf.verify(p)
    p.write_bytes(b"not an hdf5 file at all\n" * 10)
    with pytest.raises(InputError, match=rf"{p} is not an HDF5 file.*delete {p}"):
        rcf.verify(p)
    p.unlink()
    p.mkdir()
    with pytest.raises(InputError, match=rf"{p} is a folder"):
        rcf.verify(p)
    q = _cache_file(tmp_path, "bbbb")
    with h5py.File(q, "r+") as f:
        del f.attrs["data_sha256"]
    with pytest.raises(InputError, match="no content digest"):
        rcf.verify(q)


def test_a_cache_entry_without_a_digest_is_rebuilt_not_used(tmp_path, monkeypatch):
    """A whole file written before issue 36 cannot be checked: find_cached treats it as absent."""
    monkeypatch.setenv("FLEXBEARING_CACHE", str(tmp_path))
    key = {"cage": "old"}
    target = rcf.cache_path(key)
    target.parent.mkdir(parents=True)
    _cache_file(tmp_path, target.stem, parameters=key)
    shutil.move(tmp_path / f"{target.stem}.h5", target)
    assert rcf.find_cached(key) == target
    with h5py.File(target, "r+") as f:
        del f.attrs["data_sha256"]
    assert rcf.find_cached(key) is None


def test_a_cache_path_that_is_a_file_is_named_with_the_fix(tmp_path, monkeypatch):
    from flexbearing.common.cache import cache_dir
    f = tmp_path / "cachefile"
    f.write_text("x")
    monkeypatch.setenv("FLEXBEARING_CACHE", str(f))
    with pytest.raises(InputError, match=rf"cache folder {f} \(FLEXBEARING_CACHE\) is a file"):
        cache_dir()


def test_atomic_output_replaces_a_planted_link_not_its_target_and_leaves_no_temporary(tmp_path):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    cache = tmp_path / "cache"
    cache.mkdir()
    target = cache / "entry.h5"
    target.symlink_to(victim)
    write_text_atomic(target, "new content")
    assert victim.read_text() == "precious"
    assert not target.is_symlink() and target.read_text() == "new content"
    assert sorted(p.name for p in cache.iterdir()) == ["entry.h5"]


@pytest.mark.parametrize("failure", [OSError(errno.ENOSPC, "No space left on device"), KeyboardInterrupt()])
def test_a_failed_write_leaves_neither_a_temporary_nor_a_changed_target(tmp_path, failure):
    target = tmp_path / "entry.h5"
    target.write_text("old")
    with pytest.raises(type(failure)):
        with atomic_output(target) as tmp:
            tmp.write_text("half")
            raise failure
    assert sorted(p.name for p in tmp_path.iterdir()) == ["entry.h5"] and target.read_text() == "old"


def test_temporaries_are_unique_and_created_exclusively(tmp_path):
    """Two writers of the same target at once never share a temporary (mkstemp: O_EXCL, random
    name), and the names cannot be predicted from the pid."""
    target = tmp_path / "entry.h5"
    with atomic_output(target) as a, atomic_output(target) as b:
        assert a != b and a.parent == b.parent == tmp_path
        assert str(os.getpid()) not in a.name
        a.write_text("a")
        b.write_text("b")
    assert target.read_text() in ("a", "b")


@pytest.mark.parametrize("umask, mode", [(0o022, 0o644), (0o002, 0o664), (0o077, 0o600)])
def test_cache_files_get_the_umasks_permissions(tmp_path, umask, mode):
    """mkstemp makes 0600 (other users of a shared cache could not read it); the finished file
    has 0666 minus the umask, like any file the user creates."""
    old = os.umask(umask)
    try:
        p = _cache_file(tmp_path, "aaaa")
    finally:
        os.umask(old)
    assert (p.stat().st_mode & 0o777) == mode


def test_a_damaged_or_foreign_stress_search_file_is_rebuilt(tmp_path):
    from flexbearing.coupling.flexible_cage import StressRecovery
    from flexbearing.fem_cage.von_mises_search import TrackingMaxVonMises
    from test_von_mises import _cage_like, _search
    S, omega, phi_b, q_cf, coords = _cage_like()
    W, built = _search(S, omega, phi_b, q_cf, coords)
    f = tmp_path / "search.npz"
    built.save(f, source="digest-A")
    assert TrackingMaxVonMises.load(f, W, "digest-A") is not None
    assert TrackingMaxVonMises.load(f, W, "digest-B") is None         # built from another cage
    data = bytearray(f.read_bytes())
    data[len(data) // 2] ^= 0x01                                      # one flipped bit
    f.write_bytes(bytes(data))
    with pytest.raises(Exception):
        TrackingMaxVonMises.load(f, W, "digest-A")
    # StressRecovery treats both as missing (and then builds and writes the search again)
    rec = StressRecovery.__new__(StressRecovery)
    rec.source, rec.n_elastic, rec.load_modes = "digest-A", 0, np.zeros((1, 6, 1))
    assert rec._read_search(f, W) is None
    f.write_bytes(b"PK\x03\x04 truncated")
    assert rec._read_search(f, W) is None


def test_a_full_cache_disk_is_one_error_and_leaves_no_temporary(tmp_path):
    """The reduced cage's size is reserved before HDF5 writes (HDF5 crashed on ENOSPC in the middle
    of its writes): a tmpfs too small for it (root only) gives ENOSPC naming the cache file."""
    import subprocess
    disk = tmp_path / "small"
    disk.mkdir()
    if os.geteuid() != 0 or subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(disk)],
                                           capture_output=True).returncode != 0:
        pytest.skip("mounting a tmpfs needs root")
    try:
        target = disk / "cage.h5"
        with pytest.raises(OSError) as exc:
            rcf.write(target, _synthetic(m=40, nv=400), {"content_hash": "cage"})
        assert exc.value.errno == errno.ENOSPC and str(target) == exc.value.filename
        assert "MB needed" in exc.value.strerror and list(disk.iterdir()) == []
    finally:
        subprocess.run(["umount", str(disk)], check=False)
