"""What guides the cage (cage.guidance): the inner ring's land and the balls, beside the outer land.

Inner land: the cage's bore is the bush of a short journal bearing whose journal, the inner ring's
land, turns at omega_i. The references here integrate the short-bearing (Ocvirk) pressure of that
configuration in the inertial frame, with nothing taken from flexbearing.multibody.guide_land:

    h(theta) = Cg + e·n(theta),     e = cage centre − land centre,  n = (cos theta, sin theta)
    d/dz(h³ dp/dz) = 6·eta·(U_land + U_cage)·(dh/ds) + 12·eta·dh/dt,   s = R1·theta,
    dh/dt = (v_cage − v_land)·n,    ∫(z² − L²/4) dz = −L³/6 over the width,
    force on the cage (the outer surface of the film) = +∫ p·n dA,

with the half-Sommerfeld (pi-film) condition: p >= 0 for the static film (Hamrock, Fundamentals
of Fluid Film Lubrication, 1994, ch. 13; Childs 1993 §3.5 for the fixed half with whirl and
squeeze). Tolerances: 1e-8 relative, the quadrature's (scipy quad, absolute error estimate
below 1e-12 of the force here); 1e-12 where two closed forms meet.
"""
import math

import numpy as np
import pytest
from scipy.integrate import quad

from flexbearing.multibody import dynamics as D
from flexbearing.multibody import model as M
from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL
from flexbearing.multibody.guide_land import guide_land_force, rim_stiffness
from flexbearing.multibody.initial import initial_state
from flexbearing.multibody.model import build_model, state_layout
from flexbearing.common.validation import InputError

ETA, R1, L, CG = 0.055, 0.0806, 0.0283, 0.375e-3
K_RIM = rim_stiffness(230.8e9, L)
OMEGA = 14000 * math.pi / 30


def bush_film_force(ey, ez, vy, vz, w_land, w_cage, fixed_half):
    """Force (y, z) on the cage (bush) around a turning land (journal), by quadrature (module
    docstring). fixed_half: the pi-film on the converging half of the line of centres, theta in
    (theta_min − pi, theta_min) with theta_min the thinnest film (Childs; used with whirl and
    squeeze); else p = max(p, 0) over the whole circle (the static half-Sommerfeld film)."""
    U = R1 * (w_land + w_cage)

    def pbar(t):
        h = CG + ey * math.cos(t) + ez * math.sin(t)
        dh = -ey * math.sin(t) + ez * math.cos(t)
        hdot = vy * math.cos(t) + vz * math.sin(t)
        S = 6 * ETA * U * dh / R1 + 12 * ETA * hdot
        p = -S * L ** 3 / (12 * h ** 3)
        return p if fixed_half else max(p, 0.0)

    t_min = math.atan2(-ez, -ey)
    lo, hi = (t_min - math.pi, t_min) if fixed_half else (t_min - math.pi, t_min + math.pi)
    pts = None if fixed_half else [t_min]
    fy = quad(lambda t: pbar(t) * math.cos(t) * R1, lo, hi, points=pts, limit=400, epsabs=0)[0]
    fz = quad(lambda t: pbar(t) * math.sin(t) * R1, lo, hi, points=pts, limit=400, epsabs=0)[0]
    return fy, fz


def test_concentric_turning_land_drives_the_cage_by_petroff():
    """Concentric: no film force; Petroff's shear eta·(U_land − U_cage)/Cg over the bore gives the
    cage the torque 2·pi·eta·(omega_i − omega_c)·R1³·L/Cg, forward (it drags the cage along)."""
    w_i, w_c = OMEGA, 0.4 * OMEGA
    fy, fz, mx = guide_land_force(0.0, 0.0, 0.0, 0.0, w_c, w_i, R1, L, CG, ETA, 0.95, True, K_RIM, 0.1)
    assert (fy, fz) == (0.0, 0.0)
    petroff = ETA * (R1 * (w_i - w_c) / CG) * (2 * math.pi * R1 * L) * R1
    assert mx == pytest.approx(petroff, rel=1e-12)
    assert mx > 0.0


