"""Conical pockets (cage.pocket_shape = "conical", cage.pocket_cone_angle; flexbearing.multibody.pocket).

Analytic references: the cone tangent to the sphere of radius Rp about the pocket centre has the
radius Rp/cos(beta) + s·tan(beta) across its axis; a centred ball's clearance is Cp = Rp − Rb =
(Dp − Dw)/2 in every direction; the distance from a ball centre to the wall is checked against
the distance to the straight generator found by a bounded scalar minimisation (scipy, to 1e-13 m:
independent of the closed form); a ball moved along a generator keeps its gap and sees the
circumferential radius Rp + t·tan(beta) (Meusnier: r/cos(beta)); beta = 0 is the cylinder (to
rounding); the force is the pocket law along the wall normal; the pocket volume in the cage mass is a
double integral of the cone's chord lengths (scipy dblquad); the mesh's pocket nodes lie on the cone.
"""
import math

import numpy as np
import pytest
from tolerances import U, assert_within, gamma
from scipy.optimize import minimize_scalar

from flexbearing.common.validation import InputError
from flexbearing.mesh.cage_geometry import PAPER_CAGE
from flexbearing.multibody import dynamics as D
from flexbearing.multibody import model as M
from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL
from flexbearing.multibody.pocket import (conical_pocket_curvature_radii, pocket_axis_point,
                                          pocket_contact_offset, pocket_curvature_radii)
from test_pocket_shapes import annulus_minus_pockets_mass

OFF = {"traction": False, "drag": False, "damping": False, "rolling_resistance": False}
R_PITCH = 0.5 * PAPER_BEARING.pitch_diameter
BETA = math.radians(8.0)
RB, RP = 0.5 * PAPER_BEARING.ball_diameter, 0.5 * PAPER_CAGE.pocket_diameter
A = np.array([0.0, 1.0, 0.0])                 # the pocket axis (radial, +y)
CONE = 2                                      # POCKET_SHAPES index


def _model(shape="conical", beta=BETA):
    cage = PAPER_CAGE.with_(pocket_shape=shape, pocket_cone_angle=beta if shape == "conical" else 0.0)
    return M.build_model(PAPER_BEARING.with_(cage=cage), PAPER_OIL, OFF)


def _wall_distance(s_b, rho_b, beta):
    """Distance from the point (s_b, rho_b) of the meridian plane to the generator rho(s) =
    Rp/cos(beta) + s·tan(beta), by minimising over s."""
    f = lambda s: math.hypot(s - s_b, RP / math.cos(beta) + s * math.tan(beta) - rho_b)
    return minimize_scalar(f, bounds=(s_b - 0.05, s_b + 0.05), method="bounded",
                           options={"xatol": 1e-13}).fun


@pytest.mark.parametrize("s, rho, phi", [(0.0, 1e-4, 0.0), (1e-4, 5e-5, 1.0), (-2e-4, 1.5e-4, 2.5),
                                         (3e-4, 2e-4, -0.7)])
def test_approach_is_the_distance_to_the_wall(s, rho, phi):
    """Rp − Z is the distance from the ball centre to the cone; n is normal to the generator and
    the wall point p + e + Rp·n lies on the cone."""
    er = np.array([math.cos(phi), 0.0, math.sin(phi)])
    d = s * A + rho * er
    ex, ey, ez, ux, uy, uz, z = pocket_contact_offset(*d, *A, CONE, BETA)
    assert RP - z == pytest.approx(_wall_distance(s, rho, BETA), abs=1e-12)
    n = np.array([ux, uy, uz]) / z
    assert np.linalg.norm(n) == pytest.approx(1.0, abs=1e-14)
    assert n @ (math.cos(BETA) * A + math.sin(BETA) * er) == pytest.approx(0.0, abs=1e-14)
    q = np.array([ex, ey, ez]) + RP * n                     # the wall point, from the pocket centre
    sq = q @ A
    assert np.linalg.norm(q - sq * A) == pytest.approx(RP / math.cos(BETA) + sq * math.tan(BETA), abs=1e-15)
    # the line of action through the ball centre along n meets the axis at pocket_axis_point
    t = pocket_axis_point(*d, *A, CONE, BETA)
    foot = d - (rho / math.cos(BETA)) * n
    assert foot == pytest.approx(t * A, abs=1e-15)


