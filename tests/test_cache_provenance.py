"""Where cached data came from (issue 43, found item 5; what to build 3).

A digest proves a cached file is whole, not that it is the right one. Here: a reduced cage
records the parameters and the mesh (sha256) it was built from, checked by the run
(rcf.find_cached / check_provenance) against the key and the cache's mesh it is about to use,
and `report` uses only the reduced cage whose content digest the run recorded; meshes carry their
sha256 in their quality sidecar and enter the cache only whole; CAD cache records carry their own
digest, are keyed by every file the geometry reads and are written with the umask; the quality
sidecar is never written through a planted link.
"""
from __future__ import annotations

import hashlib
import json
import os
import sys
import types

import h5py
import pytest

from flexbearing.common.cache import msh_is_whole
from flexbearing.common.validation import InputError
from flexbearing.fem_cage import reduced_cage as rcf
from flexbearing.mesh import cage_mesh as CM
from flexbearing.mesh.cage_geometry import PAPER_CAGE
from test_reduced_cage import _synthetic

MSH = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n{n}\n$EndNodes\n$Elements\n0\n$EndElements\n"


def _mesh(path, n: int = 1):
    """A stand-in .msh with its quality sidecar as the cache writes them (the sidecar holding its
    sha256)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(MSH.format(n=n))
    CM.write_quality(path, {"quality": {}, "repair": None})
    return path


def _entry(tmp_path, monkeypatch, mesh_text_n: int = 1):
    """A reduced cage in the cache for the paper cage's key, built (as `build` records it) from the
    cache's mesh for that key; returns (key, reduced cage path, mesh path)."""
    monkeypatch.setenv("FLEXBEARING_CACHE", str(tmp_path / "cache"))
    key = rcf.cache_key(PAPER_CAGE, 4e-3, 2, 4e-3, "rbe3", 30, 3, True)
    mesh = _mesh(CM.cache_path(PAPER_CAGE, 4e-3, 2, 4e-3), mesh_text_n)
    p = rcf.write(rcf.cache_path(key), _synthetic(), {"content_hash": rcf.cache_path(key).stem, "parameters": key,
                                                      "mesh_sha256": rcf.file_sha256(mesh)})
    return key, p, mesh


def _recompute_digest(p):
    with h5py.File(p, "r+") as f:
        f.attrs["data_sha256"] = rcf.data_digest(f)


def test_a_cache_entry_built_from_its_key_and_mesh_is_used(tmp_path, monkeypatch):
    key, p, mesh = _entry(tmp_path, monkeypatch)
    assert rcf.find_cached(key, mesh) == p


def test_edited_parameters_with_the_digest_recomputed_are_refused(tmp_path, monkeypatch):
    """Another cage's parameters written into the entry and its digest recomputed (so `verify`
    passes): the recorded parameters are not the key the run asks for."""
    key, p, mesh = _entry(tmp_path, monkeypatch)
    with h5py.File(p, "r+") as f:
        f.attrs["parameters"] = json.dumps(dict(key, mesh_size=3e-3))
    _recompute_digest(p)
    rcf.verify(p, expect_key=p.stem)                      # whole: the digest alone cannot tell
    with pytest.raises(InputError, match=rf"reduced cage file {p} records other parameters than the cage "
                                         rf"it is asked for .*delete {p} and run again"):
        rcf.find_cached(key, mesh)


def test_a_cached_mesh_swapped_for_another_valid_mesh_is_refused_or_rebuilt(tmp_path, monkeypatch):
    """The mesh swapped with its sidecar made to match (a valid mesh of the cache): the reduced
    cage records the mesh it was built from, which is not this one. Swapped without the
    sidecar: the mesh is not verified, so the cache builds it again (not used)."""
    key, p, mesh = _entry(tmp_path, monkeypatch)
    _mesh(mesh, n=2)                                      # another valid mesh, sidecar and all
    with pytest.raises(InputError, match=r"was built from mesh sha256 [0-9a-f]{16}, the cache's mesh .* is "
                                         r"[0-9a-f]{16} \(a mesh swapped or rebuilt differently\)"):
        rcf.find_cached(key, mesh)
    mesh.write_text(MSH.format(n=3))                      # swapped, sidecar not updated
    assert not CM.verified_mesh(mesh)
    built = []

    def fake_build(geometry, size, order, path, pocket_size=None, local=None):
        built.append(path)
        return _mesh(path)
    monkeypatch.setattr(CM, "build_cage_mesh", fake_build)
    assert CM.cached_cage_mesh(PAPER_CAGE, 4e-3, 2, 4e-3) == mesh and built == [mesh]
    assert CM.cached_cage_mesh(PAPER_CAGE, 4e-3, 2, 4e-3) == mesh and built == [mesh]   # now verified


