"""EHL traction between a ball and a race: the 4106-oil traction curve and its slice integration.

Traction curve (Wang, Yang & Wang, Tribology 24(2):156, 2004, the seed paper's ref. 25; signs of
the exponents reconstructed in reference/formulas.md):

    mu(s) = (A + B·|s|)·exp(−C·|s|) + D,   mu(−s) = −mu(s),   s = du/UR,  UR = (u_ball + u_race)/2,

    A = a0·Qb^a1·Ub^a2·Tb^a3   (same for B, C, D; exponents in TRACTION_FIT_4106)
    Qb = Q/(E'·Rx²),  Ub = eta0·UR/(E'·Rx),  Tb = eta0·K0·T0/(E'·Rx)²,

with Rx the rolling-direction effective radius, T0 the oil temperature (K), K0 the oil thermal
conductivity and eta0 the viscosity "at atmospheric pressure and ambient temperature" (paper
§2.2.2). The fit is only meaningful with eta0 at ambient (the 0.055 Pa·s of the paper preset): the
formulas.md check (A −0.0204, ... at 373 K) uses eta0 = 0.055 Pa·s; with the 100 °C viscosity
(4.4 mPa·s) the same fit returns mu ≈ 0.79, which is physically wrong. Near s = 0 the fitted curve
dips slightly below zero (A + D < 0 for some conditions); those values are clipped to zero.

Slice integration (seed paper §2.2.2, eqs for T_m, after Xie et al., its ref. 10): the ellipse
(semi-major axis a along y, the groove direction) is cut into n equal-width slices along y; slice m
carries the Hertz load share

    Q_m = Q·[F(eta_hi) − F(eta_lo)],  F(eta) = (3·eta − eta³)/4,  eta = y/a,

obtained by integrating p = p0·sqrt(1 − x²/b² − y²/a²) over x (line load (3Q/4a)(1 − y²/a²));
the shares sum to 1 exactly. The sliding velocity varies across the ellipse because of the spin of
the ball relative to the race (linear in y) and the curvature of the contact surface across the
groove (quadratic in y); the caller passes it as du(y) = du0 + du1·y + du2·y² (use
`slip_polynomial_from_three_points` if it evaluates du at y = −a, 0, +a). Each slice uses
mu(du(y_m)/UR) at its centre y_m, and

    T_x = sum_m Q_m·mu_m,   M_z = −sum_m y_m·T_xm   (moment about the contact normal z, x × y = z).

Option `transverse` (off by default, as the paper takes T_eta = 0): with a transverse sliding
velocity dv (uniform across the slices) the slice's slip vector (du, dv)/UR gets mu(|s|) along it,
giving T_y = sum Q_m·mu_m·dv/|dvec| and the T_y part of the moment is zero (slices centred on x = 0).

Sign convention: du, dv = race surface velocity minus ball surface velocity at the contact; the
returned forces act on the ball (positive along +du). The race receives the opposite.

Bounded law (option; `bounded_traction_table`, TRACTION_BOUNDED_4106). The fit is a regression of
ball-on-disc traction curves; its plateau D ∝ Qb^0.74 is a power law, and at the slip-rate test's
light contacts (inner race 85–190 N, p0 0.50–0.70 GPa; outer 200–1200 N, 0.62–1.1 GPa) it gives
curve maxima of only 0.002–0.005 (inner) and 0.006–0.011 (outer) (benchmarks/results/slip_rate.md,
"fit at the test's contacts"). EHL traction of ester-class turbine oils at these pressures is of
the order of a few hundredths (qualitative sources: the EHL friction curve rises linearly with the
slide–roll ratio, reaches a plateau set by the lubricant's limiting shear stress tau_L and falls
by shear heating at larger slip, MDPI Lubricants 13(11):485, 2025, §3.3–3.4 and conclusions; the
maximum traction is set by tau_L(p, T), Bair & Winer, J. Lubr. Technol. 101(3):251, 1979; traction
grows with contact pressure and falls with surface speed, Loewenthal & Rohn, NASA TP-2154, 1983).
No numerical traction curve of 4106/MIL-L-23699 oil was retrievable here, so the bound is built
from the fit itself and is NOT checked against a published number:

    mu_b(s; Q, UR, T) = k·mu_fit(s; max(Qb, Qb_min), clamp(Ub, Ub_min, Ub_max), Tb),
    k = min(1, mu_lim / max_s mu_fit(s; ...)),

i.e. the fit is evaluated without extrapolating its power laws below the smallest dimensionless
load Qb_min (below it the curve of Qb_min is used: traction coefficient independent of load, as
the limiting-shear picture tau_L = Lambda·p gives mu = Lambda for every load), and the whole curve
is scaled down if its peak exceeds mu_lim = tau_L/p (limiting shear stress proportional to
pressure, Bair & Winer 1979). QB_MIN_4106 = 2.4e-5 is the Qb of an inner-race contact of the paper
bearing at p0 ≈ 1.0 GPa (alpha 40°, Rx = 9.9 mm: Q = 542 N, p0 = 1.01 GPa): an ASSUMED lower end of the fit's data (ball-on-disc
traction rigs run at p0 >= 1 GPa; the original data range of Wang, Yang & Wang 2004 is not known
here). MU_LIMIT_4106 = 0.06 (assumed Lambda) is inactive at the test's conditions. Inside its range the
bounded law is the fit exactly; the paper's fit stays the default of the dynamics
(model.traction_table = TRACTION_FIT_4106).

Origin law (option; TRACTION_ORIGIN_4106, `traction_law = "origin"` in coupling.validate). The
fit's intercept mu(0+) = A + D is a regression residual, not physics: a lubricated contact carries
no traction without sliding, and the EHL traction curve starts linearly from the origin (Johnson &
Tevaarwerk, Proc. R. Soc. A 356:215, 1977: the linear/viscoelastic region of the traction curve).
At the slip-rate test's light contacts (80–250 N) the fit extrapolates to A + D < 0, |A|/D up to
1.4, i.e. mu = 0 (clipped) for every slip below a few per cent (measured: outer contact of test case 1,
Q 205 N, UR 18.6 m/s: A/D = −1.42, mu = 0 up to s = 0.035): a dead zone in which neither
spin nor transverse creep produces any traction. The origin law keeps the fit's B, C, D and sets
A = −D:

    mu(s) = D·(1 − exp(−C·s)) + B·s·exp(−C·s),   mu(0) = 0,   mu'(0) = B + C·D,   mu(inf) = D,

which differs from the fit only where exp(−C·s) matters (the fit's C = 5–7: s below ~0.5), and is
odd in s like the fit. Stored as a 6-row table with no data-range clamp and no cap, flag
table[5, 1] = 1.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

# Wang, Yang & Wang (2004) fit for 4106 oil: rows A, B, C, D; columns (factor, exponent of Qb,
# exponent of Ub, exponent of Tb). Replace this table (same shape) to use another oil.
TRACTION_FIT_4106 = np.array([
    [-2.7968e-15, 0.5796, -0.5551, -0.5498],   # A
    [1.6581e-28, 0.5687, -0.3537, -1.3936],    # B
    [3.8718e-18, 0.2928, -0.5124, -0.8009],    # C
    [2.2910e-20, 0.7423, -0.6713, -0.8022],    # D
])


def bounded_traction_table(qb_range, ub_range, mu_limit, fit=TRACTION_FIT_4106) -> np.ndarray:
    """The 6-row table of the bounded law (module docstring "Bounded law"): the fit's rows A..D,
    row 4 = (Qb_min, Qb_max, Ub_min, Ub_max), row 5 = (mu_lim, 0, 0, 0)."""
    tab = np.zeros((6, 4))
    tab[:4] = fit
    tab[4] = (qb_range[0], qb_range[1], ub_range[0], ub_range[1])
    tab[5, 0] = mu_limit
    return tab


# bounded law for 4106 oil (module docstring "Bounded law"): Qb clamped from below at QB_MIN_4106,
# Ub not clamped, plateau capped at MU_LIMIT_4106
QB_MIN_4106 = 2.4e-5
MU_LIMIT_4106 = 0.06
TRACTION_BOUNDED_4106 = bounded_traction_table((QB_MIN_4106, 1.0), (0.0, 1.0), MU_LIMIT_4106)

# origin law for 4106 oil (module docstring "Origin law"): the fit with A = −D, no clamping, no cap
TRACTION_ORIGIN_4106 = bounded_traction_table((0.0, math.inf), (0.0, math.inf), 0.0)
TRACTION_ORIGIN_4106[5, 1] = 1.0


@njit(cache=True)
def traction_curve_maximum(A, B, C, D):
    """max over s >= 0 of mu(s) = (A + B·s)·exp(−C·s) + D (unclipped; B, C > 0): the stationary point
    d mu/ds = (B − C·(A + B·s))·exp(−C·s) = 0 at s* = 1/C − A/B if s* > 0, else the larger of
    mu(0) = A + D and the plateau mu(inf) = D."""
    best = max(A + D, D)
    if B > 0.0 and C > 0.0:
        s = 1.0 / C - A / B
        if s > 0.0:
            v = (A + B * s) * math.exp(-C * s) + D
            if v > best:
                best = v
    return best


@njit(cache=True)
def traction_coefficients_table(Q, u_rolling, Rx, E_eff, eta0, temperature_k, thermal_conductivity, table):
    """(A, B, C, D) of the traction curve from a coefficient table (rows A..D: factor, Qb, Ub, Tb
    exponents). Qb = Q/(E'Rx²), Ub = eta0·UR/(E'Rx), Tb = eta0·K0·T0/(E'Rx)² (module docstring).

    A table of 6 rows is the bounded law (`bounded_traction_table`, module docstring "Bounded
    law"): row 4 = (Qb_min, Qb_max, Ub_min, Ub_max), the fit's data range, into which Qb and Ub are
    clamped before the power laws are evaluated (no extrapolation); row 5 = (mu_lim, 0, 0, 0), the
    limiting-shear traction coefficient tau_L/p: if the curve's maximum exceeds mu_lim, A, B, D are
    scaled by mu_lim/max (the curve keeps its shape, its peak is tau_L/p). A 4-row table is the
    paper's fit unchanged."""
    if Q <= 0.0 or u_rolling == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    er = E_eff * Rx
    qb = Q / (er * Rx)
    ub = eta0 * abs(u_rolling) / er
    tb = eta0 * thermal_conductivity * temperature_k / (er * er)
    bounded = table.shape[0] >= 6
    if bounded:
        qb = min(max(qb, table[4, 0]), table[4, 1])
        ub = min(max(ub, table[4, 2]), table[4, 3])
    lq = math.log(qb)
    lu = math.log(ub)
    lt = math.log(tb)
    a = table[0, 0] * math.exp(table[0, 1] * lq + table[0, 2] * lu + table[0, 3] * lt)
    b = table[1, 0] * math.exp(table[1, 1] * lq + table[1, 2] * lu + table[1, 3] * lt)
    c = table[2, 0] * math.exp(table[2, 1] * lq + table[2, 2] * lu + table[2, 3] * lt)
    d = table[3, 0] * math.exp(table[3, 1] * lq + table[3, 2] * lu + table[3, 3] * lt)
    if bounded and table[5, 1] > 0.0:
        # "through the origin" option: the regression intercept A + D is replaced by the
        # physical mu(0) = 0 (module docstring, "Origin law")
        a = -d
    if bounded and table[5, 0] > 0.0:
        mx = traction_curve_maximum(a, b, c, d)
        if mx > table[5, 0]:
            f = table[5, 0] / mx
            a *= f
            b *= f
            d *= f
    return a, b, c, d


@njit(cache=True)
def traction_coefficients(Q, u_rolling, Rx, E_eff, eta0, temperature_k, thermal_conductivity):
    """(A, B, C, D) for 4106 oil (Wang, Yang & Wang 2004; TRACTION_FIT_4106).

    Q normal load (N), u_rolling = UR = (u_ball + u_race)/2 (m/s), Rx rolling-direction radius (m),
    E_eff = E' (Pa), eta0 ambient viscosity (Pa·s), temperature_k oil temperature (K),
    thermal_conductivity K0 (W/(m·K)). Zero load or speed gives (0, 0, 0, 0), i.e. no traction.
    """
    return traction_coefficients_table(Q, u_rolling, Rx, E_eff, eta0, temperature_k,
                                       thermal_conductivity, TRACTION_FIT_4106)


@njit(cache=True)
def traction_coefficient(s, A, B, C, D):
    """mu(s) = (A + B·|s|)·exp(−C·|s|) + D, odd in s, negative values near s = 0 clipped to 0."""
    x = abs(s)
    mu = (A + B * x) * math.exp(-C * x) + D
    if mu < 0.0:
        mu = 0.0
    return mu if s >= 0.0 else -mu


@njit(cache=True)
def traction_coefficient_regularised(s, A, B, C, D, s_lin):
    """mu(s) of `traction_coefficient` for |s| >= s_lin, the straight line through the origin and
    mu(s_lin) below it; odd in s. The fit has mu(0+) = A + D != 0 (a jump at s = 0 that makes a
    dynamics right-hand side discontinuous); s_lin = 0 gives the fit itself."""
    x = abs(s)
    if x >= s_lin:
        mu = traction_coefficient(x, A, B, C, D)
    else:
        mu = traction_coefficient(s_lin, A, B, C, D) * x / s_lin
    return mu if s >= 0.0 else -mu


@njit(cache=True)
def slice_load_share(eta_lo, eta_hi):
    """Fraction of the Hertz load between eta = y/a = eta_lo and eta_hi: F(hi) − F(lo),
    F(eta) = (3·eta − eta³)/4 (integral of the elliptical pressure, module docstring)."""
    return 0.25 * ((3.0 * eta_hi - eta_hi ** 3) - (3.0 * eta_lo - eta_lo ** 3))


@njit(cache=True)
def slip_polynomial_from_three_points(a, du_minus, du_centre, du_plus):
    """(du0, du1, du2) of du(y) = du0 + du1·y + du2·y² through du(−a), du(0), du(+a)."""
    du1 = (du_plus - du_minus) / (2.0 * a)
    du2 = (du_plus + du_minus - 2.0 * du_centre) / (2.0 * a * a)
    return du_centre, du1, du2


@njit(cache=True)
def sliced_traction(Q, a, u_rolling, du0, du1, du2, dv, A, B, C, D, n_slices, transverse, s_lin=0.0):
    """Traction on the ball integrated over n_slices slices along the major axis (module docstring).

    Q normal load (N); a semi-major axis (m); u_rolling = UR (m/s, its magnitude is used);
    du(y) = du0 + du1·y + du2·y² the rolling-direction sliding velocity race − ball (m/s);
    dv transverse sliding velocity (m/s, used only if transverse); A..D traction coefficients;
    n_slices >= 1; s_lin: regularisation of the curve at small slip (`traction_coefficient_regularised`,
    0 = none). Returns (T_x, T_y, M_z): rolling-direction traction (N), transverse traction
    (N, 0 unless transverse), and moment about the contact normal (N·m), all acting on the ball.
    A uniform slip (du1 = du2 = 0, dv = 0) gives T_x = Q·mu(du0/UR) exactly for any n.
    """
    if Q <= 0.0 or n_slices < 1:
        return 0.0, 0.0, 0.0
    ur = abs(u_rolling)
    if ur < 1e-12:
        ur = 1e-12
    tx = 0.0
    ty = 0.0
    mz = 0.0
    h = 2.0 / n_slices
    for m in range(n_slices):
        lo = -1.0 + m * h
        hi = lo + h
        qm = Q * slice_load_share(lo, hi)
        y = 0.5 * (lo + hi) * a
        du = du0 + y * (du1 + y * du2)
        if transverse and dv != 0.0:
            sv = math.sqrt(du * du + dv * dv)
            mu = traction_coefficient_regularised(sv / ur, A, B, C, D, s_lin)
            tmx = qm * mu * du / sv
            ty += qm * mu * dv / sv
        else:
            tmx = qm * traction_coefficient_regularised(du / ur, A, B, C, D, s_lin)
        tx += tmx
        mz -= y * tmx
    return tx, ty, mz
