"""Symmetries of the equations of motion: the right-hand side commutes with the bearing's own
symmetry group.

The bearing (outer groove in the mid-plane, inner half-grooves mirror images of each other,
symmetric cage and guide land) is invariant under

* the axial mirror X -> −X (the two inner halves swap),
* a mirror through a plane containing the shaft axis (Z -> −Z here: the sense of rotation reverses),
* a rotation about the shaft axis by any angle (also with the flexible cage, whose modal
  coordinates turn with its body frame: slow test, it needs the reduced paper cage),

so, with the loads transformed alike and gravity off (it would break the last two), the
equations must satisfy f(g·y) = g·f(y) for each such map g, to rounding. The maps act on
positions as vectors and on rotations as pseudovectors (angular velocity w -> det(P)·P·w); for a
reflection P, P·R_n(theta)·P = R_(P n)(−theta), which sends the cage angles (phi, by, bz) of
A = R_z(bz)·R_y(by)·R_x(phi) to (phi, −by, −bz) (axial mirror) and (−phi, −by, bz) (Z mirror),
in any order of the product. A rotation about X by gamma moves every azimuth by gamma, rotates the
(Y, Z) components of the ring's and cage's positions, of the ring's small tilt vector and of the
loads, and turns the cage's attitude to R_x(gamma)·A (its angles re-extracted, its rates from the
turned angular velocity).

These checks share nothing with the force models they test: a sign error in a term that only one
side of the bearing, one sense of rotation or one azimuth sees (a left/right mix-up, an abs() on a
signed speed, a hard-coded sense of whirl) breaks them. Tolerance: 1e-9 of each block's largest
entry (measured: axial mirror ≤ 4e-16, Z mirror 1.2e-12, rotations ≤ 4e-11; the cage's angular
acceleration, by a central difference, 1.4e-10 against a bound of 1e-8). The Z mirror found a
defect when it was written: the tangential squeeze force of the guide land kept its sign when the
cage whirls faster than half its spin (flexbearing.multibody.guide_land), 1.5e-5 of the cage's accelerations
at this state.
"""
import math

import numpy as np
import pytest

from flexbearing.multibody import cage_body as CB
from flexbearing.multibody import dynamics as D
from flexbearing.multibody import model as M
from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL
from flexbearing.multibody.initial import initial_state
from flexbearing.multibody.model import build_model, state_layout

OMEGA = 14000 * math.pi / 30
FA, FR = 55e3, 4e3


def _disturbed_state(model, seed=3, on_rim=False):
    """The paper case's quasi-static state with every position and velocity disturbed, so that no
    accidental symmetry of the state hides an asymmetric term. `on_rim`: the cage centre 2 %
    beyond its guide clearance (rim contact with friction, film at its eps cap)."""
    y = initial_state(model, OMEGA, FA, FR)
    rng = np.random.default_rng(seed)
    lay = state_layout(model)
    for j in range(model.n_balls):
        o = 9 * j
        y[o:o + 2] += rng.normal(size=2) * 2e-6
        y[o + 2] += rng.normal() * 2e-3
        y[o + 3:o + 5] += rng.normal(size=2) * 0.05
        y[o + 5] *= 1 + 0.02 * rng.normal()
        y[o + 6:o + 9] += rng.normal(size=3) * 20.0
    r0, c0 = lay["ring"], lay["cage"]
    y[r0:r0 + 5] += (3e-6, 10e-6, -5e-6, 1e-4, -5e-5)
    y[r0 + 5:r0 + 10] += rng.normal(size=5) * np.array([0.01, 0.01, 0.01, 0.5, 0.5])
    y[c0:c0 + 3] += (2e-5, 1e-4, 2e-4)
    y[c0 + 4:c0 + 6] += (3e-4, -2e-4)
    y[c0 + 6:c0 + 9] += rng.normal(size=3) * 0.02
    y[c0 + 10:c0 + 12] += rng.normal(size=2) * 0.1
    if on_rim:
        e = 1.02 * model.p[M.P_CG]
        dy, dz = e * np.array([0.6, -0.8]) - y[c0 + 1:c0 + 3]
        y[c0 + 1:c0 + 3] += (dy, dz)
        for j in range(model.n_balls):      # the balls follow their pockets
            psi = y[9 * j + 2]
            y[9 * j + 2] += (-dy * math.sin(psi) + dz * math.cos(psi)) / y[9 * j + 1]
    return y


