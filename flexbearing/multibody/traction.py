"""EHL traction between a ball and a race: the 4106-oil traction curve and its slice integration.

Traction curve (Wang, Yang & Wang, Tribology 24(2):156, 2004, the seed paper's ref. 25; the
extracted text lost the signs of the exponents: the signs here are the only ones that keep
mu(0) = A + D near zero and give realistic curves on the fit's ball-on-disc range):

    mu(s) = (A + B·|s|)·exp(−C·|s|) + D,   mu(−s) = −mu(s),   s = du/UR,  UR = (u_ball + u_race)/2,

    A = a0·Qb^a1·Ub^a2·Tb^a3   (same for B, C, D; exponents in TRACTION_FIT_4106)
    Qb = Q/(E'·Rx²),  Ub = eta0·UR/(E'·Rx),  Tb = eta0·K0·T0/(E'·Rx)²,

with Rx the rolling-direction effective radius, T0 the oil temperature (K), K0 the oil thermal
conductivity and eta0 the viscosity "at atmospheric pressure and ambient temperature" (paper
§2.2.2). The fit is only meaningful with eta0 at ambient (the 0.055 Pa·s of the paper preset): the
check (inner contact, Q 3 kN, 10,000 rpm, UR 43.1 m/s, 373 K: A −0.0204, B 0.0698, C 6.23,
D 0.0192) uses eta0 = 0.055 Pa·s; with the 100 °C viscosity
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

Low rolling speed (model option slip_regularisation_speed = u_reg, default 10 m/s). The
dynamics evaluate the fit at the effective rolling speed UR_eff = max(|UR|, u_reg):

    mu = mu(du/UR_eff; A..D at Ub(UR_eff)),   UR_eff = max(|UR|, u_reg),

identical to the fit wherever |UR| >= u_reg (the paper's scenes: UR 40–60 m/s at 10,000–14,000
rpm). Why: the fit's creep slope grows without bound as UR -> 0. Near s = 0 (the linear part below
s_lin) dT/d(du) = Q·mu(s_lin)/(s_lin·UR) with mu ~ A + D ∝ Ub^−0.56…−0.67 (TRACTION_FIT_4106), i.e.
dT/d(du) ∝ UR^−1.67: a ball's spin relaxes at a rate ∝ that slope, and an explicit integrator must
resolve it (measured: 0.6 s at rest would take ~7e7 steps, 5 ms at 0 rpm 576,000 steps against 816
at 14,000 rpm). Below u_reg the traction is a function of the sliding speed alone, mu(du/u_reg) at
the curve of Ub(u_reg) — the velocity-regularised friction law of multibody simulation (friction
as a steep but finite function of the sliding speed through zero; Haessig & Friedland, J. Dyn.
Syst. Meas. Control 113(3):354, 1991), its velocity scale u_reg·s* (s* ~ 0.1 at the curve's
maximum, i.e. ~1 m/s of sliding to full traction). The fit itself is a regression of ball-on-disc
traction curves measured at rolling speeds of metres per second (its data range is not known here,
see "Bounded law"), so below u_reg its power laws in Ub are an extrapolation in any case; holding
Ub at its value at u_reg is the same clamp of Ub as the bounded law's. What it changes: at rolling
speeds below u_reg (start-up, below ~2,300 rpm on the paper bearing) a sliding ball meets less
traction than the extrapolated fit gives (the fit's plateau D ∝ UR^−0.67 would grow 7.5x from 10
to 0.5 m/s). The EHL film-shear law (below) is unchanged: it uses UR >= model.min_rolling_speed.
Test: tests/test_traction_low_speed.py.

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

Origin law (option; TRACTION_ORIGIN_4106, `traction_law = "origin"` in flexbearing.studies.validation.slip_rate). The
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

EHL film-shear law (model option traction_law = "ehl"; `sliced_traction_ehl`). The fit
and its variants above have no creep stiffness at the slip-rate test's light contacts (a dead zone
up to s = 0.03–0.09); this law computes the traction from the shear of the oil film instead, at
every load, with the physics of the EHL traction curve (Johnson & Tevaarwerk, Proc. R. Soc. A
356:215, 1977; Evans & Johnson, Proc. IMechE C 200(5):313, 1986; Bair & Winer, J. Lubr. Technol.
101(3):251, 1979). Each slice m of the ellipse (the same slices and load shares as above) is a strip
along the rolling direction with centre-line pressure p_c = p0·sqrt(1 − eta_m²), half-length
b_m = b·sqrt(1 − eta_m²), mean pressure (pi/4)·p_c, transit time t_m = 2·b_m/U; the film has the
Hamrock–Dowson central thickness h (flexbearing.multibody.film) and shear rate v/h at the slice's sliding
speed v. The strip-mean shear stress:

    Newtonian -> Eyring:  tau_E = tau0·asinh(Y),  Y = X_g·(1 + (R − 1)/sqrt(1 + X_g²)),
                          X_g = eta_g·v/(h·tau0),  eta_g = eta_in·exp(alpha·(pi/4)·p_c),
                          R = eta_a/eta_g,  eta_a = eta_in·barus_strip_mean(alpha·p_c)
      (the Barus viscosity averaged along the strip: arithmetic mean eta_a where the shear is
      Newtonian, tau linear in eta; geometric mean eta_g where it is Eyring, tau linear in ln eta;
      Y interpolates, exact in both limits)
    thermal:              tau_T = tau_E/(1 + beta_T·c_th·v·tau0·Y/sqrt(1 + Y²)),
                          c_th = h/(12·k_oil) + 0.532·sqrt(2·kappa_s·b_m/U)/k_s
      (ln eta linear in T with the oil's viscosity–temperature coefficient beta_T, linearised about
      the isothermal stress: d tau/d ln eta = tau0·tanh(tau_E/tau0); temperature rise c_th·tau·v:
      the film's mean rise for uniform dissipation and the mean flash temperature of both solids,
      Jaeger's band source at Peclet >> 1 with half the heat into each; Evans & Johnson's thermal
      Eyring regime, which makes the curve fall at large slip)
    limiting shear:       tau_f = tau_L·(1 − exp(−tau_T/tau_L)),  tau_L = gamma_L·(pi/4)·p_c
      (Bair & Winer's limiting-shear law in steady shear, tau_L proportional to pressure)
    Maxwell element:      tau_mean = tau_f·(1 − (1 − exp(−x))/x),  x = G·(v/h)·t_m/tau_f
      (Johnson & Tevaarwerk's viscoelastic film, stress rising from zero at the inlet, with the
      non-linear dashpot replaced by its secant viscosity tau_f/(v/h): exact for a linear Maxwell
      fluid, the elastic limit tau_mean = G·v·t_m/(2h) for x -> 0, the steady flow stress for
      x -> inf; within 15 % of the integrated Johnson–Tevaarwerk equation in between,
      tests/test_traction_ehl.py)

and mu_m = tau_mean/((pi/4)·p_c), the slice force mu_m·Q_m along its slip vector (transverse
option as above). Below s_lin = model.traction_slip_linear the line through the origin and
mu(s_lin) is used (the same numerical regularisation as the fit). Properties: mu(0) = 0, slope at
s = 0 the Newtonian–Maxwell U·eta_a·(1 − De·(1 − exp(−1/De)))/(h·p_mean), De = eta_a·U/(G·2·b_m),
mu <= gamma_L·scale; rising monotonically to a maximum at s >= 1e-3, then falling by shear heating.

Parameters for a MIL-L-23699 / type II (pentaerythritol) ester such as 4106. No numerical traction
curve or rheological constants of a MIL-L-23699 oil could be retrieved here (only abstracts of
the papers above), so the values are the middle of the ranges those sources give for synthetic
esters and mineral oils at 0.5–2 GPa, and their ranges are declared (EHL_RANGES) for the
uncertainty study of the slip-rate validation: Eyring stress tau0 = 4 MPa (2–10 MPa, Johnson &
Tevaarwerk 1977, Evans & Johnson 1986), limiting-shear coefficient gamma_L = 0.06 (0.03–0.10, Bair
& Winer 1979), film shear modulus G = 1 GPa (0.1–3 GPa, Johnson & Tevaarwerk 1977), bearing steel
k_s = 40 W/(m·K), kappa_s = 1.1e-5 m²/s. The oil's own data come from flexbearing.multibody.bearing.Oil
(paper Table 7): the inlet viscosity at the oil temperature, alpha_p = 1.85e-8 1/Pa (Barus),
beta_T, k_oil. The level is checked against the paper's 4106 fit inside its data range (the
maxima agree within a factor 1.8, tests/test_traction_ehl.py) — the one published traction
curve of this oil available. Two scalars carry the uncertainty the validation's study samples:
traction_scale (0.5–2) multiplies tau0 and gamma_L, contact_temperature_rise (0–60 K) lowers the
inlet viscosity (the contacts run hotter than the supplied oil). Table layout: `ehl_traction_table`;
the parameters the law runs with, taken once from it: `ehl_parameters` (the model's slots P_EHL_*).
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit
from flexbearing.common.validation import require_range
from flexbearing.multibody.model_layout import (
    P_ETA0, P_EHL_TAU0, P_EHL_GAMMA_L, P_EHL_SHEAR_MODULUS, P_EHL_K_SOLID, P_EHL_KAPPA_SOLID, P_EHL_BETA_T,
    P_EHL_ETA_INLET,
)

# The fit's coefficient table, by name beside the names (`traction_coefficients_table`): rows A, B,
# C, D of the curve's coefficients, each (factor, exponent of Qb, exponent of Ub, exponent of Tb);
# the bounded and origin laws (`bounded_traction_table`) add the row of the fit's data range
# (Qb_min, Qb_max, Ub_min, Ub_max) and the row of the limit (mu_lim, through the origin: 1 or 0).
FIT_ROWS = ("A", "B", "C", "D", "data_range", "limit")
FIT_ROW_A, FIT_ROW_B, FIT_ROW_C, FIT_ROW_D, FIT_ROW_RANGE, FIT_ROW_LIMIT = (FIT_ROWS.index(r) for r in FIT_ROWS)
FIT_COLUMNS = ("factor", "qb_exponent", "ub_exponent", "tb_exponent")        # rows A..D
FIT_C_FACTOR, FIT_C_QB, FIT_C_UB, FIT_C_TB = (FIT_COLUMNS.index(c) for c in FIT_COLUMNS)
FIT_RANGE_COLUMNS = ("qb_min", "qb_max", "ub_min", "ub_max")                 # row FIT_ROW_RANGE
FIT_C_QB_MIN, FIT_C_QB_MAX, FIT_C_UB_MIN, FIT_C_UB_MAX = (FIT_RANGE_COLUMNS.index(c) for c in FIT_RANGE_COLUMNS)
FIT_LIMIT_COLUMNS = ("mu_limit", "through_origin")                           # row FIT_ROW_LIMIT
FIT_C_MU_LIMIT, FIT_C_ORIGIN = (FIT_LIMIT_COLUMNS.index(c) for c in FIT_LIMIT_COLUMNS)
FIT_TABLE_ROWS = FIT_ROW_D + 1              # the fit alone (TRACTION_FIT_4106)
BOUNDED_TABLE_ROWS = len(FIT_ROWS)          # the bounded and origin laws

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
    row FIT_ROW_RANGE = (Qb_min, Qb_max, Ub_min, Ub_max), row FIT_ROW_LIMIT = (mu_lim, 0)."""
    tab = np.zeros((BOUNDED_TABLE_ROWS, len(FIT_COLUMNS)))
    tab[:FIT_TABLE_ROWS] = fit
    tab[FIT_ROW_RANGE, [FIT_C_QB_MIN, FIT_C_QB_MAX, FIT_C_UB_MIN, FIT_C_UB_MAX]] = (qb_range[0], qb_range[1],
                                                                                  ub_range[0], ub_range[1])
    tab[FIT_ROW_LIMIT, FIT_C_MU_LIMIT] = mu_limit
    return tab


