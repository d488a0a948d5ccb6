"""Hertz point contact between a ball and a race (or any two convex/conforming bodies).

Geometry convention (Hamrock & Brewe 1983; Harris & Kotzalas, Rolling Bearing Analysis, 5th ed.,
Vol. 1, ch. 6): x is the rolling direction, y the transverse direction (along the groove).
Rx, Ry are the effective radii of curvature of the gap h = x²/(2Rx) + y²/(2Ry):

    1/Rx = 1/r_ax + 1/r_bx,   1/Ry = 1/r_ay + 1/r_by,   1/R = 1/Rx + 1/Ry,

(a concave surface has a negative radius). For a ball in a groove Ry > Rx, the contact ellipse
has its semi-major axis a along y and its semi-minor axis b along x; k = a/b is the ellipticity.
If Ry < Rx the roles swap: a is still the semi-major axis but then lies along x.

Exact solution (Hertz; Johnson, Contact Mechanics, 1985, §4.2, eqs 4.36–4.40), with the
modulus e² = m = 1 − 1/k² and K(m), E(m) the complete elliptic integrals of the first and second
kind (scipy's parameter convention m = e²):

    Ry/Rx = (k²·E(m) − K(m)) / (K(m) − E(m))          (ellipticity equation)
    b = (6·E(m)·Q·R / (pi·k·E'))^(1/3),  a = k·b,      p0 = 3Q / (2·pi·a·b),
    delta = K(m)·[ (9/(2·E(m)·R)) · (Q/(pi·k·E'))² ]^(1/3),   Q = K_H·delta^1.5,
    K_H = pi·k·E'·sqrt(2·E(m)·R / (9·K(m)³)),

E' = 2/[(1 − nu1²)/E1 + (1 − nu2²)/E2] (so Johnson's E* = E'/2).

Three implementations:
* `hertz_point_contact` / `hertz_stiffness` (numba, the default in the dynamics): exact
  ellipticity by Newton iteration on the equation above with the Abramowitz & Stegun 17.3.34 /
  17.3.36 polynomial approximations of K and E (absolute error < 2e-8). Matches `hertz_exact`
  to < 1e-6 relative (tests/test_hertz.py).
* `hertz_point_contact_hb` / `hertz_stiffness_hb` (numba): the Hamrock–Brewe (J. Lubr. Technol.
  105:171, 1983) closed-form approximations k ≈ 1.0339·(Ry/Rx)^0.636, E ≈ 1.0003 + 0.5968·Rx/Ry,
  K ≈ 1.5277 + 0.6023·ln(Ry/Rx): a few per cent off for Ry/Rx in 1–100 (tested: ≤ 4 %).
* `hertz_exact` (plain Python + scipy): the reference, solving the ellipticity equation with
  brentq and scipy.special.ellipk/ellipe.
"""
from __future__ import annotations

import math

from numba import njit

# Abramowitz & Stegun 17.3.34: K(m) = sum a_i m1^i + sum b_i m1^i · ln(1/m1), m1 = 1 − m, |err| <= 2e-8
_KA0, _KA1, _KA2, _KA3, _KA4 = 1.38629436112, 0.09666344259, 0.03590092383, 0.03742563713, 0.01451196212
_KB0, _KB1, _KB2, _KB3, _KB4 = 0.5, 0.12498593597, 0.06880248576, 0.03328355346, 0.00441787012
# Abramowitz & Stegun 17.3.36: E(m) = 1 + sum a_i m1^i + sum b_i m1^i · ln(1/m1), |err| <= 2e-8
_EA1, _EA2, _EA3, _EA4 = 0.44325141463, 0.06260601220, 0.04757383546, 0.01736506451
_EB1, _EB2, _EB3, _EB4 = 0.24998368310, 0.09200180037, 0.04069697526, 0.00526449639


@njit(cache=True)
def ellipk_m1(m1):
    """Complete elliptic integral of the first kind K(m) as a function of m1 = 1 − m, 0 < m1 <= 1.

    Abramowitz & Stegun (1964) 17.3.34, absolute error <= 2e-8.
    """
    lg = -math.log(m1)
    pa = _KA0 + m1 * (_KA1 + m1 * (_KA2 + m1 * (_KA3 + m1 * _KA4)))
    pb = _KB0 + m1 * (_KB1 + m1 * (_KB2 + m1 * (_KB3 + m1 * _KB4)))
    return pa + pb * lg