def _rhs(model, y, speed, load):
    dydt = np.zeros_like(y)
    work = D.new_work(model)
    D.rhs(0.0, y, dydt, model.p, model.flags, model.hertz_table, model.traction_table,
          np.array([[0.0, speed]]), np.array([[0.0, *load]]), np.zeros((0, 6)), work, model.cage)
    status = int(work[model.n_balls, M.WR_STATUS])
    assert status == 0, f"rhs flagged status {status}"
    return dydt, work


# ---------------------------------------------------------------- the maps (act on y and dy/dt alike)

def _axial_mirror(model, y):
    """X -> −X: x and its rate change sign; w_x stays, w_r and w_t change sign; tilts change sign."""
    g = y.copy()
    for j in range(model.n_balls):
        o = 9 * j
        g[o] = -y[o]
        g[o + 3] = -y[o + 3]
        g[o + 7:o + 9] = -y[o + 7:o + 9]
    lay = state_layout(model)
    r0, c0 = lay["ring"], lay["cage"]
    for k in (0, 3, 4, 5, 8, 9):            # x, tilt_y, tilt_z and their rates
        g[r0 + k] = -y[r0 + k]
    for k in (0, 4, 5, 6, 10, 11):          # x, by, bz and their rates
        g[c0 + k] = -y[c0 + k]
    return g


def _z_mirror(model, y):
    """Z -> −Z: azimuth psi -> −psi (ball j takes the place of ball −j), the sense of rotation
    reverses. Ball (w_x, w_r, w_t) -> (−w_x, −w_r, w_t) on the mirrored triad (e_t -> −P·e_t);
    ring z, tilt_y, spin angle and cage z, phi, by change sign."""
    z = model.n_balls
    g = y.copy()
    for j in range(z):
        o, m = 9 * j, 9 * ((-j) % z)
        b = y[o:o + 9]
        g[m:m + 9] = (b[0], b[1], -b[2], b[3], b[4], -b[5], -b[6], -b[7], b[8])
    lay = state_layout(model)
    r0, c0 = lay["ring"], lay["cage"]
    for k in (2, 3, 7, 8, 10):              # z, tilt_y, their rates, spin angle
        g[r0 + k] = -y[r0 + k]
    for k in (2, 3, 4, 8, 9, 10):           # z, phi, by and their rates
        g[c0 + k] = -y[c0 + k]
    return g


def _euler_zyx(A):
    """(phi, by, bz) of A = R_z(bz)·R_y(by)·R_x(phi) (|by| < 90°)."""
    return math.atan2(A[2, 1], A[2, 2]), -math.asin(A[2, 0]), math.atan2(A[1, 0], A[0, 0])


def _rate_matrix(by, bz):
    """G with w = G·(phi', by', bz') (flexbearing.multibody.cage_body.cage_angular_velocity)."""
    cy, sy, cz, sz = math.cos(by), math.sin(by), math.cos(bz), math.sin(bz)
    return np.array([[cz * cy, -sz, 0.0], [sz * cy, cz, 0.0], [-sy, 0.0, 1.0]])


