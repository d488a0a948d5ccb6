"""Contact geometry and kinematics of a ball in a three-point-contact bearing (split inner ring).

Paper §2.2.1 (split inner ring); Harris & Kotzalas, Rolling Bearing Analysis, 5th ed., Vol. 2, ch. 1–3 (Jones 1960).
All functions are numba-compiled, scalar in / tuple out and allocation-free, so the dynamics can
call them inside its hot loop.

Frames and conventions
----------------------
* Bearing frame: X along the shaft axis, Y horizontal, Z vertical. The outer ring is fixed.
* Ball azimuth psi is measured from +Y towards +Z. A ball lives in its *azimuthal plane*, spanned
  by the axial unit vector e_x and the radial unit vector e_r = (0, cos psi, sin psi); the third
  direction is the tangential (orbital, rolling) unit vector e_t = e_x × e_r = (0, −sin psi, cos psi).
  (e_x, e_r, e_t) is right-handed; vector components in this module are given in that order
  (x, r, t).
* Groove curvature centres are points of the ring on a circle about the ring axis; in the ball's
  plane each is a point (x, r). Nominal positions in the ring frame (paper §2.2.1):
    outer:       x = 0,                         r = dm/2 − (fe − 0.5)·Dw
    inner-left:  x = +(fi − 0.5)·Dw·sin(alphaD), r = dm/2 + (fi − 0.5)·Dw·cos(alphaD) − Pd/2
    inner-right: x = −(fi − 0.5)·Dw·sin(alphaD), same r,
  The inner-left half-groove (the half at x < 0) has its centre at +x, so it touches the ball on the
  ball's −x side: pushing the inner ring towards +X loads the left half and unloads the right half.
  Pd is the diametral (radial) clearance; the whole clearance is given to the inner ring (its groove
  centres move inward by Pd/2), as in `Bearing.free_contact_angle`.
  Caution (tests/test_geometry.py): a ball seated on the outer race and the left half at the free
  angle alpha0 = acos(Dr/(B·Dw)) clears the right half only if Pd >= 2·(fe − 0.5)·Dw·(1 − cos alphaD)
  (88 um for the paper bearing); below that (Pd = 0 included) the ball stays held by all three races.
* The inner ring moves rigidly by (x_i, y_i, z_i, theta_y, theta_z) (translations and small
  rotations about Y and Z). A ring point at (x0, r0, psi) moves by u = t + theta × p; projected on
  the ball's plane (`ring_point_in_plane`):
      x = x0 + x_i + r0·theta_psi,      r = r0 + y_i·cos psi + z_i·sin psi − x0·theta_psi,
      theta_psi = theta_y·sin psi − theta_z·cos psi.
  The tangential component of u is dropped: the groove is a surface of revolution, so a point
  sliding along it changes nothing to first order.
* Contact with a groove of radius f·Dw whose curvature centre is c = (xc, rc) (`race_contact`):
      d = |b − c|,  delta = d − (f − 0.5)·Dw   (> 0: contact, the Hertz approach),
      n = (b − c)/d, the unit normal from the ball centre towards the contact point,
  for the outer AND the inner races (the ball sits inside both "groove circles").
  The race pushes the ball with the force  F_ball = −Q·n  (towards the curvature centre).
* Contact angle alpha, signed, with cos(alpha) >= 0:
      outer race (n_r > 0):  (sin alpha, cos alpha) = ( n_x,  n_r)
      inner race (n_r < 0):  (sin alpha, cos alpha) = (−n_x, −n_r)
  i.e. sin alpha = n_x·sign(n_r), cos alpha = |n_r|. With this convention the force of the inner
  race on the ball is +Q·(sin a_i, cos a_i) and that of the outer race −Q·(sin a_o, cos a_o), as in
  Jones's equations (Harris & Kotzalas Vol. 2, eq. 3.26–3.27). The inner-left contact has a
  positive angle, the inner-right a negative one.
* Contact point (centre of the contact ellipse) = the middle of the overlap:
      p = b + (Dw/2 − max(delta, 0)/2)·n,   rho = Dw/2 − max(delta, 0)/2 its distance from b.
* Contact directions: rolling direction e_t; transverse direction (in the ball plane, tangent to the
  contact) tau = (cos alpha, −sin alpha, 0) (points roughly towards +x for every contact); normal n.
* Velocities (`ball_surface_velocity`, `ring_surface_velocity`, `contact_kinematics`):
      ball surface:  v = v_b + omega_b × (rho·n)
      ring surface:  v = v_ring + omega_ring × (p − c_ring),  omega_ring = (spin, tilt rates)
  The contact itself moves with the ball's orbit, v_contact,t = r_p·psi_dot. Speeds of the two
  surfaces relative to the contact in the rolling direction, u_ball = v_ball,t − v_contact,t and
  u_race = v_race,t − v_contact,t, give the entrainment (rolling) speed U = (u_ball + u_race)/2;
  the slide velocity (ball relative to race) has the components
      slide_rolling    = (v_ball − v_race)·e_t,
      slide_transverse = (v_ball − v_race)·tau,
  (with the outer ring fixed and omega_i > 0, U is negative at the outer race and positive at the
  inner: the surfaces run past the contact in −e_t resp. +e_t), the approach rate d(delta)/dt = (v_ball − v_race)·n, and the spin (ball relative to the race,
  about the normal) omega_spin = (omega_b − omega_ring·e_x)·n.
"""
from __future__ import annotations

