"""The bearing as numba-ready arrays: parameters, switches, Hertz tables, and the state layout.

`build_model(bearing, oil, options)` turns the validated `Bearing`/`Oil` dataclasses into a
`Model` (a NamedTuple of float64/int64 numpy arrays) that the compiled right-hand side
(`flexbearing.multibody.dynamics.rhs`) and the integrator (`flexbearing.multibody.integrator.advance`) take as plain
arguments. Nothing in the hot loop looks at a Python object.

State vector y (float64, SI; `state_layout(model)` returns the offsets)
-----------------------------------------------------------------------
Block sizes, slot names and offsets are constants of flexbearing.multibody.state_layout (BALL_STATE,
BALL_X, ..., ring_offset(Z), cage_offset(Z), modal_offset(Z)); use those, not the numbers below.

Ball j (j = 0..Z-1), block of 9 at ``9*j`` (orbiting frame of the ball, right-handed
(e_x, e_r, e_t), e_t = e_x × e_r, azimuth psi measured from +Y towards +Z, as flexbearing.multibody.geometry):

    0 x        axial position of the ball centre, m
    1 r        radial position (distance from the bearing axis), m
    2 psi      azimuth (orbital angle), rad
    3 x_dot    m/s
    4 r_dot    m/s
    5 psi_dot  orbital speed, rad/s
    6 w_x      absolute angular velocity of the ball, components on e_x, e_r, e_t, rad/s
    7 w_r
    8 w_t

Inner ring, block of 11 at ``RING = 9*Z``:
    0 x, 1 y, 2 z (m), 3 tilt_y, 4 tilt_z (rad, small rotations about Y and Z),
    5..9 their rates, 10 spin angle phi_i (rad; phi_i' = omega_i(t), the prescribed speed).

Cage, block of 12 at ``CAGE = RING + 11`` (floating frame of the cage body):
    0 x, 1 y, 2 z (m), 3 phi_c (cage spin angle about X), 4 tilt_y, 5 tilt_z (rad),
    6..8 velocities (m/s), 9 omega_c (cage spin speed, rad/s), 10, 11 tilt rates (rad/s).

Modal coordinates of a flexible cage, block of 2·n_modes at ``MODES = CAGE + 12``:
    q (n_modes) then q_dot (n_modes). A rigid cage has n_modes = 0 and the block is empty.

Parameters (`Model.p`, index constants P_* below) and switches (`Model.flags`, F_*) are plain
arrays so that numba specialises once for every bearing.

Assumed inputs (not in the paper; options keys, SI):
* ``inner_ring_mass`` (kg): the two inner half-rings, estimated as the annulus from the bore to
  dm − Dw/2 over the ring width with 15 % removed for the groove (≈ 0.94 kg for the paper
  bearing); plus ``inner_ring_added_mass`` (kg, default 0): the share of the shaft that moves
  with it. Diametral inertia of a thick ring, m·(3(Ro² + Ri²) + w²)/12; polar m(Ro² + Ri²)/2.
* Cage mass and inertia from the cage geometry: the annulus minus Z straight cylindrical
  pockets, integrated numerically (`cage_mass_properties`), 40CrNiMoA.
* ``damping_ratio`` (default 0.05): viscous contact damping c = 2·zeta·sqrt(k_lin·m_b),
  k_lin = 1.5·K·delta^0.5, added to the Hertz force of every ball–race and the Hertz part of
  every ball–pocket contact (a fraction of the critical damping of the ball on the contact's
  linearised stiffness; Harris & Kotzalas Vol. 2 §... use ~2–10 %).
* Churning drag: flexbearing.multibody.drag (sphere C_d(Re), oil–air mixture of Oil.oil_air_fraction).
* ``rim_stiffness`` (N/m, default flexbearing.multibody.guide_land.rim_stiffness: (pi/4)·E'·L) and
  ``rim_friction`` (0.1): the cage–land rim penalty contact beyond the guide clearance.
* ``pocket_friction`` (0.0): an optional Coulomb friction coefficient at the loaded side of the
  pocket, added to the hydrodynamic pocket resistances (flexbearing.multibody.pocket).
* ``gravity`` (0.0 m/s², along −Z): off by default so that steady runs compare with the
  quasi-static solution without weight.
* ``traction_slip_linear`` (2e-3): below this slip |s| the traction curve is replaced by the
  straight line through the origin and mu(s_lin): the fitted curve has mu(0+) = A + D != 0,
  i.e. a jump at s = 0 that would make the RHS discontinuous (chatter, step rejections).
* ``traction_law`` ("fit"): the traction coefficient law of flexbearing.multibody.traction: "fit", the paper's
  4106 regression (Wang, Yang & Wang 2004; default, the paper's scenes), or "ehl", the EHL
  film-shear law (Newtonian → Eyring shear of the film with a pressure-proportional limiting
  shear stress, thermal correction, Maxwell element; no dead zone at light load; the slip-rate
  validation's law). With "ehl": ``traction_scale`` (1.0) multiplies the film's strength (Eyring
  and limiting shear stresses) and ``contact_temperature_rise`` (0 K) is the contacts' inlet
  temperature above the oil temperature (ranges: flexbearing.multibody.traction.EHL_RANGES).
* ``min_rolling_speed`` (0.5 m/s): the traction laws are evaluated with UR >= this (the fit's power
  laws in Ub diverge at UR -> 0); for the fit the larger ``slip_regularisation_speed`` governs.
* ``slip_regularisation_speed`` (10 m/s, u_reg): the "fit" traction law is evaluated at the
  effective rolling speed UR_eff = max(|UR|, u_reg), its coefficients and its slide-to-roll ratio
  s = du/UR_eff (flexbearing.multibody.traction, "Low rolling speed"): below u_reg the traction is a function
  of the sliding speed du alone and its creep slope dT/d(du) stays bounded by Q·mu'/u_reg instead
  of growing as UR^-1.67. Above u_reg (the paper's scenes: UR 40–60 m/s at 10,000–14,000 rpm) it
  is the fit unchanged, to the bit. It takes a run at rest from ~1.2e8 integrator steps per
  simulated second to ~4e5 (benchmarks/results/speed.md). The "ehl" law is not affected.
* ``eps_film_max`` (0.95): the short-bearing land forces are evaluated at min(eps, eps_max);
  beyond the clearance the rim contact takes over.
* ``ball_drag_moment`` (False): the viscous moment of the oil–air mixture (at rest) on each
  spinning ball, M = −pi·eta_mix·Dw³·w (Stokes–Lamb, flexbearing.multibody.drag.ball_drag_moment_coefficient),
  with the drag switch on. Off by default: at every Table 5 case and the paper's scenes it is 4–6
  orders of magnitude below the contact moments and moves no slip (docs/race_control.md), and
  off keeps the reference runs bit-identical.
* ``spin_moment_scale_inner`` (1.0; 0.1–1000): a diagnostic, not physics: multiplies the spin
  moment (about the contact normal) of the traction at both inner half-grooves, and with it that
  contact's spin power. Used only by the race-control screening (benchmarks/race_control_screening.py)
  to ask how much stronger the inner contact's spin resistance would have to be to control the
  ball; 1.0 is the traction law itself (bit-identical).
"""
from __future__ import annotations