# bounded law for 4106 oil (module docstring "Bounded law"): Qb clamped from below at QB_MIN_4106,
# Ub not clamped, plateau capped at MU_LIMIT_4106
QB_MIN_4106 = 2.4e-5
MU_LIMIT_4106 = 0.06
TRACTION_BOUNDED_4106 = bounded_traction_table((QB_MIN_4106, 1.0), (0.0, 1.0), MU_LIMIT_4106)

# origin law for 4106 oil (module docstring "Origin law"): the fit with A = −D, no clamping, no cap
TRACTION_ORIGIN_4106 = bounded_traction_table((0.0, math.inf), (0.0, math.inf), 0.0)
TRACTION_ORIGIN_4106[FIT_ROW_LIMIT, FIT_C_ORIGIN] = 1.0


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


@njit(cache=True, inline="always")
def _fit_power_law(table, row, lq, lu, lt):
    """Coefficient `row` (FIT_ROW_A..D) of the fit: factor·Qb^a1·Ub^a2·Tb^a3 from ln Qb, ln Ub, ln Tb."""
    return table[row, FIT_C_FACTOR] * math.exp(table[row, FIT_C_QB] * lq + table[row, FIT_C_UB] * lu
                                               + table[row, FIT_C_TB] * lt)


@njit(cache=True)
def traction_coefficients_table(Q, u_rolling, Rx, E_eff, eta0, temperature_k, thermal_conductivity, table):
    """(A, B, C, D) of the traction curve from a coefficient table (rows FIT_ROW_A..D: factor, Qb,
    Ub, Tb exponents). Qb = Q/(E'Rx²), Ub = eta0·UR/(E'Rx), Tb = eta0·K0·T0/(E'Rx)² (module docstring).

    A table of BOUNDED_TABLE_ROWS (6) rows is the bounded law (`bounded_traction_table`, module
    docstring "Bounded law"): row FIT_ROW_RANGE = (Qb_min, Qb_max, Ub_min, Ub_max), the fit's data
    range, into which Qb and Ub are clamped before the power laws are evaluated (no extrapolation);
    row FIT_ROW_LIMIT = (mu_lim, through the origin): mu_lim the limiting-shear traction coefficient
    tau_L/p: if the curve's maximum exceeds mu_lim, A, B, D are scaled by mu_lim/max (the curve keeps
    its shape, its peak is tau_L/p). A 4-row table is the paper's fit unchanged."""
    if Q <= 0.0 or u_rolling == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    er = E_eff * Rx
    qb = Q / (er * Rx)
    ub = eta0 * abs(u_rolling) / er
    tb = eta0 * thermal_conductivity * temperature_k / (er * er)
    bounded = table.shape[0] >= BOUNDED_TABLE_ROWS
    if bounded:
        qb = min(max(qb, table[FIT_ROW_RANGE, FIT_C_QB_MIN]), table[FIT_ROW_RANGE, FIT_C_QB_MAX])
        ub = min(max(ub, table[FIT_ROW_RANGE, FIT_C_UB_MIN]), table[FIT_ROW_RANGE, FIT_C_UB_MAX])
    lq = math.log(qb)
    lu = math.log(ub)
    lt = math.log(tb)
    a = _fit_power_law(table, FIT_ROW_A, lq, lu, lt)
    b = _fit_power_law(table, FIT_ROW_B, lq, lu, lt)
    c = _fit_power_law(table, FIT_ROW_C, lq, lu, lt)
    d = _fit_power_law(table, FIT_ROW_D, lq, lu, lt)
    if bounded and table[FIT_ROW_LIMIT, FIT_C_ORIGIN] > 0.0:
        # "through the origin" option: the regression intercept A + D is replaced by the
        # physical mu(0) = 0 (module docstring, "Origin law")
        a = -d
    if bounded and table[FIT_ROW_LIMIT, FIT_C_MU_LIMIT] > 0.0:
        mx = traction_curve_maximum(a, b, c, d)
        if mx > table[FIT_ROW_LIMIT, FIT_C_MU_LIMIT]:
            f = table[FIT_ROW_LIMIT, FIT_C_MU_LIMIT] / mx
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
def _slice(m, n_slices, Q, a, du0, du1, du2):
    """(Q_m, eta_m, y_m, du_m) of slice m of n: load share, centre eta = y/a, centre y (m) and the
    sliding velocity du(y_m) there (module docstring, "Slice integration")."""
    hs = 2.0 / n_slices
    lo = -1.0 + m * hs
    eta = lo + 0.5 * hs
    y = eta * a
    return Q * slice_load_share(lo, lo + hs), eta, y, du0 + y * (du1 + y * du2)


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
    # Evaluated as `traction_coefficient_regularised` per slice, with what does not change from
    # slice to slice taken out of the loop (equal to round-off): 1/UR, and the slope
    # mu(s_lin)/s_lin of the linear part (its exp computed once, at the first slice below s_lin,
    # instead of at every such slice); the slice's force along its slip vector is
    # Q_m·mu(|s|)/|s|·(du, dv) with one division.
    inv_ur = 1.0 / ur
    along = transverse and dv != 0.0
    lin_slope = -1.0
    tx = 0.0
    ty = 0.0
    mz = 0.0
    for m in range(n_slices):
        qm, _, y, du = _slice(m, n_slices, Q, a, du0, du1, du2)
        if along:
            sv = math.sqrt(du * du + dv * dv)
        else:
            sv = abs(du)
        x = sv * inv_ur
        if x >= s_lin:
            mu = (A + B * x) * math.exp(-C * x) + D
            if mu < 0.0:
                mu = 0.0
        else:
            if lin_slope < 0.0:
                lin_slope = traction_coefficient(s_lin, A, B, C, D) / s_lin
            mu = lin_slope * x
        if along:
            f = qm * mu / sv
            tmx = f * du
            ty += f * dv
        else:
            tmx = qm * mu if du >= 0.0 else -(qm * mu)
        tx += tmx
        mz -= y * tmx
    return tx, ty, mz