@njit(cache=True)
def ellipe_m1(m1):
    """Complete elliptic integral of the second kind E(m) as a function of m1 = 1 − m, 0 < m1 <= 1.

    Abramowitz & Stegun (1964) 17.3.36, absolute error <= 2e-8.
    """
    lg = -math.log(m1)
    pa = 1.0 + m1 * (_EA1 + m1 * (_EA2 + m1 * (_EA3 + m1 * _EA4)))
    pb = m1 * (_EB1 + m1 * (_EB2 + m1 * (_EB3 + m1 * _EB4)))
    return pa + pb * lg


@njit(cache=True)
def race_curvature_radii(ball_diameter, pitch_diameter, groove_f, contact_angle, inner):
    """Effective radii (Rx, Ry) of a ball–race contact, m (Harris & Kotzalas Vol. 1, ch. 2).

    gamma = Dw·cos(alpha)/dm;  inner: Rx = Dw·(1 − gamma)/2,  outer: Rx = Dw·(1 + gamma)/2;
    Ry = f·Dw/(2f − 1) (ball radius Dw/2 against the groove radius −f·Dw).
    """
    gamma = ball_diameter * math.cos(contact_angle) / pitch_diameter
    if inner:
        rx = 0.5 * ball_diameter * (1.0 - gamma)
    else:
        rx = 0.5 * ball_diameter * (1.0 + gamma)
    ry = groove_f * ball_diameter / (2.0 * groove_f - 1.0)
    return rx, ry


@njit(cache=True)
def effective_modulus(E1, nu1, E2, nu2):
    """E' = 2 / [(1 − nu1²)/E1 + (1 − nu2²)/E2], Pa (Hamrock & Brewe 1983). Steel/steel ≈ 230 GPa."""
    return 2.0 / ((1.0 - nu1 * nu1) / E1 + (1.0 - nu2 * nu2) / E2)


@njit(cache=True)
def _elliptic_kde(m):
    """(K(m), E(m), K(m) − E(m)) for 0 <= m < 1, the difference without cancellation.

    m < 0.1: the hypergeometric series (Abramowitz & Stegun 17.3.11, 17.3.12)
    K = pi/2·sum c_n² m^n, E = pi/2·sum c_n² m^n/(1 − 2n), c_n = (2n)!/(2^(2n)·n!²), so that
    K − E = pi/2·sum c_n² m^n·2n/(2n − 1) (truncation < 1e-16 after 25 terms);
    m >= 0.1: the A&S 17.3.34/17.3.36 polynomials (absolute error <= 2e-8).
    """
    if m < 0.1:
        c2 = 1.0
        mn = 1.0
        ks = 1.0
        es = 1.0
        ds = 0.0
        for n in range(1, 26):
            c = (2.0 * n - 1.0) / (2.0 * n)
            c2 *= c * c
            mn *= m
            t = c2 * mn
            ks += t
            es += t / (1.0 - 2.0 * n)
            ds += t * 2.0 * n / (2.0 * n - 1.0)
        h = 0.5 * math.pi
        return h * ks, h * es, h * ds
    m1 = 1.0 - m
    kk = ellipk_m1(m1)
    ek = ellipe_m1(m1)
    return kk, ek, kk - ek


@njit(cache=True)
def ellipticity(ratio):
    """Exact ellipticity k = a/b >= 1 and E(m), K(m) for the radius ratio rho = R_major/R_minor >= 1.

    Solves rho = (k²E − K)/(K − E) = (m·K − (K − E)) / ((1 − m)(K − E)), m = 1 − 1/k², by Newton's
    method in m, started from the Hamrock–Brewe k ≈ 1.0339·rho^0.636 (k ≈ rho^(2/pi) near 1
   ), with the derivatives dK/dm = (E − (1 − m)K)/(2m(1 − m)), dE/dm = −(K − E)/(2m).
    Returns (k, E, K). For rho <= 1 + 1e-12 the contact is circular: (1, pi/2, pi/2).
    """
    if ratio <= 1.0 + 1e-12:
        return 1.0, 0.5 * math.pi, 0.5 * math.pi
    k0 = 1.0339 * ratio ** 0.636
    if k0 < 1.05:
        k0 = ratio ** (2.0 / math.pi)     # near-circular: k ≈ rho^(2/pi)
    m = 1.0 - 1.0 / (k0 * k0)
    kk, ek, d = _elliptic_kde(m)
    for _ in range(40):
        kk, ek, d = _elliptic_kde(m)
        m1 = 1.0 - m
        num = m * kk - d                  # = E − (1 − m)K = (1 − m)(k²E − K)
        den = m1 * d
        f = num / den - ratio
        dk_dm = num / (2.0 * m * m1)
        dd_dm = dk_dm + d / (2.0 * m)     # d(K − E)/dm
        dnum = kk + m * dk_dm - dd_dm
        dden = -d + m1 * dd_dm
        df = (dnum * den - num * dden) / (den * den)
        mnew = m - f / df
        if mnew <= 0.0:
            mnew = 0.5 * m
        elif mnew >= 1.0:
            mnew = 0.5 * (m + 1.0)
        if abs(mnew - m) <= 1e-15 + 1e-13 * (1.0 - m):
            m = mnew
            break
        m = mnew
    kk, ek, d = _elliptic_kde(m)
    return 1.0 / math.sqrt(1.0 - m), ek, kk


