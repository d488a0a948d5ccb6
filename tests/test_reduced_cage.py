"""The reduced cage file: schema round trip, truncation / elastic split, cache key, and that
reading it never imports dolfinx (DESIGN.md: a cached run never loads the FE stack)."""
import json
import subprocess
import sys

import numpy as np
import pytest

from flexbearing.fem_cage import reduced_cage as rcf
from flexbearing.mesh.cage_geometry import PAPER_CAGE


def _synthetic(m=10, Z=4, nv=30, seed=0):
    rng = np.random.default_rng(seed)
    omega = np.concatenate([np.zeros(6), np.sort(rng.random(m - 6)) * 1e4 + 3e3])
    data = {"mesh/vertices": rng.random((nv, 3)), "mesh/tets": rng.integers(0, nv, (20, 4)),
            "interface/positions": rng.random((Z, 3)), "interface/pocket": np.arange(Z),
            "modes/frequency_hz": omega / (2 * np.pi), "modes/omega": omega,
            "modes/modal_mass": np.eye(m), "modes/modal_stiffness": omega ** 2,
            "modes/interface": rng.random((Z, 6, m)),
            "modes/vertex_displacement": rng.random((nv, 3, m)),
            "modes/rigid_twist": np.eye(6), "stress/modes": rng.random((nv, 6, m)),
            "loads/guide_modal_loads": rng.random((m, 3))}
    inv = {"mass": 1.0, "center_of_mass": np.zeros(3), "inertia_origin": np.eye(3),
           "inertia_com": np.eye(3), "I1": 1.0, "I2": np.zeros(3), "I3": rng.random((3, m)),
           "I4": rng.random((3, m)), "I5": rng.random((3, m, m)), "I6": np.eye(m),
           "I7": np.eye(3), "I8": rng.random((3, 3, m)), "I9": rng.random((3, 3, m, m)),
           "first": np.zeros(3), "second": np.eye(3), "S1": rng.random((3, m)),
           "Sx": rng.random((3, 3, m)), "SS": rng.random((3, 3, m, m))}
    data.update({f"invariants/{k}": v for k, v in inv.items()})
    return data


# (Q) in floating point: T / s rounds (u |T| / s), s I rounds (u |T~|), the test's subtraction and
# its half step rounds (~2u each): |T~ - T| <= s/2 + 2u |T| + 4u s/2 with |T| <= 32767 s, i.e.
# half a step times 1 + (2 * 65534 + 4) u = 1 + 1.5e-11 (Higham §2.2: each operation within u)
# (tests/tolerances.py is imported inside the tests: a subprocess below imports this module as
# tests.test_reduced_cage, without tests/ on its path)
QUANTISE_SLACK = (2 * 65534 + 4) * np.finfo(float).eps / 2


def test_round_trip_truncate_elastic(tmp_path):
    from tolerances import assert_within
    data = _synthetic()
    p = rcf.write(tmp_path / "c.h5", data, {"content_hash": "abc", "parameters": {"a": 1}},
                  {"static": {"max_rel_error_full": 1e-9}})
    rc = rcf.read(p)
    assert rc.n_modes == 10
    # the mode-shape tables are stored as 16-bit integers (schema 6) and read back as float64:
    # each entry within half a step, max|column| / 65534, of what was written (quantise, (Q))
    for name, got in (("stress/modes", rc.stress_modes),
                      ("modes/vertex_displacement", rc.vertex_displacement)):
        assert got.dtype == np.float64
        half_step = np.abs(data[name]).max(axis=0) / (2 * 32767)
        assert_within(np.abs(got - data[name]), half_step * (1 + QUANTISE_SLACK), "half a step")
    assert rc.attrs["parameters"] == {"a": 1}
    assert rc.checks["static"]["max_rel_error_full"] == 1e-9
    t = rc.truncate(8)
    assert t.n_modes == 8 and t.invariants["I9"].shape == (3, 3, 8, 8)
    assert np.array_equal(t.invariants["SS"], data["invariants/SS"][:, :, :8, :8])
    e = t.elastic()
    assert list(e.modes) == [6, 7]
    assert np.array_equal(e.interface_modes, data["modes/interface"][:, :, 6:8])
    assert np.array_equal(e.invariants["I5"], data["invariants/I5"][:, 6:8, 6:8])
    assert np.array_equal(rc.guide_modal_loads, data["loads/guide_modal_loads"])
    assert np.array_equal(e.guide_modal_loads, data["loads/guide_modal_loads"][6:8])
    assert np.allclose(rcf.modal_damping(e.omega, 1e-5), 1e-5 * e.omega ** 2)
    with pytest.raises(ValueError):          # InputError is a ValueError
        rc.truncate(11)