@pytest.mark.parametrize("eps, azimuth", [(0.1, 0.3), (0.5, 2.0), (0.8, -2.5), (0.9, 4.0)])
def test_eccentric_turning_land_against_the_integrated_pressure(eps, azimuth):
    """A still cage around the turning inner-ring land, offset eps·Cg at any azimuth: the force
    is the half-Sommerfeld integral of the bush's film (relative 1e-8), i.e. guide_land_force with
    e = cage − land and omega_land = omega_i; and it has the textbook magnitude
    W = eta·U·L³·eps·sqrt(pi²(1 − eps²) + 16·eps²)/(4·Cg²·(1 − eps²)²), U = R1·omega_i."""
    e = eps * CG
    ey, ez = e * math.cos(azimuth), e * math.sin(azimuth)
    fy, fz, _ = guide_land_force(ey, ez, 0.0, 0.0, 0.0, OMEGA, R1, L, CG, ETA, 0.99, False, K_RIM, 0.1)
    ry, rz = bush_film_force(ey, ez, 0.0, 0.0, OMEGA, 0.0, fixed_half=False)
    scale = math.hypot(ry, rz)
    assert abs(fy - ry) < 1e-8 * scale and abs(fz - rz) < 1e-8 * scale
    U = R1 * OMEGA
    w = ETA * U * L ** 3 * eps * math.sqrt(math.pi ** 2 * (1 - eps ** 2) + 16 * eps ** 2) / (4 * CG ** 2 * (1 - eps ** 2) ** 2)
    assert math.hypot(fy, fz) == pytest.approx(w, rel=1e-12)
    # restoring: the film pushes the cage back towards the land's centre
    assert fy * ey + fz * ez < 0.0


@pytest.mark.parametrize("eps, w_cage_ratio, vy, vz", [(0.5, 0.45, 0.02, 0.01), (0.7, 0.3, -0.01, 0.03)])
def test_whirling_squeezing_cage_against_the_integrated_pressure(eps, w_cage_ratio, vy, vz):
    """Cage and land both turning, the cage centre moving relative to the ring's (whirl and
    squeeze), ring moving too: the dynamic short-bearing force equals the integral over the fixed
    converging half (relative 1e-8); only the relative velocity matters."""
    e = eps * CG
    ey, ez = 0.8 * e, -0.6 * e
    w_c = w_cage_ratio * OMEGA
    v_ring = (0.05, -0.02)
    fy, fz, _ = guide_land_force(ey, ez, vy, vz, w_c, OMEGA, R1, L, CG, ETA, 0.99, True, K_RIM, 0.1)
    ry, rz = bush_film_force(ey, ez, vy, vz, OMEGA, w_c, fixed_half=True)
    scale = math.hypot(ry, rz)
    assert abs(fy - ry) < 1e-8 * scale and abs(fz - rz) < 1e-8 * scale
    # the same relative motion with the ring moving: the reference sees v_cage − v_land only
    ry2, rz2 = bush_film_force(ey, ez, (vy + v_ring[0]) - v_ring[0], (vz + v_ring[1]) - v_ring[1],
                               OMEGA, w_c, fixed_half=True)
    assert abs(ry2 - ry) < 1e-12 * scale and abs(rz2 - rz) < 1e-12 * scale


# ---------------------------------------------------------------- in the equations of motion

def _bearing(guidance, pocket_shape="cylindrical"):
    return PAPER_BEARING.with_(cage=PAPER_BEARING.cage.with_(guidance=guidance, pocket_shape=pocket_shape))


def _rhs(model, y, speed=OMEGA, load=(55e3, 0.0, -4e3)):
    dydt = np.zeros_like(y)
    work = D.new_work(model)
    D.rhs(0.0, y, dydt, model.p, model.flags, model.hertz_table, model.traction_table,
          np.array([[0.0, speed]]), np.array([[0.0, *load]]), np.zeros((0, 6)), work, model.cage)
    assert work[model.n_balls, M.WR_STATUS] == 0
    return dydt, work


