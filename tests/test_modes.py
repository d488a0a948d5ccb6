"""Free–free modes (fem_cage): plain ring vs ring theory, rigid modes, M-normalisation, MPI."""
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from flexbearing.mesh.cage_geometry import NOMINAL_CAGE

ROOT = Path(__file__).resolve().parents[1]


def _ring_modes(tmp_path, size, n_modes=16, geometry=NOMINAL_CAGE):
    from flexbearing.mesh.cage_mesh import build_ring_mesh
    from flexbearing.fem_cage.modes import cage_modes
    from flexbearing.fem_cage.classify import classify_modes
    path = build_ring_mesh(geometry, size, 2, tmp_path / "ring.msh")
    f, vecs, V, domain, names, info = cage_modes(path, geometry.material, 2, n_modes)
    return f, vecs, V, classify_modes(V, vecs, f, rigid_tol_hz=1.0)


def _inplane(f, cl, n):
    return [fi for fi, c in zip(f, cl) if c["family"] == "in-plane bending" and c["n"] == n]


@pytest.fixture(scope="module")
def coarse_ring(tmp_path_factory):
    return _ring_modes(tmp_path_factory.mktemp("ring"), 8e-3, n_modes=12)


def test_rigid_modes_and_normalisation(coarse_ring):
    f, vecs, V, cl = coarse_ring
    # Six rigid modes, all below 1e-3 of the first elastic frequency (issue requirement).
    assert [c["family"] for c in cl[:6]] == ["rigid"] * 6
    assert np.max(np.abs(f[:6])) < 1e-3 * f[6]
    assert np.all(np.diff(f) >= -1e-9 * f[-1])            # ascending
    # M-orthonormality phi_i^T M phi_j = delta_ij (tolerance: SLEPc tol 1e-9 on the residual).
    from flexbearing.fem_cage.elasticity import assemble_stiffness_mass
    _, K, M = assemble_stiffness_mass(V.mesh, NOMINAL_CAGE.material, 2)
    G = np.array([[vi.dot(M * vj) for vj in vecs] for vi in vecs])
    assert np.allclose(G, np.eye(len(vecs)), atol=1e-6)
    # Rayleigh quotient phi^T K phi = omega^2 for the elastic modes.
    for fi, v in zip(f[6:], vecs[6:]):
        assert v.dot(K * v) == pytest.approx((2 * np.pi * fi) ** 2, rel=1e-8)


def test_coarse_ring_inplane_n2_near_theory(coarse_ring):
    # Coarse (8 mm, curved P2) mesh: n = 2 in-plane within 3 % of the Timoshenko ring
    # (the converged check, 2 %, is the slow test below).
    from flexbearing.fem_cage.ring_theory import thick_ring_inplane_hz
    f, vecs, V, cl = coarse_ring
    g = NOMINAL_CAGE
    fe = _inplane(f, cl, 2)
    assert len(fe) == 2                                   # the degenerate (cos, sin) pair
    ref = thick_ring_inplane_hz(2, g.outer_radius, g.inner_radius, g.width, g.material)
    assert fe[0] == pytest.approx(ref, rel=0.03)


@pytest.mark.slow
def test_converged_ring_inplane_bending_matches_ring_theory(tmp_path):
    # Plain ring of the paper's section (R = 84.9 mm, h = 8.65 mm, b = 28.3 mm), 4 mm curved P2
    # (the 3 mm mesh changes these by < 0.05 %). In-plane n = 2..4 within 2 % of the
    # Timoshenko ring (shear, rotary inertia, extension): the remaining gap is the 3-D section
    # (b/h = 3.3, anticlastic stiffening) that beam theory does not model.
    from flexbearing.fem_cage.ring_theory import thick_ring_inplane_hz
    f, vecs, V, cl = _ring_modes(tmp_path, 4e-3, n_modes=20)
    g = NOMINAL_CAGE
    assert np.max(np.abs(f[:6])) < 1e-3 * f[6]
    for n in (2, 3, 4):
        fe = _inplane(f, cl, n)
        assert len(fe) == 2
        ref = thick_ring_inplane_hz(n, g.outer_radius, g.inner_radius, g.width, g.material)
        assert fe[0] == pytest.approx(ref, rel=0.02)


@pytest.mark.slow
@pytest.mark.mpi
def test_modes_under_mpirun_match_serial(tmp_path):
    mpirun = shutil.which("mpirun")
    if mpirun is None:
        pytest.skip("mpirun not available")
    exe = str(Path(sys.executable).with_name("flexbearing"))
    # yield_when_idle: on an oversubscribed box a busy-polling rank starves its partner.
    env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_MCA_mpi_yield_when_idle="1")
    common = ["modes", "--preset", "nominal", "--size", "8e-3", "--pocket-size", "4e-3", "--no-classify", "--quiet"]
    subprocess.run([exe, *common, "--json", str(tmp_path / "s.json")], check=True, env=env, cwd=ROOT)
    subprocess.run([mpirun, "-n", "2", "--allow-run-as-root", "--oversubscribe", exe, *common,
                    "--json", str(tmp_path / "p.json")], check=True, env=env, cwd=ROOT)
    s = json.loads((tmp_path / "s.json").read_text())
    p = json.loads((tmp_path / "p.json").read_text())
    assert p["mpi_ranks"] == 2 and p["ndofs"] == s["ndofs"]
    # Same discrete problem, different partition: elastic frequencies agree to solver tolerance.
    assert np.allclose(p["frequencies_hz"][6:], s["frequencies_hz"][6:], rtol=1e-7)


def test_mode_shapes_xdmf(coarse_ring, tmp_path):
    # ParaView output: one step per mode, displacement + von Mises, and a JSON sidecar whose
    # frequencies are the solver's.
    from flexbearing.fem_cage.xdmf import write_modes_xdmf
    f, vecs, V, cl = coarse_ring
    path = write_modes_xdmf(tmp_path / "modes", V, vecs[:8], f[:8], NOMINAL_CAGE.material)
    assert path.exists() and path.with_suffix(".h5").exists()
    text = path.read_text()
    assert text.count('<Attribute Name="displacement"') == 8 and text.count('<Attribute Name="von_mises"') == 8
    meta = json.loads(path.with_suffix(".json").read_text())
    assert [m["frequency_hz"] for m in meta["modes"]] == pytest.approx(list(f[:8]))