def test_schema_version_checked(tmp_path):
    import h5py
    p = rcf.write(tmp_path / "c.h5", _synthetic(), {})
    with h5py.File(p, "a") as f:
        f.attrs["schema_version"] = 99
    with pytest.raises(ValueError, match="schema_version"):
        rcf.read(p)


def test_older_schema_versions_read_without_guide_loads(tmp_path):
    """Version-2/3 files (no /loads) still read: guide_modal_loads is None and the augmentation
    flags read False (a version-4 file without /loads, e.g. a hand-made synthetic one, reads the
    same way)."""
    import h5py
    data = _synthetic()
    del data["loads/guide_modal_loads"]
    p = rcf.write(tmp_path / "c.h5", data, {})
    for ver in (2, 3):
        with h5py.File(p, "a") as f:
            f.attrs["schema_version"] = ver
        rc = rcf.read(p)
        assert rc.guide_modal_loads is None and rc.truncate(8).guide_modal_loads is None
        assert rc.attrs["guide_load_vectors"] is False and rc.attrs["inertia_relief_vectors"] is False
    with h5py.File(p, "a") as f:
        f.attrs["schema_version"] = 4
    assert rcf.read(p).guide_modal_loads is None


def test_mode_tables_are_16_bit_on_disk_and_the_rest_float64(tmp_path):
    """Schema 6 stores only the two mode-shape tables as int16 with float64 scales per (component,
    mode); what the equations of motion use (frequencies, interface modes, invariants) stays
    float64."""
    import h5py
    data = _synthetic()
    data["stress/modes"][:, :, :6] = 0.0                   # rigid modes: no stress
    p = rcf.write(tmp_path / "c.h5", data, {})
    with h5py.File(p) as f:
        assert f.attrs["schema_version"] == 6
        for name in rcf.QUANTISED_DATASETS:
            assert f[name].dtype == np.int16
            assert f[name + rcf.SCALE_SUFFIX].dtype == np.float64
            assert f[name + rcf.SCALE_SUFFIX].shape == data[name].shape[1:]
        for name in ("modes/omega", "modes/interface", "invariants/SS", "loads/guide_modal_loads"):
            assert f[name].dtype == np.float64
    assert np.all(rcf.read(p).stress_modes[:, :, :6] == 0.0)      # an all-zero column stays exactly 0


def test_an_older_format_cache_entry_is_rebuilt_not_read(tmp_path, monkeypatch):
    """A version-4 file (float64 tables) sits at the cache path of a version-4 key; the
    version-6 key of the same cage names another file, so find_cached finds nothing and the
    caller builds the cage again (never mixes the formats)."""
    monkeypatch.setenv("FLEXBEARING_CACHE", str(tmp_path))
    key5 = rcf.cache_key(PAPER_CAGE, 4e-3, 2, 2e-3, "rbe3", 30)
    key4 = dict(key5, schema_version=4)
    old = rcf.cache_path(key4)
    rcf.write(old, _synthetic(), {"content_hash": old.stem, "parameters": key4})
    assert rcf.cache_path(key5) != old
    assert rcf.find_cached(key5) is None and rcf.find_cached(key4) == old