import math
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from flexbearing.common.validation import InputError, require_range
from flexbearing.mesh.cage_geometry import GUIDANCES, POCKET_SHAPES
from flexbearing.multibody.bearing import Bearing, Oil
from flexbearing.multibody.floating_frame import CageArrays, new_workspace, rigid_body
from flexbearing.multibody.hertz import effective_modulus, ellipticity, hertz_stiffness, race_curvature_radii
from flexbearing.multibody.traction import TRACTION_FIT_4106, TRACTION_LAWS, ehl_traction_table, fill_ehl_parameters
from flexbearing.multibody.geometry import inner_groove_centres, outer_groove_centre
from flexbearing.multibody.guide_land import fill_guide_land_parameters
from flexbearing.multibody.pocket import fill_pocket_parameters
from flexbearing.multibody import state_layout as SL

from flexbearing.multibody.model_layout import (  # noqa: F401  (the layout's names, read as model.P_* etc.)
    P_DW, P_DM, P_Z, P_FE, P_FI, P_XO, P_RO, P_XIL, P_RIL, P_XIR, P_RIR, P_MB, P_IB, P_MI, P_IID, P_IIP, P_MC,
    P_ICP, P_ICD, P_EBR, P_CP, P_KC, P_KN, P_RPOCKET, P_RCAGE_POCKET, P_R1, P_CG, P_L3, P_KRIM, P_MURIM, P_ETA0,
    P_T0K, P_K0, P_RHO_OIL, P_OILFRAC, P_ALPHA_P, P_SLIN, P_UMIN, P_ZETA, P_MUPOCKET, P_GRAV, P_EPSMAX,
    P_ALPHA0, P_LAND_L, P_ETA_TRACTION, P_ATT_RATE, P_UREG, P_OIL_WREF, P_SPIN_SCALE_INNER, P_POCKET_CONE,
    P_POCKET_B, P_EHL_TAU0, P_EHL_GAMMA_L, P_EHL_SHEAR_MODULUS, P_EHL_K_SOLID, P_EHL_KAPPA_SOLID, P_EHL_BETA_T,
    P_EHL_ETA_INLET, N_PARAMS, F_TRACTION, F_DRAG, F_DAMPING, F_TRANSVERSE, F_NSLICES, F_HERTZ_FIXED, F_ROLLRES,
    F_LAND, F_ATTITUDE, F_ATT_RING, F_TRACTION_LAW, F_INNER_HALVES, F_GUIDANCE, F_POCKET_SHAPE,
    F_BALL_DRAG_MOMENT, N_FLAGS, BALL_ATTITUDES, ATTITUDE_FREE, ATTITUDE_OUTER, ATTITUDE_INNER, ATTITUDE_JONES,
    ATTITUDE_NO_PIVOT, RACE_CONTACTS, CONTACT_OUTER, CONTACT_INNER_LEFT, CONTACT_INNER_RIGHT, CONTACT_INNER,
    CONTACT_RACE, RACE_OUTER,
    RACE_INNER, H_K, H_ELL, H_EK, H_R, H_RX, H_RY, N_HCOLS, N_HGRID, N_WC, W_C0, W_POCKET_Q, W_POCKET_Z,
    W_POCKET_T, W_DRAG, W_PK_FX, W_PK_FY, W_PK_FZ, W_PK_LY, W_PK_LZ, W_P_POCKET, W_P_CHURNING, N_WORK, WR_FX,
    WR_FY, WR_FZ, WR_LAND_FY, WR_LAND_FZ, WR_LAND_M, WR_RIM_F, WR_RING_TORQUE, WR_EPS, WR_OMEGA_I, WR_STATUS,
    WR_BAD_BALL, WR_BAD_CONTACT, WR_BAD_VALUE, WR_P_LAND, WR_P_STRUCTURAL, WC_Q, WC_COS, WC_SIN, WC_P0, WC_UR,
    WC_RX, WC_RY, WC_A, WC_SLIP, WC_DELTA, WC_FT, WC_P_TRACTION, WC_P_ROLLING, WC_P_DAMPING,
)