def _rotation(model, y, gamma, derivative=False):
    """Rotation about X by gamma. Positions: azimuths + gamma; (Y, Z) components of the ring and
    cage positions and velocities, and the ring's tilt vector and rates, turned by gamma. The
    cage's attitude R_x(gamma)·A, its rates from the turned angular velocity. Applied to dy/dt
    (`derivative`), the cage's angle block is mapped through the angular velocity and acceleration
    instead (d/dt of the same map)."""
    c, s = math.cos(gamma), math.sin(gamma)
    R2 = np.array([[c, -s], [s, c]])
    g = y.copy()
    if not derivative:
        for j in range(model.n_balls):
            g[9 * j + 2] = y[9 * j + 2] + gamma
    lay = state_layout(model)
    r0, c0 = lay["ring"], lay["cage"]
    for k in (1, 3, 6, 8):                  # (y, z), (tilt_y, tilt_z) and their rates
        g[r0 + k:r0 + k + 2] = R2 @ y[r0 + k:r0 + k + 2]
    for k in (1, 7):                        # cage (y, z) and (vy, vz)
        g[c0 + k:c0 + k + 2] = R2 @ y[c0 + k:c0 + k + 2]
    return g


def _rotate_cage_angles(y_src, y_dst, c0, gamma):
    """Angles and angle rates of the rotated cage (R_x(gamma)·A, w -> R_x(gamma)·w)."""
    c, s = math.cos(gamma), math.sin(gamma)
    Rx = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    A = np.zeros((3, 3))
    CB.cage_rotation(y_src[c0 + 3], y_src[c0 + 4], y_src[c0 + 5], A)
    phi, by, bz = _euler_zyx(Rx @ A)
    w = np.array(CB.cage_angular_velocity(y_src[c0 + 4], y_src[c0 + 5], *y_src[c0 + 9:c0 + 12]))
    y_dst[c0 + 3:c0 + 6] = (phi, by, bz)
    y_dst[c0 + 9:c0 + 12] = np.linalg.solve(_rate_matrix(by, bz), Rx @ w)
    return Rx


def _cage_angular_acceleration(y, dydt, c0):
    """Inertial angular acceleration of the cage, w' = d/dt (G(theta)·theta'), by a central
    difference along the motion (G is smooth; h = 1e-7 s, error ~1e-14·|w'|)."""
    h = 1e-7

    def w_at(sign):
        yy = y + sign * h * dydt
        return np.array(CB.cage_angular_velocity(yy[c0 + 4], yy[c0 + 5], *yy[c0 + 9:c0 + 12]))
    return (w_at(1.0) - w_at(-1.0)) / (2.0 * h)


def _blocks(model, f):
    """The state's blocks, each compared on its own scale (a flexible cage's modal rates and
    accelerations too)."""
    lay = state_layout(model)
    z, r0, c0, m0, n = model.n_balls, lay["ring"], lay["cage"], lay["modes"], lay["n_modes"]
    b = f[:9 * z].reshape(z, 9)
    out = {"ball positions": b[:, 0:3], "ball accelerations": b[:, 3:6], "ball angular accelerations": b[:, 6:9],
           "ring rates": f[r0:r0 + 5], "ring accelerations": f[r0 + 5:r0 + 10],
           "cage rates": f[c0:c0 + 6], "cage accelerations": f[c0 + 6:c0 + 12]}
    if n:
        out.update({"modal rates": f[m0:m0 + n], "modal accelerations": f[m0 + n:m0 + 2 * n]})
    return out


def _assert_equal_blocks(model, got, want, what, rtol=1e-9):
    gb, wb = _blocks(model, got), _blocks(model, want)
    for name in gb:
        scale = np.max(np.abs(wb[name])) + 1e-300
        err = np.max(np.abs(gb[name] - wb[name])) / scale
        assert err < rtol, f"{what}: {name} differ by {err:.2e} of their scale"


ATTITUDE_CASES = {
    "free balls": {},
    "free balls, cage on its rim": {"on_rim": True},
    "free balls, no transverse traction": {"transverse_traction": False},
    "outer control": {"ball_attitude": "outer"},
    "inner control": {"ball_attitude": "inner"},
    "jones": {"ball_attitude": "jones"},
    "no_pivot": {"ball_attitude": "no_pivot", "transverse_traction": False},
}


