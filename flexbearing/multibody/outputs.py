"""The recordable quantities of the bearing at one state: what a run samples.

`evaluate_outputs(model, t, y, ...)` evaluates the right-hand side at (t, y) (flexbearing.multibody.dynamics.rhs
fills its work array with every contact's load, geometry and dissipated power) and turns the work
array and the state into named SI arrays; flexbearing.multibody.output_registry says which scene output records
each, its unit and its dimensions. The power balance's entries come from flexbearing.multibody.power_loss.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from flexbearing.multibody import model as M
from flexbearing.multibody import state_layout as SL
from flexbearing.multibody.dynamics import new_work, rhs
from flexbearing.multibody.cage_offset import cage_offset_from_guide
from flexbearing.multibody.energy import mechanical_energy
from flexbearing.multibody.film import film_thickness as hd
from flexbearing.multibody.geometry import nominal_cage_speed
from flexbearing.multibody.model import (N_WC, P_EBR, P_ETA0, W_DRAG, W_PK_FX, W_PK_FZ, W_POCKET_Q, W_POCKET_T,
                             W_POCKET_Z, WC_COS, WC_DELTA, WC_FT, WC_P0, WC_Q, WC_RX, WC_RY, WC_SIN,
                             WC_SLIP, WC_UR)
from flexbearing.multibody.power_loss import RECORDED, drive_torque, power_by_source, total_loss


def evaluate_outputs(model, t: float, y: np.ndarray, speed_table: np.ndarray, load_table: np.ndarray,
                     impacts: np.ndarray, film: bool = False, energy: bool = False) -> dict:
    """Recordable quantities at (t, y), SI. Per ball arrays have shape (Z,), per contact
    (Z, 3) in the order outer, inner-left, inner-right.

    Keys: contact_load, contact_angle (signed, rad), contact_stress (p0, Pa), approach, slide_ratio
    (race − ball rolling slide / entrainment), entrainment_speed, pocket_force, pocket_offset,
    pocket_force_tangential, cage_land_force (y, z), cage_land_force_magnitude, cage_land_torque,
    cage_rim_force, cage_eccentricity_ratio, cage_speed, cage_centre (x, y, z), cage_guide_offset (y, z:
    from the guiding ring's centre, flexbearing.multibody.cage_offset), inner_ring_speed,
    inner_ring_displacement (x, y, z, tilt_y, tilt_z), ring_drive_torque, ball_position (x, r, psi),
    ball_velocity, ball_angular_velocity (w_x, w_r, w_t), ball_orbit_speed, external_load,
    nominal_cage_speed, slip_rate, contact_angle_inner_loaded, contact_angle_outer; the power
    balance (flexbearing.multibody.power_loss): drive_power = ring_drive_torque·omega_i, power_loss (total),
    power_loss_traction, _rolling, _contact_damping (Z, 3), _pocket, _churning (Z,), _guide_land,
    _cage_damping; with energy=True also mechanical_energy (kinetic + Hertz, pocket, rim and gravity
    potentials; without the external load's potential) and external_load_power = F_ext·v_ring,
    which the balance of a recorded window needs (one more pass over the contacts); with film=True
    film_thickness_min, film_thickness_central (Hamrock–Dowson, flexbearing.multibody.film).
    """
    z = model.n_balls
    work = new_work(model)
    dydt = np.zeros_like(y)
    rhs(t, y, dydt, model.p, model.flags, model.hertz_table, model.traction_table,
        speed_table, load_table, impacts, work, model.cage)
    lay = state_layout_cached(model)
    balls = y[: lay["ring"]].reshape(z, SL.BALL_STATE)
    ring = y[lay["ring"]: lay["ring"] + SL.RING_STATE]
    cage = y[lay["cage"]: lay["cage"] + SL.CAGE_STATE]
    wc = work[:z, : 3 * N_WC].reshape(z, 3, N_WC)
    Q = wc[:, :, WC_Q]
    ang = np.arctan2(wc[:, :, WC_SIN], wc[:, :, WC_COS])
    out = {
        "contact_load": Q.copy(),
        "contact_angle": ang,
        "contact_stress": wc[:, :, WC_P0].copy(),
        "approach": wc[:, :, WC_DELTA].copy(),
        "entrainment_speed": wc[:, :, WC_UR].copy(),
        "slide_ratio": wc[:, :, WC_SLIP].copy(),
        "traction_force": wc[:, :, WC_FT].copy(),
        "pocket_force": work[:z, W_POCKET_Q].copy(),
        "pocket_offset": work[:z, W_POCKET_Z].copy(),
        "pocket_force_tangential": work[:z, W_POCKET_T].copy(),
        "pocket_force_on_cage": work[:z, W_PK_FX:W_PK_FZ + 1].copy(),
        "churning_drag": work[:z, W_DRAG].copy(),
        "cage_land_force": work[z, [M.WR_LAND_FY, M.WR_LAND_FZ]].copy(),
        "cage_land_force_magnitude": float(np.hypot(work[z, M.WR_LAND_FY], work[z, M.WR_LAND_FZ])),
        "cage_land_torque": float(work[z, M.WR_LAND_M]),
        "cage_rim_force": float(work[z, M.WR_RIM_F]),
        "cage_eccentricity_ratio": float(work[z, M.WR_EPS]),
        "cage_speed": float(cage[SL.CAGE_OMEGA]),
        "cage_centre": cage[SL.CAGE_X:SL.CAGE_Z + 1].copy(),
        "cage_guide_offset": cage_offset_from_guide(int(model.flags[M.F_GUIDANCE]), cage[SL.CAGE_Y:SL.CAGE_Z + 1],
                                                    ring[SL.RING_Y:SL.RING_Z + 1], balls[:, SL.BALL_R],
                                                    balls[:, SL.BALL_PSI]),
        "cage_tilt": cage[SL.CAGE_TILT_Y:SL.CAGE_TILT_Z + 1].copy(),
        "inner_ring_speed": float(work[z, M.WR_OMEGA_I]),
        "inner_ring_displacement": ring[:SL.RING_POSITIONS].copy(),
        "ring_drive_torque": drive_torque(work, z),
        "external_load": work[z, M.WR_FX:M.WR_FX + 3].copy(),
        "ball_position": balls[:, SL.BALL_X:SL.BALL_PSI + 1].copy(),
        "ball_velocity": balls[:, SL.BALL_X_DOT:SL.BALL_PSI_DOT + 1].copy(),
        "ball_angular_velocity": balls[:, SL.BALL_W_X:SL.BALL_W_T + 1].copy(),
        "ball_orbit_speed": balls[:, SL.BALL_PSI_DOT].copy(),
    }
    sources = power_by_source(work, z)
    for src, name in RECORDED.items():
        out[name] = sources[src]
    out["power_loss"] = total_loss(sources)
    out["drive_power"] = out["ring_drive_torque"] * out["inner_ring_speed"]
    if energy:
        f_ext = work[z, M.WR_FX:M.WR_FX + 3]
        out["external_load_power"] = float(f_ext @ ring[SL.RING_VX:SL.RING_VZ + 1])
        ek, ev = mechanical_energy(t, y, model.p, model.flags, model.hertz_table, load_table, impacts, model.cage)
        out["mechanical_energy"] = float(ek + ev + f_ext @ ring[SL.RING_X:SL.RING_Z + 1])
    ao, ai = loaded_contact_angles(out["contact_load"], out["contact_angle"])
    out["contact_angle_outer"] = ao
    out["contact_angle_inner_loaded"] = ai
    alpha = 0.5 * (np.mean(ao) + np.mean(np.abs(ai)))
    nm = nominal_cage_speed(out["inner_ring_speed"], model.p[M.P_DW], model.p[M.P_DM], alpha)
    out["nominal_cage_speed"] = nm
    out["slip_rate"] = (nm - out["cage_speed"]) / nm if nm != 0.0 else 0.0
    if film:
        out.update(film_thickness(model, wc))
    return out


def loaded_contact_angles(Q: np.ndarray, ang: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Outer contact angle and the angle of the more loaded inner half, per ball (rad)."""
    ao = ang[:, 0]
    pick = np.where(Q[:, 1] >= Q[:, 2], 1, 2)
    ai = ang[np.arange(ang.shape[0]), pick]
    return ao, ai


_LAYOUT_CACHE: dict = {}


def state_layout_cached(model):
    key = (model.n_balls, model.n_modes)
    if key not in _LAYOUT_CACHE:
        _LAYOUT_CACHE[key] = M.state_layout(model)
    return _LAYOUT_CACHE[key]


def film_thickness(model, wc: np.ndarray) -> dict:
    """Minimum and central film thickness per contact (Hamrock & Dowson 1977, flexbearing.multibody.film), m,
    at the current load, entrainment speed and radii, viscosity at the oil temperature. Zero
    where there is no load."""
    p = model.p
    z = wc.shape[0]
    hmin = np.zeros((z, 3))
    hc = np.zeros((z, 3))
    _film_per_contact(wc, p[P_EBR], p[P_ETA0], p[M.P_ALPHA_P], hmin, hc)
    return {"film_thickness_min": hmin, "film_thickness_central": hc}


@njit(cache=True)
def _film_per_contact(wc, E_eff, eta0, alpha_p, hmin, hc):
    """`film_thickness` over every loaded contact in one compiled call (a sample evaluates 60)."""
    for j in range(wc.shape[0]):
        for c in range(3):
            if wc[j, c, WC_Q] > 0.0 and wc[j, c, WC_RX] > 0.0:
                hmin[j, c], hc[j, c] = hd(wc[j, c, WC_RX], wc[j, c, WC_RY], E_eff, wc[j, c, WC_Q],
                                          wc[j, c, WC_UR], eta0, alpha_p)