class Model(NamedTuple):
    """Everything the compiled code needs, as arrays (module docstring for the layouts)."""
    p: np.ndarray            # float64 (N_PARAMS,)
    flags: np.ndarray        # int64 (N_FLAGS,)
    hertz_table: np.ndarray  # float64 (2, N_HGRID, N_HCOLS)
    traction_table: np.ndarray  # float64: the table of the law flags[F_TRACTION_LAW] names (flexbearing.multibody.traction:
                                # fit (4, 4) or its bounded forms (6, 4), EHL (8, 4): the record of
                                # its inputs, the loop reads its parameters from p[P_EHL_*])
    scale: np.ndarray        # float64 (n_state,): absolute error scale of each state component
    relmask: np.ndarray      # float64 (n_state,): 1 where the relative tolerance applies
    n_balls: int
    n_modes: int
    n_state: int
    # The cage body in floating-frame form with its work arrays (flexbearing.multibody.floating_frame.CageArrays,
    # `cage_arrays`). A rigid cage is the same body with zero modes, so rigid and flexible cages
    # run through the same equations.
    cage: CageArrays | tuple = ()


DEFAULT_OPTIONS = {
    "traction": True,
    "drag": True,              # churning drag, guide-land film forces/torque, pocket friction, rim friction
    "rolling_resistance": True,
    "damping": True,
    "transverse_traction": True,
    "n_slices": 8,
    "hertz_fixed_angle": False,
    "damping_ratio": 0.05,
    "rim_stiffness": None,
    "rim_friction": 0.1,
    "pocket_friction": 0.0,
    "gravity": 0.0,
    "traction_slip_linear": 2e-3,
    "traction_law": "fit",            # "fit" (paper's 4106 regression) | "ehl" (EHL film-shear law)
    "traction_scale": 1.0,            # "ehl" only: film strength scale
    "contact_temperature_rise": 0.0,  # "ehl" only: K above the oil temperature at the contact inlets
    "min_rolling_speed": 0.5,
    "slip_regularisation_speed": 10.0,  # m/s: the "fit" law at max(|UR|, this) (module docstring)
    "eps_film_max": 0.95,
    "inner_ring_mass": None,
    "inner_ring_added_mass": 0.0,
    "n_modes": 0,
    "ball_attitude": "free",          # "free" Euler balls, race control "outer"/"inner"/"jones", or "no_pivot"
                                      # (gyroscopic pivoting held, the paper's hypothesis; dynamics docstring)
    "attitude_rate": 2e4,             # 1/s, relaxation rate of the race-control constraints
    "attitude_ring_reaction": True,   # race control / no_pivot: gyroscopic friction reaction on the inner ring
    "ball_drag_moment": False,        # viscous moment of the oil–air mixture on the spinning ball (with drag on)
    "spin_moment_scale_inner": 1.0,   # diagnostic (race-control screening): factor on the inner spin moment
}


