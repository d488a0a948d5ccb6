"""Elliptical-bore pockets (cage.pocket_shape = "elliptical", cage.pocket_circumferential_diameter;
flexbearing.multibody.pocket).

Analytic references: the ellipse's radius of curvature b²/a and a²/b at its vertices; the nearest
point of the ellipse from a point against a dense minimisation over the parametric angle (scipy,
bounded, from the best of 720 samples: independent of Eberly's bisection); a centred ball's
clearance (Dp − Dw)/2 across the short (axial) axis and (Dp_t − Dw)/2 round; a ball moved axially
is the cylinder's; a ball moved round by v, beyond the major vertex's centre of curvature, is
B − v from the wall; the pocket law along the wall normal; the pocket volume in the cage mass
(dblquad of the ellipse's chords); the mesh's pocket nodes on the ellipse.
"""
import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from flexbearing.common.validation import InputError
from flexbearing.mesh.cage_geometry import PAPER_CAGE
from flexbearing.multibody import dynamics as D
from flexbearing.multibody import model as M
from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL
from flexbearing.multibody.pocket import (ellipse_curvature_radius, ellipse_nearest_point,
                                          elliptical_pocket_curvature_radii, pocket_contact_offset)
from test_pocket_shapes import annulus_minus_pockets_mass

OFF = {"traction": False, "drag": False, "damping": False, "rolling_resistance": False}
R_PITCH = 0.5 * PAPER_BEARING.pitch_diameter
RB = 0.5 * PAPER_BEARING.ball_diameter
A = 0.5 * PAPER_CAGE.pocket_diameter          # along the bearing axis
DT = 23.0e-3
B = 0.5 * DT                                  # round (direction of rotation)
AX = np.array([0.0, 1.0, 0.0])                # pocket axis (radial, +y); e1 = x, e2 = a × e1 = −z
E1, E2 = np.array([1.0, 0.0, 0.0]), np.cross(AX, [1.0, 0.0, 0.0])
ELL = 3


def test_curvature_at_the_vertices():
    a, b = 11.5e-3, 11.25e-3
    assert ellipse_curvature_radius(a, b, a, 0.0) == pytest.approx(b * b / a, rel=1e-14)
    assert ellipse_curvature_radius(a, b, 0.0, b) == pytest.approx(a * a / b, rel=1e-14)
    assert elliptical_pocket_curvature_radii(RB, A, B, 0.0, B) == pytest.approx(
        (1.0 / (1.0 / RB - B / (A * A)), RB), rel=1e-12)


def _nearest_by_minimisation(e0, e1, y0, y1):
    f = lambda t: math.hypot(e0 * math.cos(t) - y0, e1 * math.sin(t) - y1)
    ts = np.linspace(-math.pi, math.pi, 721)
    t0 = ts[np.argmin([f(t) for t in ts])]
    r = minimize_scalar(f, bounds=(t0 - 0.01, t0 + 0.01), method="bounded", options={"xatol": 1e-14})
    return e0 * math.cos(r.x), e1 * math.sin(r.x), r.fun


@pytest.mark.parametrize("y0, y1", [(0.0, 0.0), (1e-4, 0.0), (0.0, 2e-4), (3e-4, 1e-4), (2e-5, 3e-4),
                                    (5e-4, 5e-4), (B - 1e-5, 0.0), (1e-6, A - 1e-6)])
def test_nearest_point_against_a_minimisation(y0, y1):
    """Distances to 1e-12 m (the minimiser's xatol 1e-14 rad times the radius, and its
    quadratic minimum: the points agree to sqrt of that)."""
    x0, x1, d = ellipse_nearest_point(B, A, y0, y1)
    assert (x0 / B) ** 2 + (x1 / A) ** 2 == pytest.approx(1.0, abs=1e-13)   # bisection's last bit
    r0, r1, dr = _nearest_by_minimisation(B, A, y0, y1)
    assert d == pytest.approx(dr, abs=1e-12)