# ================================================================ EHL film-shear law ("ehl")
# Rheological parameters of a MIL-L-23699 / type II (pentaerythritol) ester; module docstring
# "EHL film-shear law" gives the equations, the sources and the reasons for each value and range.
EHL_EYRING_STRESS = 4.0e6          # Pa, tau0
EHL_LIMITING_SHEAR_COEFF = 0.06     # gamma_L = tau_L/p
EHL_SHEAR_MODULUS = 1.0e9           # Pa, G of the film (Maxwell element)
EHL_STEEL_CONDUCTIVITY = 40.0       # W/(m·K), bearing steel
EHL_STEEL_DIFFUSIVITY = 1.1e-5      # m²/s, bearing steel (k/(rho·c) = 40/(7800·460))
# declared ranges (the uncertainty study of the slip-rate validation samples inside them)
EHL_RANGES = {
    "traction_scale": (0.5, 2.0),                # multiplies tau0 and gamma_L (the film's strength)
    "eyring_stress": (2.0e6, 10.0e6),            # Pa
    "limiting_shear_coeff": (0.03, 0.10),
    "shear_modulus": (0.1e9, 3.0e9),             # Pa
    "contact_temperature_rise": (0.0, 60.0),     # K above the oil temperature
}
EHL_TABLE_ROWS = 8
# The EHL law's table (`ehl_traction_table`), by name beside the names: row EHL_ROW_FILM the film's
# shear constants (EHL_FILM_COLUMNS, the names of EHL_RANGES), row EHL_ROW_THERMAL the contact
# temperature's (EHL_THERMAL_COLUMNS); rows 0–5 unused (the fit's tables have 4 or 6 rows,
# `is_ehl_table`). The model reads none of it in its loop: `fill_ehl_parameters` takes the law's
# parameters once into the model's named slots P_EHL_* (flexbearing.multibody.model_layout).
EHL_ROW_FILM, EHL_ROW_THERMAL = 6, 7
EHL_FILM_COLUMNS = ("eyring_stress", "limiting_shear_coeff", "shear_modulus", "traction_scale")
EHL_C_TAU0, EHL_C_GAMMA_L, EHL_C_SHEAR_MODULUS, EHL_C_SCALE = (EHL_FILM_COLUMNS.index(c) for c in EHL_FILM_COLUMNS)
EHL_THERMAL_COLUMNS = ("contact_temperature_rise", "solid_conductivity", "solid_diffusivity",
                       "viscosity_temperature_coeff")