def test_a_mesh_digest_in_the_file_is_covered_by_its_digest(tmp_path, monkeypatch):
    """The recorded mesh digest edited without recomputing the content digest: damaged."""
    key, p, mesh = _entry(tmp_path, monkeypatch)
    with h5py.File(p, "r+") as f:
        f.attrs["mesh_sha256"] = "0" * 64
    with pytest.raises(InputError, match="does not match the digest"):
        rcf.find_cached(key, mesh)


def _run_file(path, rc_path, sha=None):
    """A results file's reduced-cage attributes as a flexible run records them."""
    with h5py.File(rc_path, "r") as f:
        h, d = str(f.attrs["content_hash"]), str(f.attrs["data_sha256"])
    with h5py.File(path, "w") as f:
        f.attrs["reduced_cage_file"] = str(rc_path)
        f.attrs["reduced_cage_hash"] = h
        f.attrs["reduced_cage_sha256"] = d if sha is None else sha
    return path, h


def test_report_uses_only_the_reduced_cage_the_run_recorded(tmp_path, monkeypatch):
    """`report --reduced-cage OTHER` (another cage), and the run's own file edited with its digest
    recomputed after the run: each refused in one line; the run's file as it was: used."""
    from flexbearing.analysis.field_export import open_reduced_cage
    key, p, mesh = _entry(tmp_path, monkeypatch)
    run, h = _run_file(tmp_path / "run.h5", p)
    M = _synthetic()["modes/omega"].shape[0]
    rc, note = open_reduced_cage(run, p, h, M)
    assert note == "matches (content verified against its digest)"
    other = rcf.write(tmp_path / "other.h5", _synthetic(seed=5), {"content_hash": "0123456789abcdef"})
    with pytest.raises(InputError, match=rf"reduced cage file {other} holds the cage of key 0123456789abcdef, "
                                         rf"the run {run} used {h}: give the reduced cage the run used"):
        open_reduced_cage(run, other, h, M)
    with h5py.File(p, "r+") as f:
        f["modes/omega"][-1] *= 1.01
    _recompute_digest(p)
    with pytest.raises(InputError, match=rf"reduced cage file {p} is not the content the run {run} used"):
        open_reduced_cage(run, p, h, M)
    with pytest.raises(InputError, match=rf"--reduced-cage {run}: not a reduced cage file"):
        open_reduced_cage(run, run, h, M)                   # a results file given as the reduced cage


def test_a_mesh_a_full_disk_cut_short_never_enters_the_cache(tmp_path, monkeypatch):
    """gmsh reports no error when a write is cut short: the file's end is checked before the
    rename, so neither the target nor a temporary is left."""
    target = tmp_path / "meshes" / "abc.msh"
    target.parent.mkdir()
    fake = types.ModuleType("gmsh")
    fake.option = types.SimpleNamespace(setNumber=lambda *a: None)
    fake.write = lambda name: open(name, "w").write(MSH.format(n=1)[:30])
    monkeypatch.setitem(sys.modules, "gmsh", fake)
    with pytest.raises(OSError, match=r"the mesh gmsh wrote is incomplete .*is the disk full"):
        CM._write(target)
    assert list(target.parent.iterdir()) == []
    fake.write = lambda name: open(name, "w").write(MSH.format(n=1))
    CM._write(target)
    assert msh_is_whole(target) and not msh_is_whole(tmp_path / "none.msh")