def test_centred_and_displaced_ball():
    cp = A - RB
    assert cp == pytest.approx(0.5 * (PAPER_CAGE.pocket_diameter - PAPER_BEARING.ball_diameter), rel=1e-14)
    # centred: the wall is A away (the axial vertices), Z = 0: the gap is Cp; round it is B − Rb
    assert pocket_contact_offset(0.0, 0.0, 0.0, *AX, ELL, 0.0, A, B)[6] == 0.0
    assert ellipse_nearest_point(B, A, 0.0, 0.0)[2] == pytest.approx(A, rel=1e-15)
    assert ellipse_nearest_point(B, A, 0.0, 0.0)[2] < ellipse_nearest_point(B, A, 1e-9, 0.0)[2] + 1e-15
    # moved axially by u: the cylinder's Z = u, normal along x
    for u in (0.5 * cp, cp + 2e-6):
        ex, ey, ez, ux, uy, uz, z = pocket_contact_offset(*(u * E1 + 3e-5 * AX), *AX, ELL, 0.0, A, B)
        assert z == pytest.approx(u, rel=1e-12)
        assert np.array([ux, uy, uz]) / z == pytest.approx(E1, abs=1e-12)
    # moved round by v past the major vertex's centre of curvature (B − A²/B from the centre): the
    # wall is B − v away, Z = A − B + v
    v = B - A * A / B + 5e-5
    ex, ey, ez, ux, uy, uz, z = pocket_contact_offset(*(v * E2), *AX, ELL, 0.0, A, B)
    assert z == pytest.approx(A - B + v, rel=1e-12)
    assert np.array([ux, uy, uz]) / z == pytest.approx(E2, abs=1e-12)


def _model():
    cage = PAPER_CAGE.with_(pocket_shape="elliptical", pocket_circumferential_diameter=DT)
    return M.build_model(PAPER_BEARING.with_(cage=cage), PAPER_OIL, OFF)


def test_pocket_force_at_the_circumferential_vertex():
    """A ball pressed round into the wall at the major vertex by pen: Q = Kc·Cp + Kn·pen^1.5 with
    Kn the Hertz constant of the ball against the vertex's concave radius A²/B (the model's
    nominal contact), on the ball along −e2."""
    from flexbearing.multibody.hertz import effective_modulus, hertz_stiffness
    m = _model()
    cp = m.p[M.P_CP]
    c, ball = PAPER_CAGE.material, PAPER_BEARING.ball_material
    e_eff = effective_modulus(ball.youngs_modulus, ball.poisson_ratio, c.youngs_modulus, c.poisson_ratio)
    r_across = 1.0 / (1.0 / RB - B / (A * A))
    kn = hertz_stiffness(RB, r_across, e_eff) if r_across > RB else hertz_stiffness(r_across, RB, e_eff)
    assert m.p[M.P_KN] == pytest.approx(kn, rel=1e-12)
    pen = 2e-6
    v = B - RB + pen                                     # the ball's surface pen beyond the wall
    b = np.array([0.0, R_PITCH, 0.0]) + v * E2
    out = D._pocket_interface(b[0], b[1], b[2], 0, 0, 0, 0, 0, 0, 0.0, R_PITCH, 0.0, *AX,
                              0, 0, 0, 0, 0, 0, *E1, m.p, m.flags)     # the cage's axis: E1
    q = 11.0 + kn * pen ** 1.5
    assert out[10] == pytest.approx(cp + pen, rel=1e-9)
    assert out[9] == pytest.approx(q, rel=1e-8)
    assert np.array(out[0:3]) == pytest.approx(-q * E2, rel=1e-8, abs=1e-8 * q)


def test_elliptical_pocket_volume_in_the_mass():
    """rho·(annulus − Z·V), V = ∫∫ 2A·sqrt(1 − (r sin(phi)/B)²) r dr dphi over the annulus (the
    ellipse's chord along x; the section does not change along the radial axis). 2e-3: the model's grid."""
    cage = PAPER_CAGE.with_(pocket_shape="elliptical", pocket_circumferential_diameter=DT).validate()

    def chord(phi, r):
        s = 1.0 - (r * math.sin(phi) / B) ** 2
        return 2.0 * A * math.sqrt(s) * r if s > 0 else 0.0
    m_ref = annulus_minus_pockets_mass(cage, chord, math.asin(B / cage.inner_radius) * 1.01)
    assert M.cage_mass_properties(cage)[0] == pytest.approx(m_ref, rel=2e-3)
    assert abs(M.cage_mass_properties(PAPER_CAGE)[0] - m_ref) > 5e-3 * m_ref