EHL_C_TEMPERATURE_RISE, EHL_C_K_SOLID, EHL_C_KAPPA_SOLID, EHL_C_BETA_T = (EHL_THERMAL_COLUMNS.index(c)
                                                                         for c in EHL_THERMAL_COLUMNS)
TRACTION_LAWS = ("fit", "ehl")      # model option traction_law (flexbearing.multibody.model)


def flash_constants(ball=None, race=None) -> tuple[float, float]:
    """(k, kappa) that the flash term 0.532·sqrt(2·kappa·b/U)/k of `ehl_strip_shear` takes for a ball and
    a race of other materials (flexbearing.common.materials.Thermal; None = bearing steel, the law's
    constants EHL_STEEL_*). Jaeger's band source at Peclet >> 1: a body's surface temperature is
    C·q_i/e_i (e = k/sqrt(kappa), the effusivity); the heat divides so that both surfaces have one
    temperature, q_i = e_i·q/(e_1 + e_2), T = C·q/(e_1 + e_2) (Blok's partition; Jaeger, J. Proc. R.
    Soc. N.S.W. 76 (1942) 203). The steel law's "half the heat into each" is T = C·q/(2·e), so two
    bodies enter as one of effusivity (e_1 + e_2)/2: k = (k_1 + k_2)/2 and kappa = (k/e_mean)².
    Two bodies alike return their own (k, kappa) unchanged (tests/test_traction_ehl.py)."""
    steel = (EHL_STEEL_CONDUCTIVITY, EHL_STEEL_DIFFUSIVITY)
    b = steel if ball is None else (ball.conductivity, ball.diffusivity)
    r = steel if race is None else (race.conductivity, race.diffusivity)
    if b == r:
        return b
    e_mean = 0.5 * (b[0] / math.sqrt(b[1]) + r[0] / math.sqrt(r[1]))
    k = 0.5 * (b[0] + r[0])
    return k, (k / e_mean) ** 2