def test_centred_ball_clearance_and_generator_displacement():
    """Centred: gap Cp = (Dp − Dw)/2 all round. Moved by t along a generator: Z = 0 (the gap
    stays Cp) and the circumferential radius is Rp + t·tan(beta)."""
    cp = RP - RB
    assert cp == pytest.approx(0.5 * (PAPER_CAGE.pocket_diameter - PAPER_BEARING.ball_diameter), rel=1e-14)
    for phi in np.linspace(0, 2 * np.pi, 7):
        er = np.array([math.cos(phi), 0.0, math.sin(phi)])
        assert RP - _wall_distance(0.0, 0.0, BETA) == pytest.approx(0.0, abs=1e-12)   # the tangent sphere
        # from a ball Z0 off centre towards the wall (Z0 > |t|·tan(beta): it stays on that side)
        z0 = 1e-4
        for t in (-3e-4, 2e-4):
            d = t * (math.cos(BETA) * A + math.sin(BETA) * er) + z0 * (math.cos(BETA) * er - math.sin(BETA) * A)
            z = pocket_contact_offset(*d, *A, CONE, BETA)[6]
            # d formed here and Z in the kernel: <= 20 roundings on |d| <= |t| + z0 (Z is
            # Lipschitz 1 in the ball position)
            assert_within(abs(z - z0), 2 * gamma(20) * (abs(t) + z0), "approach on the generator",
                          effect=z0)
            s, rho = d @ A, np.linalg.norm(d - (d @ A) * A)
            rxi, reta = conical_pocket_curvature_radii(RB, RP, BETA, s, rho)
            rc = RP + t * math.tan(BETA)
            # 1/Rb − 1/rc ~ 1e-3 of 1/Rb: rounding of rc (1e-16 relative) is 1e-13 of R_xi
            assert rxi == pytest.approx(1.0 / (1.0 / RB - 1.0 / rc), rel=1e-11)
            assert reta == RB
    # at the nominal contact the cone's radii are the cylinder's (the Hertz constant the model uses)
    assert conical_pocket_curvature_radii(RB, RP, BETA, -1e-5 * math.sin(BETA), 1e-5 * math.cos(BETA)) == \
        pytest.approx(pocket_curvature_radii(RB, RP), rel=1e-12)


def test_zero_angle_is_the_cylinder():
    rng = np.random.default_rng(3)
    for _ in range(20):
        d = rng.normal(scale=2e-4, size=3)
        cyl = pocket_contact_offset(*d, *A, 0, 0.0)
        cone = pocket_contact_offset(*d, *A, CONE, 0.0)
        assert cone == pytest.approx(cyl, rel=1e-15, abs=1e-19)     # offsets ~2e-4 m: rounding ~1e-20 m
        assert pocket_axis_point(*d, *A, CONE, 0.0) == pocket_axis_point(*d, *A, 0, 0.0)


def _pocket(model, offset):
    b = np.array([0.0, R_PITCH, 0.0]) + offset
    return D._pocket_interface(b[0], b[1], b[2], 0, 0, 0, 0, 0, 0, 0.0, R_PITCH, 0.0, *A,
                               0, 0, 0, 0, 0, 0, 0, 0, 0, model.p, model.flags)