import math

from numba import njit


# ---------------------------------------------------------------- groove curvature centres
@njit(cache=True)
def cross(ax, ay, az, bx, by, bz):
    """The cross product a × b of two vectors given by their components (a tuple)."""
    return ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx


@njit(cache=True)
def outer_groove_centre(pitch_diameter, ball_diameter, fe):
    """Nominal outer-groove curvature centre (x, r) in a ball's plane, m.

    x = 0, r = dm/2 − (fe − 0.5)·Dw: the race bottom is at dm/2 + Dw/2, the groove radius fe·Dw.
    """
    return 0.0, 0.5 * pitch_diameter - (fe - 0.5) * ball_diameter


@njit(cache=True)
def inner_groove_centres(pitch_diameter, ball_diameter, fi, shim_angle, radial_clearance):
    """Nominal curvature centres of the two inner half-grooves in the ring frame, m.

    Returns (x_left, r_left, x_right, r_right):
        x_left = +(fi − 0.5)·Dw·sin(alphaD),  x_right = −(fi − 0.5)·Dw·sin(alphaD),
        r = dm/2 + (fi − 0.5)·Dw·cos(alphaD) − Pd/2.
    The left half (x < 0 part of the groove) has its centre at +x. With Pd = 0 a ball centred at
    (0, dm/2) touches all three races at zero load, each inner half at the angle ±alphaD.
    """
    s = (fi - 0.5) * ball_diameter
    r = 0.5 * pitch_diameter + s * math.cos(shim_angle) - 0.5 * radial_clearance
    xs = s * math.sin(shim_angle)
    return xs, r, -xs, r


@njit(cache=True)
def angular_contact_inner_centre(pitch_diameter, ball_diameter, fi, contact_angle):
    """Inner-groove centre (x, r) of an ordinary (one-groove) angular-contact ball bearing, m.

    Layout chosen so that a ball centred at b = (0, dm/2) touches both races at zero load with the
    free contact angle alpha0: inner centre b + (fi − 0.5)·Dw·(sin a0, cos a0), outer centre
    b − (fe − 0.5)·Dw·(sin a0, cos a0) (`angular_contact_outer_centre`); the centre distance is
    B·Dw, B = fi + fe − 1 (Harris & Kotzalas Vol. 1, ch. 2). Used as the special case of the
    quasi-static solver that is compared with the textbook examples.
    """
    s = (fi - 0.5) * ball_diameter
    return s * math.sin(contact_angle), 0.5 * pitch_diameter + s * math.cos(contact_angle)


@njit(cache=True)
def angular_contact_outer_centre(pitch_diameter, ball_diameter, fe, contact_angle):
    """Outer-groove centre (x, r) of an ordinary angular-contact ball bearing with free angle alpha0, m."""
    s = (fe - 0.5) * ball_diameter
    return -s * math.sin(contact_angle), 0.5 * pitch_diameter - s * math.cos(contact_angle)


@njit(cache=True)
def ring_point_in_plane(psi, x0, r0, ring_x, ring_y, ring_z, tilt_y, tilt_z):
    """Position (x, r) in the plane at azimuth psi of a ring point nominally at (x0, r0), m.

    Small-angle rigid-body motion u = t + theta × p, theta = (0, tilt_y, tilt_z), projected on
    (e_x, e_r):  x = x0 + ring_x + r0·theta_psi,  r = r0 + ring_y·cos psi + ring_z·sin psi − x0·theta_psi,
    with theta_psi = tilt_y·sin psi − tilt_z·cos psi.
    """
    c = math.cos(psi)
    s = math.sin(psi)
    th = tilt_y * s - tilt_z * c
    return x0 + ring_x + r0 * th, r0 + ring_y * c + ring_z * s - x0 * th