def ehl_traction_table(viscosity_temperature_coeff: float, traction_scale: float = 1.0,
                       contact_temperature_rise: float = 0.0, eyring_stress: float = EHL_EYRING_STRESS,
                       limiting_shear_coeff: float = EHL_LIMITING_SHEAR_COEFF,
                       shear_modulus: float = EHL_SHEAR_MODULUS, ball_thermal=None,
                       race_thermal=None) -> np.ndarray:
    """The (8, 4) coefficient table of the EHL film-shear law (module docstring): rows 0–5 unused,
    row EHL_ROW_FILM = (tau0 Pa, gamma_L, G Pa, traction_scale), row EHL_ROW_THERMAL = (contact
    temperature rise K, k_solid W/(m·K), kappa_solid m²/s, beta_T 1/K: the oil's viscosity–temperature
    coefficient). Values outside EHL_RANGES are refused (flexbearing.common.validation.require_range
    names the field). ball_thermal, race_thermal (flexbearing.common.materials.Thermal, None =
    bearing steel): the solids of the flash temperature, combined by `flash_constants` (a silicon
    nitride ball). What the law computes from it: `ehl_parameters`."""
    for name, value in (("traction_scale", traction_scale), ("contact_temperature_rise", contact_temperature_rise),
                        ("eyring_stress", eyring_stress), ("limiting_shear_coeff", limiting_shear_coeff),
                        ("shear_modulus", shear_modulus)):
        lo, hi = EHL_RANGES[name]
        require_range(f"traction.{name}", value, lo, hi)
    require_range("oil.viscosity_temperature_coeff", viscosity_temperature_coeff, 0.0, 1.0)
    tab = np.zeros((EHL_TABLE_ROWS, 4))
    tab[EHL_ROW_FILM, [EHL_C_TAU0, EHL_C_GAMMA_L, EHL_C_SHEAR_MODULUS, EHL_C_SCALE]] = (
        eyring_stress, limiting_shear_coeff, shear_modulus, traction_scale)
    k_solid, kappa_solid = flash_constants(ball_thermal, race_thermal)
    tab[EHL_ROW_THERMAL, [EHL_C_TEMPERATURE_RISE, EHL_C_K_SOLID, EHL_C_KAPPA_SOLID, EHL_C_BETA_T]] = (
        contact_temperature_rise, k_solid, kappa_solid, viscosity_temperature_coeff)
    return tab


