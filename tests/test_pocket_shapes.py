"""Pocket shapes (cage.pocket_shape): the spherical pocket beside the cylindrical one.

Analytic references: the clearance Cp = (Dp − Dw)/2 of both; the approach measured from the
cylinder's axis or from the sphere's centre; a sphere in a spherical cup is a circular Hertz
contact with relative radius R = Rb·Rp/(Rp − Rb) in every direction, Q = (4/3)·E*·sqrt(R)·delta^1.5
with E* = E'/2 (Johnson, Contact Mechanics, 1985, eq. 4.23 and §4.2), i.e. Kn = (2/3)·E'·sqrt(R);
the volume a spherical pocket removes from the cage ring, a double integral of the sphere's chord
lengths over the annulus (scipy dblquad, independent of the model's midpoint grid).
"""
import math

import numpy as np
import pytest
from tolerances import U, assert_within, gamma
from scipy.integrate import dblquad

from flexbearing.common.validation import InputError
from flexbearing.mesh.cage_geometry import PAPER_CAGE
from flexbearing.multibody import dynamics as D
from flexbearing.multibody import model as M
from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL
from flexbearing.multibody.hertz import effective_modulus
from flexbearing.multibody.pocket import pocket_curvature_radii, spherical_pocket_curvature_radii

OFF = {"traction": False, "drag": False, "damping": False, "rolling_resistance": False}
R_PITCH = 0.5 * PAPER_BEARING.pitch_diameter


def _model(shape):
    b = PAPER_BEARING.with_(cage=PAPER_CAGE.with_(pocket_shape=shape))
    return build(b)


def build(b):
    return M.build_model(b, PAPER_OIL, OFF)


def _pocket(model, ball_offset):
    """The pocket at (0, R_pitch, 0), radial axis +y; the ball at the pocket centre + offset."""
    b = np.array([0.0, R_PITCH, 0.0]) + ball_offset
    return D._pocket_interface(b[0], b[1], b[2], 0, 0, 0, 0, 0, 0, 0.0, R_PITCH, 0.0, 0.0, 1.0, 0.0,
                               0, 0, 0, 0, 0, 0, 0, 0, 0, model.p, model.flags)


def test_curvature_radii_and_hertz_constant():
    rb, rp = 11e-3, 11.25e-3
    r = rb * rp / (rp - rb)
    assert spherical_pocket_curvature_radii(rb, rp) == pytest.approx((r, r), rel=1e-14)
    assert pocket_curvature_radii(rb, rp) == pytest.approx((r, rb), rel=1e-14)
    m = _model("spherical")
    c = PAPER_CAGE.material
    ball = PAPER_BEARING.ball_material
    e_eff = effective_modulus(ball.youngs_modulus, ball.poisson_ratio, c.youngs_modulus, c.poisson_ratio)
    r_conf = 1.0 / (2.0 / PAPER_BEARING.ball_diameter - 2.0 / PAPER_CAGE.pocket_diameter)
    # the Hertz constant of the exact-ellipticity solution at k = 1 against Johnson's closed form
    assert m.p[M.P_KN] == pytest.approx(2.0 / 3.0 * e_eff * math.sqrt(r_conf), rel=1e-9)
    assert m.p[M.P_CP] == pytest.approx(0.5 * (PAPER_CAGE.pocket_diameter - PAPER_BEARING.ball_diameter), rel=1e-14)