def cage_arrays(body) -> CageArrays:
    """The numba argument of a cage body (flexbearing.multibody.floating_frame.FlexibleBody)."""
    Mmat, rvec, U, Wab = new_workspace(body.n_modes)
    d = 6 + body.n_modes
    land = getattr(body, "land_modes", None)
    land = np.zeros((3, body.n_modes)) if land is None else np.ascontiguousarray(land, dtype=np.float64)
    if land.shape != (3, body.n_modes):
        raise ValueError(f"cage body land_modes must be (3, {body.n_modes}), got {land.shape}")
    return CageArrays(np.array([body.mass]), *(np.ascontiguousarray(a, dtype=np.float64) for a in body[1:11]),
                      Mmat, rvec, U, Wab, np.zeros(d), np.zeros(d), np.zeros((3, 3)), np.zeros((8, 3)),
                      np.zeros((body.node_position.shape[0] + 1, 6)), land)


def rigid_cage_body(cage, pitch_diameter: float):
    """The rigid cage as a floating-frame body with zero modes: mass and inertia of the annulus
    minus the pockets (`cage_mass_properties`), CoM at the frame origin, one interface node per
    pocket on its axis at the pitch radius (the ball centres' radius)."""
    mc, icp, icd = cage_mass_properties(cage)
    psi = 2.0 * math.pi * np.arange(cage.n_pockets) / cage.n_pockets
    r = 0.5 * pitch_diameter
    nodes = np.stack([np.zeros_like(psi), r * np.cos(psi), r * np.sin(psi)], axis=1)
    return rigid_body(mc, np.zeros(3), np.diag([icp, icd, icd]), node_position=nodes)


def state_layout(model: Model) -> dict:
    """Offsets and block sizes of the state vector (module docstring)."""
    z = model.n_balls
    ring = SL.ring_offset(z)
    cage = SL.cage_offset(z)
    modes = SL.modal_offset(z)
    return {"ball": 0, "ball_block": SL.BALL_STATE, "ring": ring, "ring_block": SL.RING_STATE, "cage": cage,
            "cage_block": SL.CAGE_STATE, "modes": modes, "n_modes": model.n_modes,
            "n_state": SL.state_size(z, model.n_modes),
            "ball_fields": ["x", "r", "psi", "x_dot", "r_dot", "psi_dot", "w_x", "w_r", "w_t"],
            "ring_fields": ["x", "y", "z", "tilt_y", "tilt_z", "x_dot", "y_dot", "z_dot",
                            "tilt_y_dot", "tilt_z_dot", "phi"],
            "cage_fields": ["x", "y", "z", "phi", "tilt_y", "tilt_z", "x_dot", "y_dot", "z_dot",
                            "omega", "tilt_y_dot", "tilt_z_dot"]}