@njit(cache=True)
def _axes_ratio(Rx, Ry):
    """rho = R_major/R_minor >= 1 and the reduced radius R = 1/(1/Rx + 1/Ry)."""
    R = 1.0 / (1.0 / Rx + 1.0 / Ry)
    if Ry >= Rx:
        return Ry / Rx, R
    return Rx / Ry, R


@njit(cache=True)
def hertz_point_contact(Rx, Ry, E_eff, Q):
    """Hertz contact ellipse for load Q (exact ellipticity, A&S elliptic integrals).

    Returns (a, b, p0, delta): semi-major axis a (along y, the groove, when Ry > Rx), semi-minor
    axis b (rolling direction), maximum pressure p0 = 3Q/(2·pi·a·b) and the approach delta, in
    m, m, Pa, m. Equations in the module docstring (Johnson 1985 §4.2; Hamrock & Brewe 1983).
    Q <= 0 gives zeros.
    """
    if Q <= 0.0:
        return 0.0, 0.0, 0.0, 0.0
    rho, R = _axes_ratio(Rx, Ry)
    k, ek, kk = ellipticity(rho)
    b = (6.0 * ek * Q * R / (math.pi * k * E_eff)) ** (1.0 / 3.0)
    a = k * b
    p0 = 3.0 * Q / (2.0 * math.pi * a * b)
    delta = kk * (4.5 / (ek * R) * (Q / (math.pi * k * E_eff)) ** 2) ** (1.0 / 3.0)
    return a, b, p0, delta


@njit(cache=True, inline="always")
def hertz_load(K, delta):
    """Hertz point-contact load Q = K·delta^1.5, N (K the contact's constant, N/m^1.5; delta the
    approach, m; Harris & Kotzalas, Essential Concepts of Bearing Technology, 2007, §6.3). The
    race contacts of the dynamics (flexbearing.multibody.race_kernels) take their elastic load from it."""
    return K * delta * math.sqrt(delta)


@njit(cache=True)
def hertz_potential(K, delta):
    """Elastic energy of a Hertz point contact, J: V = ∫ K·d^1.5 dd = (2/5)·K·delta^2.5 (the
    potential of `hertz_load`; flexbearing.multibody.energy)."""
    return 0.4 * K * delta ** 2.5


@njit(cache=True)
def hertz_stiffness(Rx, Ry, E_eff):
    """Load–deflection constant K_H of Q = K_H·delta^1.5, N/m^1.5 (exact ellipticity).

    K_H = pi·k·E'·sqrt(2·E(m)·R / (9·K(m)³)) (Hamrock & Brewe 1983 with exact k, E, K).
    """
    rho, R = _axes_ratio(Rx, Ry)
    k, ek, kk = ellipticity(rho)
    return math.pi * k * E_eff * math.sqrt(2.0 * ek * R / (9.0 * kk ** 3))


@njit(cache=True)
def hertz_from_approach(Rx, Ry, E_eff, delta):
    """Load and ellipse for a given approach delta (what the dynamics knows).

    Q = K_H·delta^1.5, then a, b, p0 as in `hertz_point_contact`. Returns (Q, a, b, p0);
    delta <= 0 (no contact) gives zeros.
    """
    if delta <= 0.0:
        return 0.0, 0.0, 0.0, 0.0
    rho, R = _axes_ratio(Rx, Ry)
    k, ek, kk = ellipticity(rho)
    kh = math.pi * k * E_eff * math.sqrt(2.0 * ek * R / (9.0 * kk ** 3))
    Q = kh * delta * math.sqrt(delta)
    b = (6.0 * ek * Q * R / (math.pi * k * E_eff)) ** (1.0 / 3.0)
    a = k * b
    p0 = 3.0 * Q / (2.0 * math.pi * a * b)
    return Q, a, b, p0