@pytest.mark.parametrize("direction", [(0.0, 1.0, 0.0), (0.0, 0.6, 0.8), (0.48, 0.6, 0.64)])
def test_approach_from_the_centre_or_the_axis(direction):
    """A ball offset by s along a unit direction d: the spherical pocket's approach is s, the
    cylindrical pocket's s·|d less its radial part|; the force on the ball is −Kc·(offset) in the
    linear branch (Kc = 11/Cp) and Kc·Cp + Kn·(Z − Cp)^1.5 beyond, along the offset."""
    d = np.array(direction)
    d /= np.linalg.norm(d)
    sph, cyl = _model("spherical"), _model("cylindrical")
    cp = sph.p[M.P_CP]
    # Z comes from positions near R_pitch = 0.0835 m: its rounding (~4e-18 m) is 1e-12 of Z but
    # ~1e-12 of Z − Cp = 3 um only after 1.5x amplification: 1e-10 on the Hertz branch
    for s, rtol in ((0.6 * cp, 1e-12), (cp + 3e-6, 1e-10)):
        out = _pocket(sph, s * d)
        # the ball is placed at R_pitch + offset: its y coordinate rounds by u R_pitch (the
        # kernel's difference from the pocket centre is then exact, Sterbenz), Z is Lipschitz 1
        # in the offset, and <= 8 further roundings (a norm): 2 u R_pitch + 2 gamma_8 Z
        assert_within(abs(out[10] - s), 2 * U * R_PITCH + 2 * gamma(8) * s, "approach Z", effect=s)
        q = 11.0 / cp * s if s <= cp else 11.0 + sph.p[M.P_KN] * (s - cp) ** 1.5
        assert out[9] == pytest.approx(q, rel=rtol)
        assert np.array(out[0:3]) == pytest.approx(-q * d, rel=rtol, abs=rtol * q)
        # the contact point on the spherical wall: centre + Rp along the offset
        rp = 0.5 * PAPER_CAGE.pocket_diameter
        wall = np.array([0.0, R_PITCH, 0.0]) + rp * d
        # <= 10 roundings on coordinates ~R_pitch, and the offset's direction: its placement
        # error (<= 2 u R_pitch in each of 3 coordinates) over its length s, times Rp
        assert_within(np.abs(np.array(out[6:9]) - wall),
                      2 * gamma(10) * (R_PITCH + np.abs(wall)) + rp * 2 * math.sqrt(3) * U * R_PITCH / s,
                      "contact point", effect=s)
        across = s * math.hypot(d[0], d[2])
        out_c = _pocket(cyl, s * d)
        assert_within(abs(out_c[10] - across), 2 * U * R_PITCH + 2 * gamma(8) * s, "approach across",
                      effect=s)


def test_radial_offset_loads_only_the_spherical_pocket():
    sph, cyl = _model("spherical"), _model("cylindrical")
    dr = 0.5 * sph.p[M.P_CP]
    assert _pocket(cyl, np.array([0.0, dr, 0.0]))[9] == 0.0
    out = _pocket(sph, np.array([0.0, dr, 0.0]))
    assert out[1] == pytest.approx(-11.0 * 0.5, rel=1e-12)


def annulus_minus_pockets_mass(cage, chord, half: float) -> float:
    """rho·(annulus − Z·V), the reference cage mass of the pocket-shape tests: V the volume of one
    pocket inside the annulus r_i <= r <= r_o, by dblquad of chord(phi, r) (the pocket's chord
    along x, times r) over r_i..r_o and |phi| <= half."""
    ri, ro, w = cage.inner_radius, cage.outer_radius, cage.width
    v = dblquad(chord, ri, ro, -half, half, epsabs=1e-14, epsrel=1e-10)[0]
    return cage.material.density * (math.pi * (ro ** 2 - ri ** 2) * w - cage.n_pockets * v)


def test_spherical_pocket_volume_in_the_mass():
    """Cage mass with spherical pockets = rho·(annulus − Z·V), V the sphere's volume inside the
    annulus r_i <= r <= r_o, by dblquad over (r, phi) of the chord 2·sqrt(Rp² − |p − c|²) along x
    (the sphere, 22.5 mm, fits in the 28.3 mm width). Tolerance 2e-3: the model's midpoint grid
    (its annulus alone is within 1e-3, tests/test_dynamics.py)."""
    cage = PAPER_CAGE.with_(pocket_shape="spherical")
    rp, rc = 0.5 * cage.pocket_diameter, 0.5 * cage.pocket_centre_diameter
    assert rp < 0.5 * cage.width

    def chord(phi, r):
        s = rp * rp - (r * r + rc * rc - 2 * r * rc * math.cos(phi))
        return 2.0 * math.sqrt(s) * r if s > 0 else 0.0
    m_ref = annulus_minus_pockets_mass(cage, chord, math.asin(rp / rc) * 1.01)
    m, _, _ = M.cage_mass_properties(cage)
    assert m == pytest.approx(m_ref, rel=2e-3)
    # and it differs from the cylindrical pockets' cage by more than that tolerance
    assert abs(M.cage_mass_properties(PAPER_CAGE)[0] - m_ref) > 1e-2 * m_ref