def test_cache_key_depends_on_every_input():
    base = rcf.cache_key(PAPER_CAGE, 3e-3, 2, 1.5e-3, "rbe3", 30)
    variants = [rcf.cache_key(PAPER_CAGE.with_(width=0.029), 3e-3, 2, 1.5e-3, "rbe3", 30),
                rcf.cache_key(PAPER_CAGE, 2e-3, 2, 1.5e-3, "rbe3", 30),
                rcf.cache_key(PAPER_CAGE, 3e-3, 1, 1.5e-3, "rbe3", 30),
                rcf.cache_key(PAPER_CAGE, 3e-3, 2, None, "rbe3", 30),
                rcf.cache_key(PAPER_CAGE, 3e-3, 2, 1.5e-3, "rbe2", 30),
                rcf.cache_key(PAPER_CAGE, 3e-3, 2, 1.5e-3, "rbe3", 40),
                rcf.cache_key(PAPER_CAGE, 3e-3, 2, 1.5e-3, "rbe3", 30, 3, False),
                rcf.cache_key(PAPER_CAGE, 3e-3, 2, 1.5e-3, "rbe3", 30, 3, True, False),
                rcf.cache_key(PAPER_CAGE, 3e-3, 2, 1.5e-3, "rbe3", 30, 3, True, True, False)]
    # the runtime's 8-argument call (flexbearing.coupling.flexible_cage) gets the land-load and inertia-relief
    # augmented version-4 file
    assert rcf.cache_key(PAPER_CAGE, 3e-3, 2, 1.5e-3, "rbe3", 30, 3, True) == \
        rcf.cache_key(PAPER_CAGE, 3e-3, 2, 1.5e-3, "rbe3", 30, 3, True, True, True)
    assert base["schema_version"] == 6 and base["guide_load_vectors"] and base["inertia_relief_vectors"]
    mat = PAPER_CAGE.material.__class__(7800.0, 209e9, 0.295)
    variants.append(rcf.cache_key(PAPER_CAGE.with_(material=mat), 3e-3, 2, 1.5e-3, "rbe3", 30))
    paths = {rcf.cache_path(k) for k in variants}
    assert rcf.cache_path(base) not in paths and len(paths) == len(variants)
    assert rcf.find_cached(base) is None or rcf.find_cached(base).exists()


def test_reading_does_not_import_dolfinx(tmp_path):
    p = rcf.write(tmp_path / "c.h5", _synthetic(), {})
    code = ("import sys; from flexbearing.fem_cage import reduced_cage as r; from flexbearing.fem_cage.von_mises_search import "
            f"MaxVonMises; rc = r.read({str(p)!r}).truncate(8); ev = MaxVonMises(rc.stress_modes);"
            "ev(rc.omega * 0 + 1.0); "
            "assert 'dolfinx' not in sys.modules and 'ufl' not in sys.modules, 'FE stack imported'")
    subprocess.run([sys.executable, "-c", code], check=True)


def test_cli_on_cached_file_never_imports_dolfinx(tmp_path):
    """`flexbearing reduce --json --xdmf` with the paper cage's file in the cache reads the file
    only (a synthetic file stands in for it here)."""
    import os
    import flexbearing.mesh.cage_mesh as cm
    key = rcf.cache_key(PAPER_CAGE, cm.DEFAULT_MESH_SIZE, cm.DEFAULT_ORDER, cm.DEFAULT_POCKET_SIZE,
                        rcf.DEFAULT_COUPLING, rcf.DEFAULT_N_FIXED, cm.DEFAULT_DEGREE)
    cache = tmp_path / "cache"
    env = dict(os.environ, FLEXBEARING_CACHE=str(cache))
    code = ("import sys; from flexbearing.fem_cage import reduced_cage as r; import os; "
            f"r.write(r.cache_path({key!r}), __import__('tests.test_reduced_cage', fromlist=['x'])"
            f"._synthetic(m=30), {{'content_hash': r.cache_path({key!r}).stem, 'parameters': {key!r}}}, "
            "{'static': {'max_rel_error_full': 1e-10}}); "
            "from flexbearing.cli.main import main; "
            f"rc = main(['reduce', '--quiet', '--json', {str(tmp_path / 's.json')!r}, '--xdmf', "
            f"{str(tmp_path / 'm.xdmf')!r}]); "
            "assert rc == 0; assert 'dolfinx' not in sys.modules, 'dolfinx imported'")
    subprocess.run([sys.executable, "-c", code], check=True, env=env, cwd=str(
        __import__("pathlib").Path(__file__).parent.parent))
    summary = json.loads((tmp_path / "s.json").read_text())
    assert summary["static"]["max_rel_error_full"] == 1e-10
    assert len(summary["kept_frequencies_hz"]) == 26
    assert (tmp_path / "m.xdmf").exists()