# ---------------------------------------------------------------- one ball–race contact
@njit(cache=True)
def race_contact(xb, rb, xc, rc, groove_f, ball_diameter):
    """Approach and contact angle of a ball (centre xb, rb) in a groove (centre xc, rc, radius f·Dw).

    delta = |b − c| − (f − 0.5)·Dw (m, positive = in contact, the Hertz approach);
    cos(alpha) = |n_r|, sin(alpha) = n_x·sign(n_r), n = (b − c)/|b − c| (module docstring):
    the centre lies radially inside the ball centre for the outer race and outside it for the
    inner race, so the race type follows from the geometry. Returns (delta, cos_alpha, sin_alpha).
    """
    dx = xb - xc
    dr = rb - rc
    d = math.sqrt(dx * dx + dr * dr)
    delta = d - (groove_f - 0.5) * ball_diameter
    if dr >= 0.0:
        return delta, dr / d, dx / d
    return delta, -dr / d, -dx / d


@njit(cache=True)
def contact_normal(xb, rb, xc, rc):
    """Unit normal (n_x, n_r) from the ball centre towards the contact point, n = (b − c)/|b − c|.

    The race force on the ball is −Q·n (towards the curvature centre) for both races.
    """
    dx = xb - xc
    dr = rb - rc
    d = math.sqrt(dx * dx + dr * dr)
    return dx / d, dr / d


@njit(cache=True)
def contact_point(xb, rb, nx, nr, delta, ball_diameter):
    """Centre of the contact ellipse (x_p, r_p) and its distance rho from the ball centre, m.

    p = b + rho·n, rho = Dw/2 − max(delta, 0)/2 (the middle of the Hertz overlap); the ball and the
    race share this point. Returns (x_p, r_p, rho).
    """
    rho = 0.5 * ball_diameter - 0.5 * max(delta, 0.0)
    return xb + rho * nx, rb + rho * nr, rho


# ---------------------------------------------------------------- velocities
@njit(cache=True)
def ball_surface_velocity(rho, nx, nr, vb_x, vb_r, vb_t, wb_x, wb_r, wb_t):
    """Velocity (x, r, t) of the ball's material point at p = b + rho·n, m/s.

    v = v_b + omega_b × (rho·n), components in (e_x, e_r, e_t), n = (nx, nr, 0):
    omega × n = (−w_t·n_r, w_t·n_x, w_x·n_r − w_r·n_x).
    v_b = (x_dot, r_dot, r_b·psi_dot) is the ball-centre velocity, omega_b the absolute angular velocity.
    """
    return (vb_x - rho * wb_t * nr,
            vb_r + rho * wb_t * nx,
            vb_t + rho * (wb_x * nr - wb_r * nx))


@njit(cache=True)
def ring_velocity_in_plane(psi, ring_speed, ring_x, ring_y, ring_z, ring_vx, ring_vy, ring_vz,
                           tilt_y_rate=0.0, tilt_z_rate=0.0):
    """The ring's rigid-body velocity field over the ball plane at azimuth psi, as coefficients.

    v = v_ring + omega × (p − c_ring), omega = (ring_speed, tilt_y_rate, tilt_z_rate) (small
    tilts, the convention of `ring_point_in_plane`), c_ring = (ring_x, ring_y, ring_z), at the
    point p = (x_p, r_p·cos psi, r_p·sin psi), projected on (e_x, e_r, e_t):

        v(x_p, r_p) = (a_x − r_p·g1,  a_r + x_p·g1,  a_t − x_p·g2 + ring_speed·(r_p − r_c))   (`ring_velocity_at`)

    g1 = tilt_z_rate·cos psi − tilt_y_rate·sin psi, g2 = tilt_y_rate·cos psi + tilt_z_rate·sin psi
    (the tilt rates about e_t and e_r), r_c = ring_y·cos psi + ring_z·sin psi,
    a_x = v_ring,x + tilt_z_rate·ring_y − tilt_y_rate·ring_z,
    a_r = v_ring,r + ring_speed·(ring_z·cos psi − ring_y·sin psi) − ring_x·g1,
    a_t = v_ring,t + ring_x·g2.
    The spin of an offset ring moves its surface radially in the ball plane (the ring_speed term of
    a_r): with a 20 um offset at 1466 rad/s that is 0.03 m/s, the order of the sliding speeds.
    Returns (a_x, a_r, a_t, g1, g2, r_c).
    """
    c = math.cos(psi)
    s = math.sin(psi)
    g1 = tilt_z_rate * c - tilt_y_rate * s
    g2 = tilt_y_rate * c + tilt_z_rate * s
    return (ring_vx + tilt_z_rate * ring_y - tilt_y_rate * ring_z,
            ring_vy * c + ring_vz * s + ring_speed * (ring_z * c - ring_y * s) - ring_x * g1,
            -ring_vy * s + ring_vz * c + ring_x * g2,
            g1, g2, ring_y * c + ring_z * s)