def test_refusals_and_scene_key():
    from flexbearing.simulation.scene import loads_scene
    with pytest.raises(InputError, match=r"cage.pocket_circumferential_diameter = 0.022 .*allowed"):
        PAPER_CAGE.with_(pocket_shape="elliptical", pocket_circumferential_diameter=22e-3).validate()
    # the ball must fit the ellipse's tightest curvature A²/B > Rb: B < A²/Rb = 11.506 mm
    with pytest.raises(InputError, match=r"cage.pocket_circumferential_diameter = 0.0232"):
        PAPER_CAGE.with_(pocket_shape="elliptical", pocket_circumferential_diameter=23.2e-3).validate()
    with pytest.raises(InputError, match=r"applies to elliptical pockets only"):
        PAPER_CAGE.with_(pocket_circumferential_diameter=23e-3).validate()
    base = ('name = "ell"\n[operation]\nduration = 0.01\n[operation.speed]\n'
            'phases = [{ kind = "uniform", duration = 0.01, rpm = 14000 }]\n[operation.load]\naxial_load = 55e3\n'
            '[output]\nsample_interval = 1e-3\nrecord = ["pocket_force"]\n')
    s = loads_scene(base + '[cage]\npocket_shape = "elliptical"\npocket_circumferential_diameter = 23e-3\n', "e.toml")
    assert (s.bearing.cage.pocket_shape, s.bearing.cage.pocket_circumferential_diameter) == ("elliptical", 23e-3)
    assert "pocket_circumferential_diameter" not in PAPER_CAGE.to_dict()


def test_elliptical_pocket_mesh(tmp_path):
    from flexbearing.mesh.cage_mesh import build_cage_mesh, mesh_quality_of
    from flexbearing.verification.cad_test_cage import mesh_groups
    g = PAPER_CAGE.with_(pocket_shape="elliptical", pocket_circumferential_diameter=DT).validate()
    path = build_cage_mesh(g, 8e-3, 2, tmp_path / "e.msh", pocket_size=6e-3)
    shift = mesh_quality_of(path)["repair"]["max_node_shift_m"]
    groups = mesh_groups(path)
    for k in range(g.n_pockets):
        th = 2 * math.pi * k / g.n_pockets
        tang = np.array([0.0, -math.sin(th), math.cos(th)])
        X = groups[f"pocket_{k:02d}"][2]
        lev = np.hypot(X[:, 0] / A, (X @ tang) / B)
        assert np.max(np.abs(lev - 1.0)) * A <= 1e-9 + 1e-5 * g.outer_radius + shift


def test_a_run_with_elliptical_pockets_loads_them():
    """The whole dynamics with elliptical pockets (rhs, outputs): a 2 ms rigid-cage run finishes
    and its pockets carry load (the integration check; the law is tested above)."""
    import h5py
    import tempfile
    from pathlib import Path
    from flexbearing.simulation.run import run_scene
    from flexbearing.simulation.scene import loads_scene
    text = ('name = "ell"\n[cage]\npocket_shape = "elliptical"\npocket_circumferential_diameter = 23e-3\n'
            '[operation]\nduration = 0.002\n[operation.speed]\n'
            'phases = [{ kind = "uniform", duration = 0.002, rpm = 14000 }]\n[operation.load]\n'
            'axial_load = 55e3\nradial_load = 4e3\n[integrator]\ntolerance = 1e-6\ninitial_step = 1e-7\n'
            '[output]\nsample_interval = 1e-4\nrecord = ["pocket_force"]\n')
    out = Path(tempfile.mkdtemp()) / "ell.h5"
    run_scene(loads_scene(text, "ell.toml"), out, quiet=True)
    with h5py.File(out, "r") as f:
        q = f["outputs/pocket_force"][()]
    assert np.max(np.abs(q)) > 1.0