def test_quantisation_bound_holds_under_cancellation():
    """rcf.quantisation_bound: the max von Mises of sigma = S q moved by the 16-bit storage of S is
    within the bound, here where 40 modes with large coordinates cancel to a small result (the
    bound scales with sum_k |q_k| max|S_k|, not with the result). The uniaxial one-mode case
    reaches the bound's value exactly: vm = |sigma_xx|, error half a step."""
    from tolerances import assert_within, gamma
    from flexbearing.fem_cage.stress_modes import von_mises
    rng = np.random.default_rng(3)
    n, m = 500, 40
    S = rng.normal(size=(n, 6, m)) * 1e8
    q = rng.normal(size=m)
    q[-1] = -(S[:, :, :-1] @ q[:-1])[0, 0] / S[0, 0, -1]          # node 0's sigma_xx cancels
    ints, scale = rcf.quantise(S)
    St = rcf.dequantise(ints, scale)
    e = 0.5 * scale @ np.abs(q)
    # per entry within half a step (1 + QUANTISE_SLACK); the m-term products with q and e's own
    # sum add gamma_m each (Higham eq. (3.5))
    assert_within(np.abs((St - S) @ q), e * (1 + QUANTISE_SLACK + 2 * gamma(m)), "sum of steps",
                  effect=np.abs(S @ q).max())
    exact, stored = von_mises(S @ q).max(), von_mises(St @ q).max()
    assert abs(stored - exact) <= rcf.quantisation_bound(scale, q)
    # one mode, uniaxial: sigma_xx = 1 + 1/2 step rounds to 1 step, e_xx = step/2, the bound
    # sqrt(1/2 (e^2 + e^2)) = step/2 = the actual change
    step = 1.0
    col = np.zeros((2, 6, 1))
    col[0, 0, 0], col[1, 0, 0] = 32767 * step, 0.5000001 * step
    ints, scale = rcf.quantise(col)
    assert scale[0, 0] == pytest.approx(step, rel=1e-15)
    # a chain of <= 8 roundings (scale, e, the squares, sums and root; Higham Lemma 3.1), and one product
    assert rcf.quantisation_bound(scale, np.ones(1)) == pytest.approx(0.5 * step, rel=2 * gamma(8))
    assert rcf.dequantise(ints, scale)[1, 0, 0] == pytest.approx(1.0 * step, rel=2 * gamma(1))


def test_a_version_5_file_with_float32_tables_still_reads(tmp_path):
    """Schema 5 stored the mode tables as float32 (no scales): read() widens them to float64."""
    import h5py
    data = _synthetic()
    p = rcf.write(tmp_path / "c.h5", data, {})
    with h5py.File(p, "a") as f:
        f.attrs["schema_version"] = 5
        for name in rcf.QUANTISED_DATASETS:
            del f[name], f[name + rcf.SCALE_SUFFIX]
            f[name] = data[name].astype(np.float32)
    rc = rcf.read(p)
    assert rc.stress_modes.dtype == np.float64
    assert np.array_equal(rc.stress_modes, data["stress/modes"].astype(np.float32).astype(float))