@njit(cache=True)
def ring_velocity_at(a_x, a_r, a_t, g1, g2, r_c, ring_speed, x_p, r_p):
    """Velocity (x, r, t) at the point (x_p, r_p) of the ball plane of the field
    `ring_velocity_in_plane` returned, m/s."""
    return a_x - r_p * g1, a_r + x_p * g1, a_t - x_p * g2 + ring_speed * (r_p - r_c)


@njit(cache=True)
def ring_surface_velocity(psi, r_p, ring_speed, ring_y, ring_z, ring_vx, ring_vy, ring_vz,
                          x_p=0.0, ring_x=0.0, tilt_y_rate=0.0, tilt_z_rate=0.0):
    """Velocity (x, r, t) of the race point (x_p, r_p) at azimuth psi of a ring, m/s: the
    rigid-body velocity v_ring + omega × (p − c_ring) of `ring_velocity_in_plane`."""
    a_x, a_r, a_t, g1, g2, r_c = ring_velocity_in_plane(psi, ring_speed, ring_x, ring_y, ring_z, ring_vx,
                                                         ring_vy, ring_vz, tilt_y_rate, tilt_z_rate)
    return ring_velocity_at(a_x, a_r, a_t, g1, g2, r_c, ring_speed, x_p, r_p)


@njit(cache=True)
def contact_kinematics(nx, nr, r_p, orbit_speed, ball_v_x, ball_v_r, ball_v_t,
                       race_v_x, race_v_r, race_v_t, wb_x, wb_r, wb_t, ring_speed):
    """Rolling and sliding at one contact (module docstring for the directions), SI.

    Inputs: normal n (nx, nr) from the ball centre to the contact point, contact radius r_p, ball
    orbital speed psi_dot (rad/s), surface velocities of the ball and of the race at the contact
    point (from `ball_surface_velocity`, `ring_surface_velocity`), the ball's absolute angular
    velocity and the ring's spin.
    Returns (entrainment_speed, u_ball, u_race, slide_rolling, slide_transverse, approach_rate,
    spin) with
      u = v_t − r_p·psi_dot (surface speeds relative to the moving contact, rolling direction e_t),
      entrainment_speed = (u_ball + u_race)/2,
      slide = v_ball − v_race resolved on e_t and tau = (cos a, −sin a, 0),
      approach_rate = (v_ball − v_race)·n (= d(delta)/dt),
      spin = (omega_b − omega_ring·e_x)·n (ball relative to race about the normal, rad/s).
    """
    if nr >= 0.0:
        ca = nr
        sa = nx
    else:
        ca = -nr
        sa = -nx
    vc = r_p * orbit_speed
    u_ball = ball_v_t - vc
    u_race = race_v_t - vc
    dvx = ball_v_x - race_v_x
    dvr = ball_v_r - race_v_r
    slide_t = ball_v_t - race_v_t
    slide_tau = dvx * ca - dvr * sa
    approach = dvx * nx + dvr * nr
    spin = (wb_x - ring_speed) * nx + wb_r * nr
    return 0.5 * (u_ball + u_race), u_ball, u_race, slide_t, slide_tau, approach, spin


@njit(cache=True)
def pitch_orbit_speed(inner_speed, outer_speed, ball_diameter, pitch_diameter, contact_angle):
    """Epicyclic cage (ball orbit) speed for pure rolling with equal contact angles, rad/s.

    omega_m = [omega_i·(1 − gamma) + omega_o·(1 + gamma)]/2, gamma = Dw·cos(alpha)/dm
    (Harris & Kotzalas Vol. 1, ch. 8; with a fixed outer ring nm = 0.5·ni·(1 − Dw·cos alpha/dm), paper §3.2).
    """
    g = ball_diameter * math.cos(contact_angle) / pitch_diameter
    return 0.5 * (inner_speed * (1.0 - g) + outer_speed * (1.0 + g))


def nominal_cage_speed(omega_i: float, dw: float, dm: float, alpha: float) -> float:
    """nm = 0.5·omega_i·(1 − Dw·cos(alpha)/dm), rad/s (paper §3.2)."""
    return 0.5 * omega_i * (1.0 - dw * math.cos(alpha) / dm)