# cached: a run builds its model twice (integration, outputs), each build needs it twice, and one
# quadrature takes ~15 ms; the cage geometry is a frozen dataclass (hashable, immutable)
@lru_cache(maxsize=32)
def cage_mass_properties(cage, n_r: int = 24, n_phi: int = 240, n_x: int = 80) -> tuple[float, float, float]:
    """Mass (kg), polar and diametral moments of inertia (kg·m²) of the cage ring with its pockets.

    Midpoint quadrature over the annulus R_i <= r <= R_o, |x| <= w/2, one pocket pitch in phi,
    excluding the points inside the radial cylindrical pocket (distance to the pocket axis < Dp/2)
    or the spherical one (distance to its centre on the pocket-centre radius < Dp/2) or the
    conical one (distance to the axis < CageGeometry.cone_radius), times Z.
    Polar I = ∫ rho·r² dV, diametral I = ∫ rho·(x² + r²/2) dV (axisymmetric average).
    """
    ri, ro, w, z = cage.inner_radius, cage.outer_radius, cage.width, cage.n_pockets
    rp = 0.5 * cage.pocket_diameter
    rho = cage.material.density
    dr, dphi, dx = (ro - ri) / n_r, 2 * math.pi / z / n_phi, w / n_x
    r = ri + (np.arange(n_r) + 0.5) * dr
    phi = -math.pi / z + (np.arange(n_phi) + 0.5) * dphi
    x = -0.5 * w + (np.arange(n_x) + 0.5) * dx
    R, PHI, X = np.meshgrid(r, phi, x, indexing="ij")
    # distance from the pocket axis (the radial line at phi = 0 in the mid-plane)
    yy = R * np.sin(PHI)
    if cage.pocket_shape == "spherical":
        rc = 0.5 * cage.pocket_centre_diameter
        solid = ((R * np.cos(PHI) - rc) ** 2 + yy ** 2 + X ** 2) >= rp ** 2
    elif cage.pocket_shape == "conical":         # radius Rp/cos(beta) + s·tan(beta) at s from the centre
        s = R * np.cos(PHI) - 0.5 * cage.pocket_centre_diameter
        solid = np.sqrt(yy ** 2 + X ** 2) >= cage.cone_radius(s)
    elif cage.pocket_shape == "elliptical":      # semi-axes Dp/2 along x, Dp_t/2 around
        solid = (X / rp) ** 2 + (yy / (0.5 * cage.pocket_circumferential_diameter)) ** 2 >= 1.0
    else:
        solid = (yy ** 2 + X ** 2) >= rp ** 2
    dv = R * dr * dphi * dx * solid
    m = rho * z * dv.sum()
    ip = rho * z * (dv * R ** 2).sum()
    idiam = rho * z * (dv * (X ** 2 + 0.5 * R ** 2)).sum()
    return float(m), float(ip), float(idiam)


def _hertz_tables(bearing: Bearing, e_eff: float) -> np.ndarray:
    tab = np.zeros((2, N_HGRID, N_HCOLS))
    for kind, (f, inner) in enumerate(((bearing.fe, False), (bearing.fi, True))):
        for i in range(N_HGRID):
            ca = i / (N_HGRID - 1)
            alpha = math.acos(min(1.0, ca))
            rx, ry = race_curvature_radii(bearing.ball_diameter, bearing.pitch_diameter, f, alpha, inner)
            rho = max(ry / rx, rx / ry)
            k, ek, kk = ellipticity(rho)
            tab[kind, i] = (hertz_stiffness(rx, ry, e_eff), k, ek, 1.0 / (1.0 / rx + 1.0 / ry), rx, ry)
    return tab


def _option(options: dict, key: str):
    return options[key] if key in options else DEFAULT_OPTIONS[key]


def _fill_inner_ring(p, bearing, options) -> None:
    """The inner ring's mass and inertias in p (assumed geometry, module docstring; model options
    inner_ring_mass, inner_ring_added_mass)."""
    dw, dm = bearing.ball_diameter, bearing.pitch_diameter
    ro_i, ri_i, w_i = 0.5 * (dm - 0.5 * dw), 0.5 * bearing.bore_diameter, bearing.width
    m_ring = _option(options, "inner_ring_mass")
    if m_ring is None:
        m_ring = 0.85 * bearing.ring_material.density * math.pi * (ro_i ** 2 - ri_i ** 2) * w_i
    m_ring = require_range("model.inner_ring_mass", m_ring, 1e-3, 1e3, unit="kg")
    m_ring += require_range("model.inner_ring_added_mass", _option(options, "inner_ring_added_mass"), 0.0, 1e4, unit="kg")
    p[P_MI] = m_ring
    p[P_IID] = m_ring * (3.0 * (ro_i ** 2 + ri_i ** 2) + w_i ** 2) / 12.0
    p[P_IIP] = 0.5 * m_ring * (ro_i ** 2 + ri_i ** 2)