@pytest.mark.parametrize("case", list(ATTITUDE_CASES))
def test_axial_mirror(case):
    """f(P·y; −Fx) = P·f(y; Fx) for the mirror X -> −X, gravity on (it is symmetric under this map).
    The left and right inner half-grooves exchange their roles: every term that treats one half
    differently from the other fails this."""
    opts = dict(ATTITUDE_CASES[case])
    on_rim = opts.pop("on_rim", False)
    model = build_model(PAPER_BEARING, PAPER_OIL, {**opts, "gravity": 9.81})
    y = _disturbed_state(model, on_rim=on_rim)
    f, work = _rhs(model, y, OMEGA, (FA, 0.0, -FR))
    fm, work_m = _rhs(model, _axial_mirror(model, y), OMEGA, (-FA, 0.0, -FR))
    _assert_equal_blocks(model, fm, _axial_mirror(model, f), f"axial mirror, {case}")
    z = model.n_balls
    assert (work[z, M.WR_RIM_F] > 0.0) == on_rim
    assert work_m[z, M.WR_RING_TORQUE] == pytest.approx(work[z, M.WR_RING_TORQUE], rel=1e-9)


@pytest.mark.parametrize("case", list(ATTITUDE_CASES))
def test_mirror_through_the_axis_reverses_the_rotation(case):
    """f(P·y; −omega_i, −Fz) = P·f(y; omega_i, Fz) for the mirror Z -> −Z, gravity off: the same
    bearing turning the other way. Fails on any term that assumes the sense of rotation."""
    opts = dict(ATTITUDE_CASES[case])
    on_rim = opts.pop("on_rim", False)
    model = build_model(PAPER_BEARING, PAPER_OIL, opts)
    y = _disturbed_state(model, on_rim=on_rim)
    f, work = _rhs(model, y, OMEGA, (FA, 1.5e3, -FR))
    fm, work_m = _rhs(model, _z_mirror(model, y), -OMEGA, (FA, 1.5e3, FR))
    _assert_equal_blocks(model, fm, _z_mirror(model, f), f"Z mirror, {case}")
    z = model.n_balls
    assert (work[z, M.WR_RIM_F] > 0.0) == on_rim
    # the drive torque changes sign with the speed: the same power
    assert work_m[z, M.WR_RING_TORQUE] == pytest.approx(-work[z, M.WR_RING_TORQUE], rel=1e-9)


@pytest.mark.parametrize("gamma_deg, on_rim", [(7.3, False), (90.0, False), (211.0, True)])
def test_rotation_about_the_shaft_axis(gamma_deg, on_rim):
    """f(R·y; R·F) = R·f(y; F) for a rotation by gamma about X, gravity off: no azimuth (ball 0,
    pocket 0, the +Y axis) is special."""
    model = build_model(PAPER_BEARING, PAPER_OIL, {})
    _check_rotation(model, _disturbed_state(model, on_rim=on_rim), math.radians(gamma_deg), on_rim)


@pytest.mark.slow
@pytest.mark.parametrize("gamma_deg, on_rim", [(7.3, False), (211.0, True)])
def test_rotation_about_the_shaft_axis_flexible_cage(paper_reduced_cage, gamma_deg, on_rim):
    """The same rotation with the reduced paper cage (26 modes, flexbearing.coupling.flexible_cage) as a
    floating-frame body: the modal coordinates live in the cage's body frame, which turns with
    the bearing, so the map leaves them and their rates unchanged, and f(R·y) = R·f(y) holds to
    rounding whether or not the mesh itself is symmetric. Checks the frame-objectivity of the
    floating-frame terms (mass matrix, quadratic velocity forces, deformed pocket and guide-land
    points) at a state with the cage deformed, vibrating, tilted and (211°) on its rim. The state's
    modal coordinates: the static centrifugal deformation plus a random one of its size, rates
    random of that size times 2000 1/s. Bounds as the rigid cage's (1e-9 of each block, 1e-8 for
    w'); measured: modal accelerations 1.4e-13, cage accelerations 6.5e-11 (on the rim), w' 9.6e-12."""
    from flexbearing.coupling.flexible_cage import flexible_cage_body
    basis = flexible_cage_body(paper_reduced_cage, 26, 1e-5, centrifugal_correction=False)
    model = build_model(PAPER_BEARING, PAPER_OIL, {}, cage_body=basis.body)
    lay = state_layout(model)
    m0, n = lay["modes"], lay["n_modes"]
    y = _disturbed_state(model, on_rim=on_rim)
    b = basis.body
    q_static = y[lay["cage"] + 9] ** 2 * (b.Sx[1, 1] + b.Sx[2, 2]) / b.stiffness
    rng = np.random.default_rng(11)
    size = np.max(np.abs(q_static))
    y[m0:m0 + n] = q_static + rng.normal(size=n) * size
    y[m0 + n:m0 + 2 * n] = rng.normal(size=n) * size * 2000.0
    _check_rotation(model, y, math.radians(gamma_deg), on_rim)