class EhlParameters(NamedTuple):
    """The EHL film-shear law's parameters as its kernel `sliced_traction_ehl` takes them (SI)."""
    tau0: float            # Eyring stress times the film-strength scale, Pa
    gamma_l: float         # limiting-shear coefficient tau_L/p times the same scale
    shear_modulus: float   # G of the film, Pa
    k_solid: float         # the solids' conductivity in the flash term, W/(m·K)
    kappa_solid: float     # and their diffusivity, m²/s
    beta_t: float          # the oil's viscosity–temperature coefficient, 1/K
    eta_inlet: float       # the inlet viscosity, Pa·s (`ehl_inlet_viscosity`)


def ehl_inlet_viscosity(eta_oil: float, table) -> float:
    """The oil's viscosity at the contact inlet, Pa·s: eta_oil·exp(−beta_T·ΔT) (module docstring,
    "EHL film-shear law"), eta_oil at the oil temperature, ΔT the table's contact temperature rise."""
    return eta_oil * math.exp(-table[EHL_ROW_THERMAL, EHL_C_BETA_T] * table[EHL_ROW_THERMAL, EHL_C_TEMPERATURE_RISE])


def ehl_parameters(table, eta_oil: float) -> EhlParameters:
    """`EhlParameters` of an `ehl_traction_table` for an oil of viscosity eta_oil (Pa·s) at its
    temperature: the film's stresses scaled by traction_scale, the inlet viscosity once
    (`ehl_inlet_viscosity`). The model's slots (`fill_ehl_parameters`) and `ehl_traction_curve`
    both take the law from here."""
    film, thermal = table[EHL_ROW_FILM], table[EHL_ROW_THERMAL]
    scale = float(film[EHL_C_SCALE])
    return EhlParameters(float(film[EHL_C_TAU0] * scale), float(film[EHL_C_GAMMA_L] * scale),
                         float(film[EHL_C_SHEAR_MODULUS]), float(thermal[EHL_C_K_SOLID]),
                         float(thermal[EHL_C_KAPPA_SOLID]), float(thermal[EHL_C_BETA_T]),
                         float(ehl_inlet_viscosity(eta_oil, table)))


# the model's slots of `EhlParameters`, field by field (flexbearing.multibody.model_layout)
EHL_SLOTS = EhlParameters(P_EHL_TAU0, P_EHL_GAMMA_L, P_EHL_SHEAR_MODULUS, P_EHL_K_SOLID, P_EHL_KAPPA_SOLID,
                          P_EHL_BETA_T, P_EHL_ETA_INLET)


def fill_ehl_parameters(p, table=None) -> None:
    """The EHL law's slots P_EHL_* of the model's parameter vector p (flexbearing.multibody.model_layout;
    flexbearing.multibody.model.build_model), once per model: `ehl_parameters` of the
    `ehl_traction_table` at the oil viscosity p[P_ETA0] (constant during a run); None (a fit law)
    sets them to zero."""
    values = ehl_parameters(table, p[P_ETA0]) if table is not None else (0.0,) * len(EHL_SLOTS)
    for slot, value in zip(EHL_SLOTS, values):
        p[slot] = value