def _switches(options, bearing, n_slices) -> np.ndarray:
    """The switches of the model options (flags, F_*) but the traction law, the guidance and the
    pocket shape, which build_model sets."""
    flags = np.zeros(N_FLAGS, dtype=np.int64)
    flags[F_TRACTION] = bool(_option(options, "traction"))
    flags[F_DRAG] = bool(_option(options, "drag"))
    flags[F_ROLLRES] = bool(_option(options, "rolling_resistance"))  # active only with drag on
    flags[F_LAND] = bool(_option(options, "drag"))
    flags[F_DAMPING] = bool(_option(options, "damping"))
    flags[F_TRANSVERSE] = bool(_option(options, "transverse_traction"))
    flags[F_NSLICES] = n_slices
    flags[F_INNER_HALVES] = bearing.n_inner_halves
    flags[F_HERTZ_FIXED] = bool(_option(options, "hertz_fixed_angle"))
    attitude = _option(options, "ball_attitude")
    if attitude not in BALL_ATTITUDES:
        raise InputError(f"model.ball_attitude = {attitude!r} is not known; allowed: {list(BALL_ATTITUDES)}")
    flags[F_ATTITUDE] = BALL_ATTITUDES.index(attitude)
    flags[F_ATT_RING] = bool(_option(options, "attitude_ring_reaction"))
    flags[F_BALL_DRAG_MOMENT] = bool(_option(options, "ball_drag_moment"))
    return flags


def build_model(bearing: Bearing, oil: Oil, options: dict | None = None, cage_body=None) -> Model:
    """Model arrays for `bearing` lubricated with `oil` (module docstring for every entry).

    options: any key of DEFAULT_OPTIONS; unknown keys are an InputError.
    cage_body: the cage as a floating-frame body (flexbearing.multibody.floating_frame.FlexibleBody; the
    flexible cage of flexbearing.coupling.flexible_cage); None = the rigid cage (`rigid_cage_body`).
    """
    options = dict(options or {})
    unknown = set(options) - set(DEFAULT_OPTIONS)
    if unknown:
        raise InputError(f"model options {sorted(unknown)} are not known; allowed: {sorted(DEFAULT_OPTIONS)}")
    bearing.validate()
    oil.validate()
    n_slices = int(_option(options, "n_slices"))
    require_range("model.n_slices", n_slices, 1, 64)
    if int(_option(options, "n_modes")) != 0:
        raise InputError(f"model.n_modes = {_option(options, 'n_modes')}: the modes of a flexible cage come "
                         "from its reduced cage file (cage.model = 'flexible'), not from this option")
    if cage_body is None:
        cage_body = rigid_cage_body(bearing.cage, bearing.pitch_diameter)
    if cage_body.node_position.shape[0] != bearing.n_balls:
        raise InputError(f"cage body has {cage_body.node_position.shape[0]} pocket interface nodes, "
                         f"the bearing {bearing.n_balls} balls")
    n_modes = cage_body.n_modes
    zeta = require_range("model.damping_ratio", _option(options, "damping_ratio"), 0.0, 1.0)
    s_lin = require_range("model.traction_slip_linear", _option(options, "traction_slip_linear"), 1e-6, 0.1)
    u_min = require_range("model.min_rolling_speed", _option(options, "min_rolling_speed"), 1e-3, 10.0, unit="m/s")
    u_reg = require_range("model.slip_regularisation_speed", _option(options, "slip_regularisation_speed"),
                          1e-3, 50.0, unit="m/s")
    eps_max = require_range("model.eps_film_max", _option(options, "eps_film_max"), 0.1, 0.999)

    dw, dm, z = bearing.ball_diameter, bearing.pitch_diameter, bearing.n_balls
    bm, rm, cage = bearing.ball_material, bearing.ring_material, bearing.cage
    p = np.zeros(N_PARAMS)
    p[P_DW], p[P_DM], p[P_Z], p[P_FE], p[P_FI] = dw, dm, z, bearing.fe, bearing.fi
    p[P_XO], p[P_RO] = outer_groove_centre(dm, dw, bearing.fe)
    p[P_XIL], p[P_RIL], p[P_XIR], p[P_RIR] = inner_groove_centres(dm, dw, bearing.fi,
                                                                  *bearing.groove_layout)
    p[P_MB] = bearing.ball_mass
    p[P_IB] = 0.4 * bearing.ball_mass * (0.5 * dw) ** 2
    _fill_inner_ring(p, bearing, options)
    mc, icp, icd = cage_mass_properties(cage)
    p[P_MC], p[P_ICP], p[P_ICD] = mc, icp, icd
    e_br = effective_modulus(bm.youngs_modulus, bm.poisson_ratio, rm.youngs_modulus, rm.poisson_ratio)
    e_bc = effective_modulus(bm.youngs_modulus, bm.poisson_ratio, cage.material.youngs_modulus,
                             cage.material.poisson_ratio)
    p[P_EBR] = e_br
    # ball–pocket (paper §2.3.1) and guide land (Ocvirk short bearing and rim): each law fills its slots
    fill_pocket_parameters(p, bearing, e_bc, _option(options, "pocket_friction"))
    fill_guide_land_parameters(p, bearing, e_bc, _option(options, "rim_stiffness"), _option(options, "rim_friction"))
    # oil: the traction fit and the film models take eta0 "at ambient" (flexbearing.multibody.traction)
    p[P_ETA0] = oil.viscosity()                      # land film, film thickness: at the oil temperature
    p[P_ETA_TRACTION] = oil.viscosity(oil.temperature_ref_c)  # traction fit: "ambient" eta0 (traction.py)
    p[P_T0K] = oil.temperature_k
    p[P_K0] = oil.thermal_conductivity
    p[P_RHO_OIL] = oil.density
    p[P_OILFRAC] = oil.oil_air_fraction
    p[P_OIL_WREF] = oil.supply_reference_rpm * math.pi / 30.0
    p[P_ALPHA_P] = oil.pressure_viscosity_coeff
    p[P_SLIN], p[P_UMIN], p[P_ZETA] = s_lin, u_min, zeta
    p[P_UREG] = u_reg
    p[P_GRAV] = require_range("model.gravity", _option(options, "gravity"), 0.0, 100.0, unit="m/s^2")
    p[P_EPSMAX] = eps_max
    p[P_ALPHA0] = bearing.free_contact_angle

    flags = _switches(options, bearing, n_slices)
    p[P_SPIN_SCALE_INNER] = require_range("model.spin_moment_scale_inner", _option(options, "spin_moment_scale_inner"),
                                          0.1, 1000.0)
    p[P_ATT_RATE] = require_range("model.attitude_rate", _option(options, "attitude_rate"), 1e2, 1e6, unit="1/s")

    law = _option(options, "traction_law")
    if law not in TRACTION_LAWS:
        raise InputError(f"model.traction_law = {law!r} is not known; allowed: {list(TRACTION_LAWS)}")
    if law == "ehl":
        ttab = ehl_traction_table(oil.viscosity_temperature_coeff, float(_option(options, "traction_scale")),
                                  float(_option(options, "contact_temperature_rise")),
                                  ball_thermal=bearing.ball_thermal, race_thermal=bearing.ring_thermal)
    else:
        for key in ("traction_scale", "contact_temperature_rise"):
            if key in options and options[key] != DEFAULT_OPTIONS[key]:
                raise InputError(f"model.{key} = {options[key]!r} applies to traction_law = 'ehl' only "
                                 f"(this model has {law!r})")
        ttab = np.array(TRACTION_FIT_4106, dtype=np.float64)
    # the EHL law's parameters and inlet viscosity, once per model (zero under the fit)
    fill_ehl_parameters(p, ttab if law == "ehl" else None)
    flags[F_TRACTION_LAW] = TRACTION_LAWS.index(law)
    flags[F_GUIDANCE] = GUIDANCES.index(cage.guidance)
    flags[F_POCKET_SHAPE] = POCKET_SHAPES.index(cage.pocket_shape)
    htab = _hertz_tables(bearing, e_br)
    n_state = SL.state_size(z, n_modes)
    scale, relmask = _error_scales(z, n_modes, dw)
    return Model(p=p, flags=flags, hertz_table=htab, traction_table=ttab,
                 scale=scale, relmask=relmask, n_balls=z, n_modes=n_modes, n_state=n_state,
                 cage=cage_arrays(cage_body))