def _check_rotation(model, y, gamma, on_rim):
    c0 = state_layout(model)["cage"]
    gamma_deg = math.degrees(gamma)
    load = np.array([FA, 1.5e3, -FR])
    f, work = _rhs(model, y, OMEGA, load)
    yr = _rotation(model, y, gamma)
    Rx = _rotate_cage_angles(y, yr, c0, gamma)
    fr, work_r = _rhs(model, yr, OMEGA, Rx @ load)
    want = _rotation(model, f, gamma, derivative=True)
    # the cage's angle block through the angular velocity and acceleration (w -> Rx·w, w' -> Rx·w')
    want[c0 + 3:c0 + 6] = yr[c0 + 9:c0 + 12]
    got_wdot = _cage_angular_acceleration(yr, fr, c0)
    want_wdot = Rx @ _cage_angular_acceleration(y, f, c0)
    assert np.max(np.abs(got_wdot - want_wdot)) < 1e-8 * np.max(np.abs(want_wdot))
    want[c0 + 9:c0 + 12] = fr[c0 + 9:c0 + 12]      # compared through w' above
    _assert_equal_blocks(model, fr, want, f"rotation by {gamma_deg}°")
    z = model.n_balls
    assert (work[z, M.WR_RIM_F] > 0.0) == on_rim
    assert work_r[z, M.WR_RING_TORQUE] == pytest.approx(work[z, M.WR_RING_TORQUE], rel=1e-9)


@pytest.mark.parametrize("control", ["outer", "inner"])
def test_quasi_static_solution_mirrors(control):
    """The quasi-static solver (an independent implementation of the same contact geometry) under
    the two mirrors: −omega_i with −Fz gives the same loads and angles at the mirrored azimuths
    (ball j at −psi_j), the ring's z and tilt_y and every spin reversed; −Fx gives the contact angles
    mirrored (sign reversed) and the ring's x and tilts reversed. Bound 1e-9 (measured 8e-13,
    the solver's tolerance)."""
    from flexbearing.multibody.quasi_static import grooves_from_bearing, solve_quasi_static
    g = grooves_from_bearing(PAPER_BEARING)
    a = solve_quasi_static(g, OMEGA, fx=FA, fy=1.5e3, fz=-FR, control=control)
    z = len(a.psi)
    mirrored = [(-j) % z for j in range(z)]
    b = solve_quasi_static(g, -OMEGA, fx=FA, fy=1.5e3, fz=FR, control=control)
    assert a.converged and b.converged
    qmax = np.max(a.load)
    assert np.max(np.abs(b.load[mirrored] - a.load)) < 1e-9 * qmax
    assert np.max(np.abs(b.contact_angle[mirrored] - a.contact_angle)) < 1e-9
    u = a.ring_displacement * np.array([1, 1, -1, -1, 1])
    assert np.max(np.abs(b.ring_displacement - u)) < 1e-9 * np.max(np.abs(u))
    assert b.cage_speed == pytest.approx(-a.cage_speed, rel=1e-9)
    c = solve_quasi_static(g, OMEGA, fx=-FA, fy=1.5e3, fz=-FR, control=control)
    assert c.converged
    assert np.max(np.abs(c.load - a.load[:, [0, 2, 1]])) < 1e-9 * qmax
    assert np.max(np.abs(c.contact_angle + a.contact_angle[:, [0, 2, 1]])) < 1e-9
    u = a.ring_displacement * np.array([-1, 1, 1, -1, -1])
    assert np.max(np.abs(c.ring_displacement - u)) < 1e-9 * np.max(np.abs(u))
    assert c.cage_speed == pytest.approx(a.cage_speed, rel=1e-9)