def test_spherical_pocket_refusals():
    with pytest.raises(InputError, match="cage.pocket_shape"):
        PAPER_CAGE.with_(pocket_shape="square").validate()
    # the sphere must open through bore and outside
    with pytest.raises(InputError, match="cage.pocket_centre_diameter"):
        PAPER_CAGE.with_(pocket_shape="spherical", pocket_centre_diameter=150e-3).validate()
    # and sit on the bearing's pitch circle
    off = PAPER_CAGE.with_(pocket_shape="spherical", pocket_centre_diameter=166e-3)
    off.validate()
    with pytest.raises(InputError, match="cage.pocket_centre_diameter"):
        PAPER_BEARING.with_(cage=off).validate()


def _mesh_volume_and_groups(path):
    """Volume of the curved quadratic mesh (gmsh's Gauss points and Jacobians, degree 4) and the
    nodes of each physical group."""
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    try:
        gmsh.merge(str(path))
        et = gmsh.model.mesh.getElementType("Tetrahedron", 2)
        pts, w = gmsh.model.mesh.getIntegrationPoints(et, "Gauss4")
        _, det, _ = gmsh.model.mesh.getJacobians(et, pts)
        vol = float(np.sum(np.asarray(det).reshape(-1, len(w)) * w))
        groups = {}
        for d, t in gmsh.model.getPhysicalGroups():
            _, coords = gmsh.model.mesh.getNodesForPhysicalGroup(d, t)
            groups[gmsh.model.getPhysicalName(d, t)] = coords.reshape(-1, 3)
    finally:
        gmsh.finalize()
    return vol, groups


def test_spherical_pocket_mesh_of_an_inner_guided_cage(tmp_path):
    """An inner-land guided cage with 14 spherical pockets: one group per pocket whose nodes lie on
    its sphere (centre on the pitch circle), the bore tagged "guide" (200), the outside "outside"
    (205), no "bore"; and the mesh's volume is the annulus less 14 of the spheres' parts inside
    it (the dblquad of the module docstring), within 1e-4 (a curved quadratic mesh at 6 mm)."""
    from flexbearing.mesh.cage_mesh import build_cage_mesh, mesh_quality_of
    g = PAPER_CAGE.with_(n_pockets=14, guidance="inner", pocket_shape="spherical").validate()
    path = build_cage_mesh(g, 6e-3, 2, tmp_path / "c.msh", pocket_size=4e-3)
    vol, groups = _mesh_volume_and_groups(path)
    shift = mesh_quality_of(path)["repair"]["max_node_shift_m"]
    tol = 1e-9 + 1e-5 * g.outer_radius + shift
    rp, rc = 0.5 * g.pocket_diameter, 0.5 * g.pocket_centre_diameter
    for k in range(14):
        th = 2 * math.pi * k / 14
        X = groups[f"pocket_{k:02d}"]
        d = np.linalg.norm(X - rc * np.array([0.0, math.cos(th), math.sin(th)]), axis=1)
        assert np.max(np.abs(d - rp)) <= tol
    assert np.max(np.abs(np.hypot(groups["guide"][:, 1], groups["guide"][:, 2]) - g.inner_radius)) <= tol
    assert np.max(np.abs(np.hypot(groups["outside"][:, 1], groups["outside"][:, 2]) - g.outer_radius)) <= tol
    assert "bore" not in groups
    ri, ro, w = g.inner_radius, g.outer_radius, g.width

    def chord(phi, r):
        s = rp * rp - (r * r + rc * rc - 2 * r * rc * math.cos(phi))
        return 2.0 * math.sqrt(s) * r if s > 0 else 0.0
    half = math.asin(rp / rc) * 1.01
    v_pocket = dblquad(chord, ri, ro, -half, half, epsabs=1e-14, epsrel=1e-10)[0]
    v_ref = math.pi * (ro ** 2 - ri ** 2) * w - 14 * v_pocket
    assert vol == pytest.approx(v_ref, rel=1e-4)


def test_paper_cage_keeps_its_cache_identity():
    """The new fields at the paper's values (outer guidance, cylindrical pockets on the 167 mm
    pitch circle) stay out of the hashed dict, so cached meshes and reduced cages keep their keys;
    a spherical or inner-guided cage gets its own."""
    from flexbearing.mesh.cage_mesh import mesh_key
    d = PAPER_CAGE.to_dict()
    assert not {"guidance", "pocket_shape", "pocket_centre_diameter"} & set(d)
    keys = {str(mesh_key(g, 4e-3, 2, 4e-3)) for g in (PAPER_CAGE, PAPER_CAGE.with_(guidance="inner"),
                                                       PAPER_CAGE.with_(pocket_shape="spherical"))}
    assert len(keys) == 3