# ---------------------------------------------------------------- Hamrock–Brewe approximations
@njit(cache=True)
def _hb_kef(Rx, Ry):
    rho, R = _axes_ratio(Rx, Ry)
    k = 1.0339 * rho ** 0.636
    ek = 1.0003 + 0.5968 / rho
    kk = 1.5277 + 0.6023 * math.log(rho)
    return k, ek, kk, R


@njit(cache=True)
def hertz_point_contact_hb(Rx, Ry, E_eff, Q):
    """Hertz ellipse with the Hamrock–Brewe (1983) approximations (a, b, p0, delta).

    k ≈ 1.0339·(Ry/Rx)^0.636, E ≈ 1.0003 + 0.5968·Rx/Ry, K ≈ 1.5277 + 0.6023·ln(Ry/Rx);
    a = (6k²EQR/(pi·E'))^(1/3), b = (6EQR/(pi·k·E'))^(1/3), p0 = 3Q/(2·pi·a·b),
    delta = K·[(9/(2ER))·(Q/(pi·k·E'))²]^(1/3). A few per cent off the exact solution.
    """
    if Q <= 0.0:
        return 0.0, 0.0, 0.0, 0.0
    k, ek, kk, R = _hb_kef(Rx, Ry)
    a = (6.0 * k * k * ek * Q * R / (math.pi * E_eff)) ** (1.0 / 3.0)
    b = (6.0 * ek * Q * R / (math.pi * k * E_eff)) ** (1.0 / 3.0)
    p0 = 3.0 * Q / (2.0 * math.pi * a * b)
    delta = kk * (4.5 / (ek * R) * (Q / (math.pi * k * E_eff)) ** 2) ** (1.0 / 3.0)
    return a, b, p0, delta


@njit(cache=True)
def hertz_stiffness_hb(Rx, Ry, E_eff):
    """K_H = pi·k·E'·sqrt(2ER/(9K³)) with the Hamrock–Brewe k, E, K (1983)."""
    k, ek, kk, R = _hb_kef(Rx, Ry)
    return math.pi * k * E_eff * math.sqrt(2.0 * ek * R / (9.0 * kk ** 3))


# ---------------------------------------------------------------- exact reference (scipy)
def hertz_exact(Rx, Ry, E_eff, Q):
    """Reference Hertz solution with scipy's complete elliptic integrals (not compiled).

    Solves (k²E(m) − K(m))/(K(m) − E(m)) = R_major/R_minor for k with brentq, m = 1 − 1/k²
    (scipy.special.ellipk/ellipe take the parameter m = e², not the modulus e), then a, b, p0,
    delta as in the module docstring. Returns a dict with k, E, K, a, b, p0, delta, stiffness.
    """
    from scipy.optimize import brentq
    from scipy.special import ellipe, ellipk

    rho = max(Ry / Rx, Rx / Ry)
    R = 1.0 / (1.0 / Rx + 1.0 / Ry)
    if rho <= 1.0 + 1e-12:
        k = 1.0
    else:
        def g(kv):
            m = 1.0 - 1.0 / kv ** 2
            K, E = ellipk(m), ellipe(m)
            return (kv * kv * E - K) / (K - E) - rho
        k = brentq(g, 1.0 + 1e-8, 10.0 * rho + 10.0, xtol=1e-15, rtol=1e-15, maxiter=500)
    m = 1.0 - 1.0 / k ** 2
    K, E = float(ellipk(m)), float(ellipe(m))
    b = (6.0 * E * Q * R / (math.pi * k * E_eff)) ** (1.0 / 3.0)
    a = k * b
    p0 = 3.0 * Q / (2.0 * math.pi * a * b)
    delta = K * (4.5 / (E * R) * (Q / (math.pi * k * E_eff)) ** 2) ** (1.0 / 3.0)
    stiffness = math.pi * k * E_eff * math.sqrt(2.0 * E * R / (9.0 * K ** 3))
    return {"k": k, "E": E, "K": K, "a": a, "b": b, "p0": p0, "delta": delta, "stiffness": stiffness}