def ehl_traction_coefficient_bound(table) -> float:
    """The largest traction coefficient the EHL film-shear law can give: gamma_L·scale (module
    docstring, "EHL film-shear law"). Each slice's mu_m = tau_mean/((pi/4)·p_c) with tau_mean <=
    tau_f (the Maxwell factor 1 − (1 − exp(−x))/x lies in [0, 1)) and tau_f = tau_L·(1 −
    exp(−tau_T/tau_L)) < tau_L = gamma_L·(pi/4)·p_c (Bair & Winer's limiting shear, J. Lubr. Technol.
    101(3):251, 1979); below s_lin the line through the origin stays below mu(s_lin). So every slice,
    and the contact's resultant |(T_x, T_y)| <= sum_m mu_m·Q_m, stays below gamma_L·scale·Q."""
    return float(table[EHL_ROW_FILM, EHL_C_GAMMA_L] * table[EHL_ROW_FILM, EHL_C_SCALE])


def is_ehl_table(table) -> bool:
    """True for a table of the EHL film-shear law (`ehl_traction_table`)."""
    return table.shape[0] == EHL_TABLE_ROWS


@njit(cache=True)
def barus_strip_mean(c):
    """Mean of exp(c·sqrt(1 − xi²)) over xi in [−1, 1] (the Barus viscosity averaged along a strip of
    the Hertz ellipse, c = alpha·p_centre), ≈ exp(c)/sqrt(1 + 2c/pi): exact at c = 0 and as
    c → inf (Laplace: exp(c)·sqrt(pi/(2c))), within 6.5 % in between (tests/test_traction_ehl.py)."""
    return math.exp(c) / math.sqrt(1.0 + 2.0 * c / math.pi)


@njit(cache=True)
def _strip_viscosity(eta_in, c):
    """(eta_g, R) of a strip with centre-line alpha·p_c = c: the geometric-mean Barus viscosity
    eta_in·exp((pi/4)·c) and the ratio R = eta_a/eta_g >= 1 of the arithmetic mean to it."""
    e_quarter = math.exp(0.25 * math.pi * c)
    return eta_in * e_quarter, barus_strip_mean(c) / e_quarter


@njit(cache=True)
def _strip_shear_core(v, p_mean, eta_g, ratio, h, c_th, t_m, tau0, gamma_l, g_mod, beta_t):
    """Strip-mean shear stress (module docstring, "EHL film-shear law") from the strip's mean
    pressure, viscosities, thermal coefficient c_th (K·m²/W) and transit time t_m (s)."""
    rate = v / h
    xg = eta_g * rate / tau0
    y = xg * (1.0 + (ratio - 1.0) / math.sqrt(1.0 + xg * xg))
    root_y = math.sqrt(1.0 + y * y)
    tau_iso = tau0 * math.log(y + root_y)                             # tau0·asinh(y)
    tau_th = tau_iso / (1.0 + beta_t * c_th * v * tau0 * y / root_y)  # d tau/d ln(eta) = tau0·tanh
    tau_l = gamma_l * p_mean
    tau_f = -tau_l * math.expm1(-tau_th / tau_l)                      # Bair–Winer limit
    x = g_mod * rate * t_m / tau_f                                    # Maxwell element
    if x < 1e-6:
        return tau_f * x * (0.5 - x / 6.0)
    return tau_f * (1.0 - (1.0 - math.exp(-x)) / x)


@njit(cache=True)
def ehl_strip_shear(v, p_c, b_m, h, u_roll, eta_in, alpha_p, k_oil, tau0, gamma_l, g_mod,
                    k_steel, kappa_steel, beta_t):
    """Mean shear stress (Pa) of the film over one strip of the Hertz ellipse (module docstring,
    "EHL film-shear law"): sliding speed v >= 0 (m/s), centre-line pressure p_c (Pa), half-length
    b_m of the strip along the rolling direction (m), film thickness h (m), rolling speed u_roll
    (m/s), inlet viscosity eta_in (Pa·s), alpha_p (1/Pa), oil conductivity k_oil (W/(m·K)), Eyring
    stress tau0 (Pa), limiting-shear coefficient gamma_l, film shear modulus g_mod (Pa), steel
    conductivity and diffusivity, viscosity–temperature coefficient beta_t (1/K). Thermal
    coefficient: the film's mean rise h/(12·k_oil) (uniform dissipation, parabolic profile) plus
    the mean flash temperature of both solids, 0.532·sqrt(2·kappa·b_m/U)/k_steel (Jaeger band
    source, Pe >> 1, half the heat into each)."""
    if v <= 0.0 or p_c <= 0.0:
        return 0.0
    u = max(u_roll, 1e-3)
    eta_g, ratio = _strip_viscosity(eta_in, alpha_p * p_c)
    c_th = h / (12.0 * k_oil) + 0.532 * math.sqrt(2.0 * kappa_steel * b_m / u) / k_steel
    return _strip_shear_core(v, 0.25 * math.pi * p_c, eta_g, ratio, h, c_th, 2.0 * b_m / u, tau0, gamma_l,
                             g_mod, beta_t)