def test_pocket_force_along_the_wall_normal():
    """A ball pressed into the cone along its normal n by Z: Q = Kc·Z (Z <= Cp), Kc·Cp + Kn·(Z −
    Cp)^1.5 beyond (the cylinder's Kn: the nominal contact), on the ball along −n, which has an
    axial (radial-to-the-bearing) part sin(beta)·Q: the cone pushes the ball towards its narrow end."""
    m = _model()
    cp = m.p[M.P_CP]
    assert m.p[M.P_KN] == _model("cylindrical").p[M.P_KN]
    er = np.array([0.6, 0.0, 0.8])
    n = math.cos(BETA) * er - math.sin(BETA) * A
    for z, rtol in ((0.5 * cp, 1e-12), (cp + 3e-6, 1e-9)):
        out = _pocket(m, z * n)
        # placed at R_pitch + offset: u R_pitch (Sterbenz-exact difference from the pocket centre
        # after that) + <= 12 roundings of the cone geometry on Z
        assert_within(abs(out[10] - z), 2 * U * R_PITCH + 2 * gamma(12) * z, "approach Z", effect=z)
        q = 11.0 / cp * z if z <= cp else 11.0 + m.p[M.P_KN] * (z - cp) ** 1.5
        assert out[9] == pytest.approx(q, rel=rtol)
        assert np.array(out[0:3]) == pytest.approx(-q * n, rel=rtol, abs=rtol * q)
        # contact point on the cone's wall
        w = np.array(out[6:9]) - np.array([0.0, R_PITCH, 0.0])
        rho_w = RP / math.cos(BETA) + (w @ A) * math.tan(BETA)
        # the wall point's coordinates are ~R_pitch: <= 12 roundings there and in the generator's
        # radius (a norm and a chain of 4, with a libm tangent), and the normal's direction: the
        # offset's placement error (2 u R_pitch in each of 3 coordinates) over its length z, times Rp
        assert_within(abs(np.linalg.norm(w - (w @ A) * A) - rho_w),
                      2 * gamma(12) * (R_PITCH + rho_w) + RP * 2 * math.sqrt(3) * U * R_PITCH / z,
                      "contact point on the cone", effect=z)
    # a ball moved towards the wide end along the axis is free; towards the narrow end it is held
    assert _pocket(m, 1e-4 * A)[9] == 0.0
    assert _pocket(m, -1e-4 * A + 1e-9 * er)[10] == pytest.approx(1e-4 * math.sin(BETA) + 1e-9 * math.cos(BETA), rel=1e-9)


def test_conical_pocket_volume_in_the_mass():
    """rho·(annulus − Z·V), V the cone's part inside the annulus: dblquad over (r, phi) of the
    chord 2·sqrt(R(s)² − (r·sin(phi))²) along x (s = r·cos(phi) − Rpitch). 2e-3: the model's grid."""
    cage = PAPER_CAGE.with_(pocket_shape="conical", pocket_cone_angle=BETA).validate()
    ri, ro, rc = cage.inner_radius, cage.outer_radius, 0.5 * cage.pocket_centre_diameter

    def chord(phi, r):
        rr = cage.cone_radius(r * math.cos(phi) - rc)
        s = rr * rr - (r * math.sin(phi)) ** 2
        return 2.0 * math.sqrt(s) * r if s > 0 else 0.0
    m_ref = annulus_minus_pockets_mass(cage, chord, math.asin(cage.cone_radius(ro - rc) / ri) * 1.01)
    assert M.cage_mass_properties(cage)[0] == pytest.approx(m_ref, rel=2e-3)
    assert abs(M.cage_mass_properties(PAPER_CAGE)[0] - m_ref) > 5e-3 * m_ref