# ---------------------------------------------------------------- other cages (cage.guidance, cage.pocket_shape)
CAGE_CASES = {
    "inner-land guided": dict(guidance="inner"),
    "inner-land guided, on its rim": dict(guidance="inner", on_rim=True),
    "ball riding, spherical pockets": dict(guidance="balls", pocket_shape="spherical"),
    # not on its rim: the spherical pockets (Cp 0.25 mm) hold the cage radially before it reaches
    # the land's rim (Cg 0.375 mm), the balls would sit deep in their pockets
    "outer-land guided, spherical pockets": dict(pocket_shape="spherical"),
}


def _cage_case(case):
    """Model and disturbed state of a cage case; `on_rim` puts the cage 2 % beyond its guide
    clearance from the land's centre (the ring's for the inner land)."""
    opts = dict(CAGE_CASES[case])
    on_rim = opts.pop("on_rim", False)
    bearing = PAPER_BEARING.with_(cage=PAPER_BEARING.cage.with_(**opts))
    model = build_model(bearing, PAPER_OIL, {})
    y = _disturbed_state(model, on_rim=on_rim)
    if on_rim and bearing.cage.guidance == "inner":
        lay = state_layout(model)
        r0, c0 = lay["ring"], lay["cage"]
        e = 1.02 * model.p[M.P_CG]
        dy, dz = y[r0 + 1:r0 + 3] + e * np.array([0.6, -0.8]) - y[c0 + 1:c0 + 3]
        y[c0 + 1:c0 + 3] += (dy, dz)
        for j in range(model.n_balls):
            psi = y[9 * j + 2]
            y[9 * j + 2] += (-dy * math.sin(psi) + dz * math.cos(psi)) / y[9 * j + 1]
    return model, y, on_rim


@pytest.mark.parametrize("case", list(CAGE_CASES))
def test_other_cages_axial_mirror(case):
    """The axial mirror for the inner-land guided, ball-riding and spherical-pocket cages."""
    model, y, on_rim = _cage_case(case)
    f, work = _rhs(model, y, OMEGA, (FA, 0.0, -FR))
    fm, _ = _rhs(model, _axial_mirror(model, y), OMEGA, (-FA, 0.0, -FR))
    _assert_equal_blocks(model, fm, _axial_mirror(model, f), f"axial mirror, {case}")
    assert (work[model.n_balls, M.WR_RIM_F] > 0.0) == on_rim


@pytest.mark.parametrize("case", list(CAGE_CASES))
def test_other_cages_mirror_through_the_axis(case):
    """The mirror Z -> −Z (the rotation reversed): the inner land's Couette term, whose speed is
    the ring's, must turn with it."""
    model, y, on_rim = _cage_case(case)
    f, work = _rhs(model, y, OMEGA, (FA, 1.5e3, -FR))
    fm, work_m = _rhs(model, _z_mirror(model, y), -OMEGA, (FA, 1.5e3, FR))
    _assert_equal_blocks(model, fm, _z_mirror(model, f), f"Z mirror, {case}")
    z = model.n_balls
    assert work_m[z, M.WR_RING_TORQUE] == pytest.approx(-work[z, M.WR_RING_TORQUE], rel=1e-9)


@pytest.mark.parametrize("case", list(CAGE_CASES))
def test_other_cages_rotation_about_the_shaft_axis(case):
    """A rotation by 211° about the shaft axis."""
    model, y, on_rim = _cage_case(case)
    _check_rotation(model, y, math.radians(211.0), on_rim)