def test_the_quality_sidecar_is_not_written_through_a_planted_link(tmp_path):
    mesh = tmp_path / "m.msh"
    mesh.write_text(MSH.format(n=1))
    victim = tmp_path / "victim.txt"
    victim.write_text("keep")
    os.symlink(victim, CM.quality_path(mesh))
    CM.write_quality(mesh, {"quality": {}, "repair": None})
    assert victim.read_text() == "keep" and not CM.quality_path(mesh).is_symlink()
    assert json.loads(CM.quality_path(mesh).read_text())["msh_sha256"] == hashlib.sha256(mesh.read_bytes()).hexdigest()


# ---------------------------------------------------------------- the CAD cache
def test_the_cad_key_holds_every_file_the_geometry_reads(tmp_path):
    from flexbearing.mesh.cad_cage import read_cad_source
    from test_cad_script_safety import STEP_STUB
    (tmp_path / "cage.step").write_bytes(STEP_STUB)
    geo = tmp_path / "cage.geo"
    geo.write_text('Merge "cage.step";\n')
    a = read_cad_source(geo).digests
    (tmp_path / "cage.step").write_bytes(STEP_STUB.replace(b"DATA;", b"DATA;\n/* changed */"))
    b = read_cad_source(geo).digests
    assert a["cad_sha256"] == b["cad_sha256"] and a["merged_sha256"] != b["merged_sha256"]
    assert set(a) == {"cad_sha256", "merged_sha256"}


@pytest.fixture(scope="module")
def cad_step(tmp_path_factory):
    from flexbearing.verification.cad_test_cage import make_cad_cage
    return make_cad_cage(tmp_path_factory.mktemp("cad") / "cage14.step")


def test_a_truncated_or_edited_cad_record_is_found_again_and_written_with_the_umask(tmp_path, monkeypatch, cad_step):
    """meshes/*.cad.json truncated (it gave a traceback on every run) or edited (it was used
    silently): found again from the CAD file and rewritten; its mode is the umask's."""
    import shutil
    from flexbearing.mesh.cad_cage import cad_cage_geometry, read_cad_record
    from flexbearing.verification.cad_test_cage import BORE, PITCH, Z
    monkeypatch.setenv("FLEXBEARING_CACHE", str(tmp_path / "cache"))
    step = shutil.copy(cad_step, tmp_path / "cage14.step")
    old = os.umask(0o027)
    try:
        g, report, key = cad_cage_geometry(step, Z, PITCH * 1e-3, 22e-3, "inner")
    finally:
        os.umask(old)
    (store,) = (tmp_path / "cache" / "meshes").glob("*.cad.json")
    assert store.stat().st_mode & 0o777 == 0o640
    assert read_cad_record(store, key)[0] == g
    text = store.read_text()
    store.write_text(text[: len(text) // 2])                               # truncated
    assert read_cad_record(store, key) is None
    assert cad_cage_geometry(step, Z, PITCH * 1e-3, 22e-3, "inner")[0] == g
    rec = json.loads(store.read_text())
    rec["geometry"]["bore_diameter"] = 0.150                                 # edited
    store.write_text(json.dumps(rec))
    assert read_cad_record(store, key) is None
    g2 = cad_cage_geometry(step, Z, PITCH * 1e-3, 22e-3, "inner")[0]
    assert g2.bore_diameter == pytest.approx(BORE * 1e-3, rel=1e-6)


def test_report_reduced_cage_other_is_refused_before_any_work(tmp_path, monkeypatch, capsys):
    """`flexbearing report RUN --reduced-cage OTHER`: one line, exit 2, no output folder."""
    from flexbearing.cli.main import main
    key, p, mesh = _entry(tmp_path, monkeypatch)
    run, h = _run_file(tmp_path / "run.h5", p)
    other = rcf.write(tmp_path / "other.h5", _synthetic(seed=5), {"content_hash": h})    # its key, other content
    for given, match in ((other, rf"reduced cage file {other} is not the content the run {run} used"),
                         (run, rf"--reduced-cage {run}: not a reduced cage file")):
        code = main(["report", str(run), "-o", str(tmp_path / "rep"), "--reduced-cage", str(given), "--quiet"])
        err = capsys.readouterr().err.strip().splitlines()
        assert code == 2 and len(err) == 1 and __import__("re").search(match, err[0]), err
    assert not (tmp_path / "rep").exists()