def test_cone_angle_refusals_and_scene_keys():
    from flexbearing.simulation.scene import loads_scene
    with pytest.raises(InputError, match=r"cage.pocket_cone_angle = 0.6 .*allowed"):
        PAPER_CAGE.with_(pocket_shape="conical", pocket_cone_angle=0.6).validate()
    with pytest.raises(InputError, match=r"cage.pocket_cone_angle = 0.1 rad applies to conical pockets only"):
        PAPER_CAGE.with_(pocket_cone_angle=0.1).validate()
    with pytest.raises(InputError, match=r"cage.pocket_cone_angle = 0.4 rad: the conical pocket is .* mm across"):
        PAPER_CAGE.with_(pocket_shape="conical", pocket_cone_angle=0.4).validate()
    base = ('name = "cone"\n[operation]\nduration = 0.01\n[operation.speed]\n'
            'phases = [{ kind = "uniform", duration = 0.01, rpm = 14000 }]\n[operation.load]\naxial_load = 55e3\n'
            '[output]\nsample_interval = 1e-3\nrecord = ["pocket_force"]\n')
    s = loads_scene(base + '[cage]\npocket_shape = "conical"\npocket_cone_angle = 0.14\n', "cone.toml")
    assert (s.bearing.cage.pocket_shape, s.bearing.cage.pocket_cone_angle) == ("conical", 0.14)
    assert "pocket_cone_angle" not in PAPER_CAGE.to_dict()


def test_conical_pocket_mesh(tmp_path):
    """Every node of pocket k lies on its cone (curved quadratic mesh at 6 mm: CAD precision or the
    repair's reported shift)."""
    from flexbearing.mesh.cage_mesh import build_cage_mesh, mesh_quality_of
    from flexbearing.verification.cad_test_cage import mesh_groups
    g = PAPER_CAGE.with_(pocket_shape="conical", pocket_cone_angle=BETA).validate()
    path = build_cage_mesh(g, 8e-3, 2, tmp_path / "c.msh", pocket_size=6e-3)
    shift = mesh_quality_of(path)["repair"]["max_node_shift_m"]
    groups = mesh_groups(path)
    rc = 0.5 * g.pocket_centre_diameter
    for k in range(g.n_pockets):
        th = 2 * math.pi * k / g.n_pockets
        a = np.array([0.0, math.cos(th), math.sin(th)])
        X = groups[f"pocket_{k:02d}"][2]
        s = X @ a
        dist = np.linalg.norm(X - np.outer(s, a), axis=1) - g.cone_radius(s - rc)
        assert np.max(np.abs(dist)) <= 1e-9 + 1e-5 * g.outer_radius + shift


def test_a_run_with_a_zero_angle_cone_is_the_cylindrical_run(tmp_path):
    """Through the whole dynamics (rhs, the cage's reaction point, the outputs): a 2 ms rigid-cage
    run with conical pockets of angle 0 gives the cylindrical run's pocket forces, to the
    integrator's tolerance (1e-6 relative per step; the pocket geometry differs by rounding only)."""
    import h5py
    from flexbearing.simulation.run import run_scene
    from flexbearing.simulation.scene import loads_scene
    base = ('name = "{n}"\n[cage]\npocket_shape = "{shape}"\n[operation]\nduration = 0.002\n[operation.speed]\n'
            'phases = [{{ kind = "uniform", duration = 0.002, rpm = 14000 }}]\n[operation.load]\n'
            'axial_load = 55e3\nradial_load = 4e3\n[integrator]\ntolerance = 1e-6\ninitial_step = 1e-7\n'
            '[output]\nsample_interval = 1e-4\nrecord = ["pocket_force"]\n')
    forces = {}
    for shape in ("cylindrical", "conical"):
        s = loads_scene(base.format(n=shape, shape=shape), f"{shape}.toml")
        run_scene(s, tmp_path / f"{shape}.h5", quiet=True)
        with h5py.File(tmp_path / f"{shape}.h5", "r") as f:
            forces[shape] = f["outputs/pocket_force"][()]
    scale = np.max(np.abs(forces["cylindrical"]))
    assert scale > 1.0                                   # the pockets carry load
    assert np.max(np.abs(forces["conical"] - forces["cylindrical"])) <= 1e-4 * scale
