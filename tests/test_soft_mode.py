"""The ball's soft ("pendulum") direction between two grooves (docs/design_clearance_rattle.md).

A ball loaded by a contact force Q along the line through a groove's curvature centre c, at distance
d = |b − c| from its centre b, is a two-force member: the potential of the contact, Phi(d − d0),
has the Hessian Phi''·n nᵀ + (Phi'/d)·(I − n nᵀ), n = (b − c)/d. Across the contact line it is a
spring Q/d = Q/((f − 1/2)·Dw + delta), the geometric ("pendulum") stiffness; along it the Hertz
stiffness 1.5·Q/delta. When the outer and inner normals line up, the soft stiffness of the ball is
Q_o/d_o + Q_i/d_i exactly. These tests differentiate the model's own contact geometry
(flexbearing.multibody.geometry.race_contact, contact_normal: the force on the ball is −Q·n,
flexbearing.multibody.race_kernels) with the Hertz law Q = K·delta^1.5, and compare the Jacobian
with that Hessian.
"""
import math

import numpy as np
import pytest

from flexbearing.multibody import geometry as geo
from flexbearing.multibody.bearing import PAPER_BEARING

B = PAPER_BEARING
DW = B.ball_diameter
K_HERTZ = 1.0e10           # N/m^1.5: any constant; the Hessian is linear in it


def grooves(alpha_deg: float):
    """Outer and inner groove centres (x, r) and f with both contacts at alpha on one line through
    a ball at (0, dm/2), each approached by 20 um (loads of the order of the paper case's)."""
    a = math.radians(alpha_deg)
    n = np.array([math.sin(a), math.cos(a)])           # from the outer groove centre to the ball
    b = np.array([0.0, 0.5 * B.pitch_diameter])
    approach = 20e-6
    c_o = b - ((B.fe - 0.5) * DW + approach) * n
    c_i = b + ((B.fi - 0.5) * DW + approach) * n
    return b, [(c_o, B.fe), (c_i, B.fi)]


def force(b, contacts):
    """Force of the races on the ball, −Σ K·delta^1.5·n, from the model's contact geometry."""
    f = np.zeros(2)
    for c, gf in contacts:
        delta, _, _ = geo.race_contact(b[0], b[1], c[0], c[1], gf, DW)
        if delta > 0.0:
            nx, nr = geo.contact_normal(b[0], b[1], c[0], c[1])
            f -= K_HERTZ * delta ** 1.5 * np.array([nx, nr])
    return f


def jacobian(b, contacts, h=1e-9):
    """Stiffness −dF/db by central differences (error O(h²/delta²) ~ 1e-8 of the Hertz part)."""
    J = np.zeros((2, 2))
    for k in range(2):
        e = np.zeros(2)
        e[k] = h
        J[:, k] = -(force(b + e, contacts) - force(b - e, contacts)) / (2.0 * h)
    return J


def hessian(b, contacts):
    """Σ 1.5·Q/delta·n nᵀ + Q/d·(I − n nᵀ) (module docstring)."""
    H = np.zeros((2, 2))
    for c, gf in contacts:
        d = float(np.linalg.norm(b - c))
        delta = d - (gf - 0.5) * DW
        q = K_HERTZ * delta ** 1.5
        n = (b - c) / d
        H += 1.5 * q / delta * np.outer(n, n) + q / d * (np.eye(2) - np.outer(n, n))
    return H


@pytest.mark.parametrize("alpha_deg", [0.0, 30.0, 40.0])
def test_pendulum_stiffness_of_a_ball_on_one_line(alpha_deg):
    b, contacts = grooves(alpha_deg)
    J = jacobian(b, contacts)
    H = hessian(b, contacts)
    # central differences of a smooth force: relative error ~ (h/delta)² ~ 1e-8, rounding ~ 1e-7
    assert np.allclose(J, H, rtol=1e-5, atol=1e-5 * np.abs(H).max())
    a = math.radians(alpha_deg)
    across = np.array([math.cos(a), -math.sin(a)])     # perpendicular to the contact line
    q = [K_HERTZ * 20e-6 ** 1.5] * 2
    pendulum = q[0] / ((B.fe - 0.5) * DW) + q[1] / ((B.fi - 0.5) * DW)   # the Q/((f − ½)·Dw)
    soft = across @ J @ across
    # exact value Q/d with d = (f − ½)·Dw + delta (the approach adds ~5 % to d here)
    exact = sum(qk / ((f - 0.5) * DW + 20e-6) for qk, f in zip(q, (B.fe, B.fi)))
    assert soft == pytest.approx(exact, rel=1e-5)
    assert soft == pytest.approx(pendulum, rel=0.07)
    # the soft direction is an eigenvector; the other is the contact line, both Hertz springs
    # (1.5·Q/delta each, the races held) and no geometric term: 30 times stiffer here
    w = np.linalg.eigvalsh(0.5 * (J + J.T))
    assert w[0] == pytest.approx(exact, rel=1e-5)
    assert w[1] == pytest.approx(2 * 1.5 * q[0] / 20e-6, rel=1e-5)


def test_misaligned_normals_stiffen_the_soft_direction():
    """With the outer and inner normals apart by Δ (the paper case: 28° and 39°), the Hertz springs
    add k_o·k_i/(k_o + k_i)·sin²Δ to the soft direction to first order; the Hessian has it exactly."""
    b, contacts = grooves(30.0)
    c_i, f_i = contacts[1]
    rot = math.radians(10.0)                           # swing the inner groove centre round the ball
    v = c_i - b
    c_i = b + np.array([v[0] * math.cos(rot) - v[1] * math.sin(rot), v[0] * math.sin(rot) + v[1] * math.cos(rot)])
    contacts = [contacts[0], (c_i, f_i)]
    J = jacobian(b, contacts)
    assert np.allclose(J, hessian(b, contacts), rtol=1e-5, atol=1e-5 * np.abs(J).max())
    q = K_HERTZ * 20e-6 ** 1.5
    k_n = 1.5 * q / 20e-6
    soft = np.linalg.eigvalsh(0.5 * (J + J.T))[0]
    geometric = q / ((B.fe - 0.5) * DW + 20e-6) + q / ((B.fi - 0.5) * DW + 20e-6)
    hertz_share = 0.5 * k_n * math.sin(rot) ** 2
    # the first-order split is good to O(geometric/k_n + sin²Δ) ~ 3 % here
    assert soft == pytest.approx(geometric + hertz_share, rel=0.05)
    assert geometric < soft < 1.5 * geometric