@njit(cache=True)
def sliced_traction_ehl(Q, a, b, p0, h, u_rolling, du0, du1, du2, dv, n_slices, transverse, s_lin,
                        eta_in, alpha_p, k_oil, tau0, gamma_l, g_mod, k_solid, kappa_solid, beta_t):
    """`sliced_traction` with the EHL film-shear law: each slice gets mu = (strip-mean shear
    stress)/(strip-mean pressure) of `ehl_strip_shear` at its sliding speed. Q load (N), a, b
    semi-axes across / along the rolling direction (m), p0 Hertz peak pressure (Pa), h central film
    thickness (m), u_rolling = UR (m/s), du(y) as in `sliced_traction`, eta_in the inlet viscosity
    (Pa·s), alpha_p, k_oil, and the law's parameters (`EhlParameters`: tau0 and gamma_l already
    scaled; the model's slots P_EHL_*). Below the slip s_lin (>= 0) the curve is the straight line
    through the origin and mu(s_lin), as `sliced_traction`. Returns (T_x, T_y, M_z) on the ball."""
    if Q <= 0.0 or n_slices < 1 or h <= 0.0:
        return 0.0, 0.0, 0.0
    ur = abs(u_rolling)
    if ur < 1e-12:
        ur = 1e-12
    u = max(ur, 1e-3)
    # per contact: the film's thermal term and the flash term of the full half-length b
    c_film = h / (12.0 * k_oil)
    c_flash = 0.532 * math.sqrt(2.0 * kappa_solid * b / u) / k_solid
    v_lin = s_lin * ur
    tx = 0.0
    ty = 0.0
    mz = 0.0
    for m in range(n_slices):
        qm, eta_m, y, du = _slice(m, n_slices, Q, a, du0, du1, du2)
        root = math.sqrt(max(1.0 - eta_m * eta_m, 0.0))
        p_c = p0 * root
        if transverse and dv != 0.0:
            sv = math.sqrt(du * du + dv * dv)
        else:
            sv = abs(du)
        if sv <= 0.0 or p_c <= 0.0:
            continue
        v_eval = sv if sv >= v_lin else v_lin
        eta_g, ratio = _strip_viscosity(eta_in, alpha_p * p_c)
        p_mean = 0.25 * math.pi * p_c
        tau = _strip_shear_core(v_eval, p_mean, eta_g, ratio, h, c_film + c_flash * math.sqrt(root),
                                2.0 * b * root / u, tau0, gamma_l, g_mod, beta_t)
        fm = qm * tau / p_mean
        if v_eval > sv:
            fm *= sv / v_eval
        if transverse and dv != 0.0:
            tmx = fm * du / sv
            ty += fm * dv / sv
        else:
            tmx = fm if du >= 0.0 else -fm
        tx += tmx
        mz -= y * tmx
    return tx, ty, mz


def ehl_traction_curve(slips, Q, Rx, Ry, E_eff, u_rolling, oil, table, n_slices: int = 8, s_lin: float = 0.0):
    """mu(s) of the EHL film-shear law for a uniform slide/roll ratio s (numpy array) at one
    contact: the Hertz ellipse (flexbearing.multibody.hertz, exact), the Hamrock–Dowson central film with the
    inlet viscosity at the contact temperature, and `sliced_traction_ehl` with the law's
    `ehl_parameters`; the same evaluation as the dynamics (flexbearing.multibody.race_kernels._race_traction).
    For plots, tests and tables (not compiled)."""
    from flexbearing.multibody.film import film_thickness
    from flexbearing.multibody.hertz import hertz_point_contact
    a, b, p0, _ = hertz_point_contact(Rx, Ry, E_eff, Q)
    law = ehl_parameters(table, oil.viscosity())
    h = film_thickness(Rx, Ry, E_eff, Q, u_rolling, law.eta_inlet, oil.pressure_viscosity_coeff)[1]
    out = np.empty(len(np.atleast_1d(slips)))
    for i, s in enumerate(np.atleast_1d(slips)):
        tx, _, _ = sliced_traction_ehl(Q, a, b, p0, h, u_rolling, s * abs(u_rolling), 0.0, 0.0, 0.0,
                                       n_slices, False, s_lin, law.eta_inlet, oil.pressure_viscosity_coeff,
                                       oil.thermal_conductivity, law.tau0, law.gamma_l, law.shear_modulus,
                                       law.k_solid, law.kappa_solid, law.beta_t)
        out[i] = tx / Q
    return out