def test_model_guiding_radius_and_clearance():
    """P_R1 is the cage's bore for the inner land, its outside for the outer; Cg from the land's
    diameter (default: the paper outer land's relative diametral clearance, 0.75/178.45, applied to
    the cage bore: flexbearing.simulation.derived)."""
    b = _bearing("inner")
    m = build_model(b, PAPER_OIL)
    assert m.p[M.P_R1] == b.cage.inner_radius
    assert m.p[M.P_CG] == pytest.approx(0.5 * 161.15e-3 * 0.75 / 178.45, rel=1e-12)
    b2 = b.with_(inner_land_diameter=160.6e-3)
    assert build_model(b2, PAPER_OIL).p[M.P_CG] == pytest.approx(0.5 * (161.15e-3 - 160.6e-3), rel=1e-12)
    with pytest.raises(InputError, match="bearing.inner_land_diameter"):
        b.with_(inner_land_diameter=161.2e-3).validate()
    with pytest.raises(InputError, match="cage.guidance"):
        PAPER_BEARING.with_(cage=PAPER_BEARING.cage.with_(guidance="shaft")).validate()


def _displaced_state(model, dy_cage=(1.2e-4, -0.9e-4), ring_offset=(2e-5, -3e-5)):
    y = initial_state(model, OMEGA, 55e3, 4e3)
    lay = state_layout(model)
    r0, c0 = lay["ring"], lay["cage"]
    y[r0 + 1:r0 + 3] += ring_offset
    y[r0 + 6:r0 + 8] += (0.01, -0.02)
    y[c0 + 1:c0 + 3] = y[r0 + 1:r0 + 3] + dy_cage
    y[c0 + 7:c0 + 9] += (0.03, 0.01)
    return y


def test_inner_land_in_the_equations_acts_between_cage_and_ring():
    """guidance = inner: the recorded land force is guide_land_force at the cage's offset and
    velocity relative to the land's axis in the cage's plane (the axis moves with the ring's centre
    and tilt: at the lever l = x_c − x_i it is at (y_i + tilt_z·l, z_i − tilt_y·l)) with the land
    turning at omega_i; the ring takes the opposite force (its acceleration differs from the
    ball-riding model's by −F/m_i, the cage's by +F/m_c), the force being normal to the tilted land
    axis (1, tilt_z, −tilt_y): F_x = tilt_y·F_z − tilt_z·F_y; the ring's tilts take the moments
    l·F_z and −l·F_y, and about X the opposite torque plus the moment of the pair."""
    inner = build_model(_bearing("inner"), PAPER_OIL)
    balls = build_model(_bearing("balls"), PAPER_OIL)
    y = _displaced_state(inner)
    lay = state_layout(inner)
    r0, c0, z = lay["ring"], lay["cage"], inner.n_balls
    y[r0 + 3:r0 + 5] += (2e-5, -3e-5)                 # a tilted ring, tilting
    y[r0 + 8:r0 + 10] += (0.5, 0.2)
    y[c0] += 1e-4                                     # the cage beside the ring's centre
    y[c0 + 6] += 0.02
    f_in, w_in = _rhs(inner, y)
    f_b, w_b = _rhs(balls, y)
    lever, ty, tz = y[c0] - y[r0], y[r0 + 3], y[r0 + 4]
    ey, ez = y[c0 + 1] - y[r0 + 1] - tz * lever, y[c0 + 2] - y[r0 + 2] + ty * lever
    vy = y[c0 + 7] - y[r0 + 6] - y[r0 + 9] * lever - tz * (y[c0 + 6] - y[r0 + 5])
    vz = y[c0 + 8] - y[r0 + 7] + y[r0 + 8] * lever + ty * (y[c0 + 6] - y[r0 + 5])
    p = inner.p
    fy, fz, mx = guide_land_force(ey, ez, vy, vz, y[c0 + 9], OMEGA, p[M.P_R1], p[M.P_LAND_L], p[M.P_CG],
                                  p[M.P_ETA0], p[M.P_EPSMAX], True, p[M.P_KRIM], p[M.P_MURIM], 1)
    assert (w_in[z, M.WR_LAND_FY], w_in[z, M.WR_LAND_FZ], w_in[z, M.WR_LAND_M]) == pytest.approx((fy, fz, mx), rel=1e-12)
    assert w_in[z, M.WR_EPS] == pytest.approx(math.hypot(ey, ez) / p[M.P_CG], rel=1e-12)
    # balls: no land at all
    assert (w_b[z, M.WR_LAND_FY], w_b[z, M.WR_LAND_FZ], w_b[z, M.WR_LAND_M], w_b[z, M.WR_EPS]) == (0, 0, 0, 0)
    mi = p[M.P_MI]
    fx = ty * fz - tz * fy
    d_ring = (f_in[r0 + 5:r0 + 8] - f_b[r0 + 5:r0 + 8]) * mi
    assert d_ring == pytest.approx([-fx, -fy, -fz], rel=1e-9, abs=1e-9 * math.hypot(fy, fz))
    d_tilt = (f_in[r0 + 8:r0 + 10] - f_b[r0 + 8:r0 + 10]) * p[M.P_IID]
    assert d_tilt == pytest.approx([lever * fz, -lever * fy], rel=1e-9, abs=1e-9 * lever * math.hypot(fy, fz))
    # the drive torque on the ring: minus the land's torque, minus the pair's moment about x
    m_pair = (y[c0 + 1] - y[r0 + 1]) * (-fz) - (y[c0 + 2] - y[r0 + 2]) * (-fy)     # −F at the cage centre
    assert w_in[z, M.WR_RING_TORQUE] - w_b[z, M.WR_RING_TORQUE] == pytest.approx(m_pair - mx, rel=1e-9)
    # the same cage under outer-ring guidance sees a different land (its own offset, land at rest)
    outer = build_model(PAPER_BEARING, PAPER_OIL)
    _, w_out = _rhs(outer, y)
    assert w_out[z, M.WR_LAND_M] < 0.0 < w_in[z, M.WR_LAND_M]   # outer land brakes, inner drives