def with_traction_table(model: Model, table: np.ndarray, law: str = "fit") -> Model:
    """`model` with another traction table of the named law (flexbearing.multibody.traction: "fit" for the
    4106 fit and its bounded and origin forms, "ehl" for `ehl_traction_table`): the table, the
    flag F_TRACTION_LAW that tells the right-hand side how to read it and the EHL law's slots
    P_EHL_* (flexbearing.multibody.traction.fill_ehl_parameters) change together."""
    if law not in TRACTION_LAWS:
        raise InputError(f"traction law = {law!r} is not known; allowed: {list(TRACTION_LAWS)}")
    table = np.ascontiguousarray(table, dtype=np.float64)
    flags = model.flags.copy()
    flags[F_TRACTION_LAW] = TRACTION_LAWS.index(law)
    p = model.p.copy()
    fill_ehl_parameters(p, table if law == "ehl" else None)
    return model._replace(traction_table=table, flags=flags, p=p)


def _error_scales(z: int, n_modes: int, dw: float) -> tuple[np.ndarray, np.ndarray]:
    """Absolute error scales of the state components, used by the integrator's error norm.

    The contact approaches are micrometres, so positions are measured against 1e-4 m (a
    tolerance tol = 1e-6 then bounds the local error near 1e-10 m, i.e. 1e-4 of a 1 um approach);
    velocities against 0.1 m/s, the balls' translational velocities (x', r') against 0.3 m/s (below);
    ball angular velocities (spin ~ 2000 rad/s) against 10 rad/s;
    cumulative angles (ball azimuth, ring and cage spin angle) against 1e-3 rad with no relative
    part (they grow without bound). Orbital and spin speeds also get the relative tolerance.

    Ball x', r': the balls' fastest motion is their vibration on the Hertz contacts,
    omega_H = sqrt((k_o + k_i)/m_b) ~ 1.3e5 rad/s at the paper's loads (k = 1.5·Q/delta ~ 2e8 N/m
    per contact; the Jacobian's largest eigenvalues, -1e4 ± 1.3e5j). In that mode a velocity error
    e_v is worth a displacement e_v/omega_H, so against 0.1 m/s the velocities were weighted ~130x
    tighter than the positions (1e-4 m ~ 13 m/s); the integrator's error norm was 98 % ball x', r'
    (measured, tol 1e-6, paper steady case) and the step size followed it. 0.3 m/s keeps them
    ~40x tighter than the positions. Measured over 5 ms of the paper steady case: 655 steps at
    0.1 m/s, 572 at 0.3, 482 at 1.0; 1.0 m/s moves the report's statistics by <= 0.03 % (contact
    stresses) and <= 0.6 % (p99 cage forces) but lets the energy of a conservative free run
    drift by 1.4e-3 of its Hertz energy per second (tests/test_energy.py bounds it at 1e-3, from
    1.1e-4 at 0.1 m/s) and moves the race-control pitch by 0.023° (tests/test_ball_attitude.py:
    0.02°); 0.3 m/s passes both.
    """
    n = SL.state_size(z, n_modes)
    s = np.zeros(n)
    rel = np.zeros(n)
    for j in range(z):
        b = SL.ball_offset(j)
        s[b + SL.BALL_X:b + SL.BALL_R + 1] = 1e-4
        s[b + SL.BALL_PSI] = 1e-4 / (0.5 * 0.167)   # ~1e-4 m of arc at the pitch radius
        s[b + SL.BALL_X_DOT:b + SL.BALL_R_DOT + 1] = 0.3   # ball x', r': the Hertz vibration (docstring)
        s[b + SL.BALL_PSI_DOT] = 1.0
        s[b + SL.BALL_W_X:b + SL.BALL_W_T + 1] = 10.0
        rel[b + SL.BALL_PSI_DOT:b + SL.BALL_W_T + 1] = 1.0
    r0 = SL.ring_offset(z)
    s[r0 + SL.RING_X:r0 + SL.RING_Z + 1] = 1e-4
    s[r0 + SL.RING_TILT_Y:r0 + SL.RING_TILT_Z + 1] = 1e-3
    s[r0 + SL.RING_VX:r0 + SL.RING_VZ + 1] = 0.1
    s[r0 + SL.RING_TILT_Y_DOT:r0 + SL.RING_TILT_Z_DOT + 1] = 1.0
    s[r0 + SL.RING_PHI] = 1e-3
    c0 = SL.cage_offset(z)
    s[c0 + SL.CAGE_X:c0 + SL.CAGE_Z + 1] = 1e-4
    s[c0 + SL.CAGE_PHI] = 1e-3
    s[c0 + SL.CAGE_TILT_Y:c0 + SL.CAGE_TILT_Z + 1] = 1e-3
    s[c0 + SL.CAGE_VX:c0 + SL.CAGE_VZ + 1] = 0.1
    s[c0 + SL.CAGE_OMEGA] = 1.0
    rel[c0 + SL.CAGE_OMEGA] = 1.0
    s[c0 + SL.CAGE_TILT_Y_DOT:c0 + SL.CAGE_TILT_Z_DOT + 1] = 1.0
    if n_modes:
        # modal coordinates of mass-normalised modes: displacement ~ q / sqrt(cage mass), so the
        # position and velocity scales of the bodies apply
        m0 = SL.modal_offset(z)
        s[m0:m0 + n_modes] = 1e-4
        s[m0 + n_modes:] = 0.1
    return s, rel