@pytest.mark.parametrize("shape", ["cylindrical", "spherical"])
def test_ball_riding_cage_is_centred_by_its_pockets(shape):
    """guidance = balls, drag and damping off: moving the cage by delta along y changes the pocket
    forces on it by −Kc·delta·sum(sin² psi_j), psi_j the pocket axes' azimuths (cylindrical pockets: only the offset across each
    radial axis counts) or −Kc·delta·Z (spherical: the whole offset), Kc = 11/Cp, as long as every
    ball stays inside its clearance (the linear branch, exact to rounding)."""
    opts = {"drag": False, "damping": False, "traction": False}
    model = build_model(_bearing("balls", shape), PAPER_OIL, opts)
    y = initial_state(model, OMEGA, 55e3, 4e3)
    lay = state_layout(model)
    c0, z = lay["cage"], model.n_balls
    _, w0 = _rhs(model, y)
    assert np.all(w0[:z, M.W_POCKET_Z] < model.p[M.P_CP] / 2)
    delta = 0.2 * model.p[M.P_CP]
    y1 = y.copy()
    y1[c0 + 1] += delta
    _, w1 = _rhs(model, y1)
    assert np.all(w1[:z, M.W_POCKET_Z] < model.p[M.P_CP])
    dF = np.sum(w1[:z, M.W_PK_FY] - w0[:z, M.W_PK_FY])
    psi = y[c0 + 3] + 2 * math.pi * np.arange(z) / z       # the pocket axes' azimuths
    kc = model.p[M.P_KC]
    want = -kc * delta * (np.sum(np.sin(psi) ** 2) if shape == "cylindrical" else z)
    assert dF == pytest.approx(want, rel=1e-9)


def test_scene_cage_guidance_and_pocket_shape():
    """[cage] guidance and pocket_shape in a scene; unknown values are refused naming the field;
    the spherical pockets follow a changed pitch circle."""
    from flexbearing.simulation.scene import loads_scene
    base = ('name = "t"\n[operation]\nduration = 0.01\n[operation.speed]\n'
            'phases = [{kind = "uniform", duration = 0.01, rpm = 10000}]\n[operation.load]\naxial_load = 5e3\n'
            '[output]\nsample_interval = 1e-3\nrecord = ["cage_speed"]\n')
    s = loads_scene(base + '[cage]\nguidance = "inner"\npocket_shape = "spherical"\n')
    assert (s.bearing.cage.guidance, s.bearing.cage.pocket_shape) == ("inner", "spherical")
    s = loads_scene(base + '[bearing]\npitch_diameter = 0.1672\n[cage]\npocket_shape = "spherical"\n')
    assert s.bearing.cage.pocket_centre_diameter == 0.1672
    with pytest.raises(InputError, match=r"cage.guidance = 'shaft' must be one of 'outer', 'inner', 'balls'"):
        loads_scene(base + '[cage]\nguidance = "shaft"\n')
    with pytest.raises(InputError, match=r"cage.pocket_shape"):
        loads_scene(base + '[cage]\npocket_shape = "square"\n')
