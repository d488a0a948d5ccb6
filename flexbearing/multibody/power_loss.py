"""Where the bearing's power goes: friction torque, power loss by source and the power balance.

Every dissipative force of the model is an action–reaction pair between two bodies (ball and race,
ball and pocket, cage and guide land, ball and the oil–air mixture at rest). The power a source
dissipates is minus the power of its pair, summed over both bodies,

    P_s = −Σ_bodies (F·v + M·w)        (v at the point of action, w the body's angular velocity),

which `flexbearing.multibody.dynamics.rhs` evaluates with the forces it applies (work columns WC_P_*, W_P_*,
WR_P_*). The sources:

    traction      sliced EHL traction of each race contact: Σ_slices τ·Δu = T_t·du0 − M_n·du1 + T_tau·dv
                  (rolling-direction sliding, spin and transverse sliding; dynamics._race)
    rolling       EHL rolling resistance F_R at the contact and pressure rolling force F_H through
                  the ball centre (flexbearing.multibody.drag); in pure rolling on the fixed outer race F_H·v_centre
    damping       viscous damping of the race contacts, (Q − Q_el)·d(delta)/dt
    pocket        lubricated pocket (Poiseuille rolling, Couette sliding, Coulomb friction) and its
                  damping, on the ball and the cage pocket
    churning      drag of the oil–air mixture on the orbiting balls, −F_d·v, and with the option
                  ball_drag_moment its moment on the spinning balls, c·|w|²
    guide_land    short-bearing film force and Petroff torque of the guide lands, rim friction
    cage_damping  modal damping of a flexible cage, Σ d_k·q_k'²

Power balance. The work–energy theorem of the model's equations, with E = kinetic energy + Hertz,
pocket and rim potentials + gravity − F_ext·x_ring (flexbearing.multibody.energy.mechanical_energy), the
external load held at its value at t and the ring spin prescribed:

    dE/dt = T_drive·omega_i − Σ_s P_s,     T_drive = −(moment of the races on the inner ring about X)

T_drive is what the drive must supply to hold the prescribed spin, the bearing's friction torque;
in a steady state dE/dt averages to zero and T_drive·omega_i = Σ P_s, the power loss. The balance
holds to rounding when the Hertz constant is held at a fixed angle (model option hertz_fixed_angle,
measured 1e-10 of the loss, tests/test_power_loss.py); with K(alpha) (the default) the Hertz force
is very slightly non-conservative (9e-6 of the loss at the paper case); a constrained ball attitude
(ball_attitude "outer", "inner", "jones", "no_pivot") adds the work of its constraint moments,
M_n·sigma + M_t·w_t per ball (sigma the spin on the controlling race, w_t the yaw), which no source
counts and which vanishes once the constraints hold (tests/test_ball_attitude.py, to 1e-9 of the
loss; with attitude_ring_reaction on, the gyroscopic friction pair also works on a moving ring).
`power_balance` evaluates both sides at one state; `window_power` averages recorded samples.
"""
from __future__ import annotations

import numpy as np

from flexbearing.multibody import dynamics as D
from flexbearing.multibody.energy import mechanical_energy
from flexbearing.multibody import model as M

SOURCES = ("traction", "rolling", "damping", "pocket", "churning", "guide_land", "cage_damping")


def power_by_source(work: np.ndarray, n_balls: int) -> dict:
    """Dissipated power per source, W, from a filled work array (`dynamics.rhs`).

    Race sources as (Z, 3) arrays (outer, inner-left, inner-right), pocket and churning as (Z,),
    guide_land and cage_damping as floats."""
    z = n_balls
    wc = work[:z, : 3 * M.N_WC].reshape(z, 3, M.N_WC)
    return {
        "traction": wc[:, :, M.WC_P_TRACTION].copy(),
        "rolling": wc[:, :, M.WC_P_ROLLING].copy(),
        "damping": wc[:, :, M.WC_P_DAMPING].copy(),
        "pocket": work[:z, M.W_P_POCKET].copy(),
        "churning": work[:z, M.W_P_CHURNING].copy(),
        "guide_land": float(work[z, M.WR_P_LAND]),
        "cage_damping": float(work[z, M.WR_P_STRUCTURAL]),
    }


def drive_torque(work: np.ndarray, n_balls: int) -> float:
    """T_drive = −(moment of the races on the inner ring about X), N·m (module docstring)."""
    return float(-work[n_balls, M.WR_RING_TORQUE])


def power_balance(model, t: float, y: np.ndarray, speed_table, load_table, impacts,
                  h: float = 1e-8) -> dict:
    """Both sides of the energy theorem at the state (t, y) (module docstring), W.

    energy_rate = dE/dt along the motion, the central difference (E(y + h·y') − E(y − h·y'))/(2h)
    of energy.mechanical_energy at fixed t (the external load's potential −F(t)·x is part of E,
    so the load's own power needs no separate term); drive_power = T_drive·omega_i; loss = Σ P_s;
    residual = energy_rate − (drive_power − loss). h = 1e-8 s: the state moves by ~1 nm, the
    difference's truncation (h²·E''') and rounding (1e-16·E/h) errors are both ~1e-8 of the loss.
    Returns {"sources": power_by_source, "loss", "drive_torque", "drive_power", "energy_rate",
    "residual"}.
    """
    z = model.n_balls
    work = D.new_work(model)
    dydt = np.zeros_like(y)
    D.rhs(t, y, dydt, model.p, model.flags, model.hertz_table, model.traction_table, speed_table,
          load_table, impacts, work, model.cage)
    # mechanical_energy reuses the cage's scratch arrays: read everything from work first
    sources = power_by_source(work, z)
    torque = drive_torque(work, z)
    omega_i = float(work[z, M.WR_OMEGA_I])

    def energy(state):
        ek, ev = mechanical_energy(t, state, model.p, model.flags, model.hertz_table, load_table,
                                     impacts, model.cage)
        return ek + ev

    rate = (energy(y + h * dydt) - energy(y - h * dydt)) / (2.0 * h)
    loss = total_loss(sources)
    drive = torque * omega_i
    return {"sources": sources, "loss": loss, "drive_torque": torque, "drive_power": drive,
            "energy_rate": rate, "residual": rate - (drive - loss)}


def total_loss(sources: dict) -> float:
    """Σ over the sources and their contacts of the dissipated power, W."""
    return float(sum(np.sum(sources[s]) for s in SOURCES))


# ---------------------------------------------------------------- recorded samples
# The datasets of the sources' power, which a run records for the scene output "power_loss"
# (flexbearing.multibody.output_registry)
RECORDED = {"traction": "power_loss_traction", "rolling": "power_loss_rolling",
            "damping": "power_loss_contact_damping", "pocket": "power_loss_pocket",
            "churning": "power_loss_churning", "guide_land": "power_loss_guide_land",
            "cage_damping": "power_loss_cage_damping"}

# report rows: (label, key); race sources split into the outer race and the two inner halves
BREAKDOWN = (("EHL traction, outer race", "traction_outer"), ("EHL traction, inner race", "traction_inner"),
             ("EHL rolling resistance, outer race", "rolling_outer"),
             ("EHL rolling resistance, inner race", "rolling_inner"),
             ("Race contact damping", "damping"), ("Ball–pocket (lubricant, damping)", "pocket"),
             ("Churning drag of the balls", "churning"), ("Cage guide land (film, rim)", "guide_land"),
             ("Cage structural damping", "cage_damping"))


def window_power(t: np.ndarray, data: dict) -> dict:
    """Window means of the recorded power datasets (samples t, data[name] arrays along t), W.

    Returns the mean of each BREAKDOWN key, "loss" (their sum), "drive_torque" (N·m),
    "drive_power", "load_power" (mean F_ext·v_ring), "energy_rate" = (E_last − E_first)/(t_last −
    t_first) from the recorded mechanical energy (kinetic + potentials, without the load's
    potential; None without it or with one sample) and "residual" = drive_power + load_power −
    loss − energy_rate: the sampled form of the energy theorem, its size is the sampling error of
    the window means plus what the module docstring lists.
    """
    t = np.asarray(t, dtype=float)
    if t.size == 0:
        raise ValueError("window_power: the window has no samples")
    out = {}
    for src, name in RECORDED.items():
        a = np.asarray(data[name], dtype=float)
        if a.ndim == 3:                                   # (n, Z, 3): outer, inner halves
            if src in ("traction", "rolling"):
                out[f"{src}_outer"] = float(a[:, :, 0].sum(axis=1).mean())
                out[f"{src}_inner"] = float(a[:, :, 1:].sum(axis=(1, 2)).mean())
            else:
                out[src] = float(a.sum(axis=(1, 2)).mean())
        elif a.ndim == 2:
            out[src] = float(a.sum(axis=1).mean())
        else:
            out[src] = float(a.mean())
    out["loss"] = float(sum(out[k] for _, k in BREAKDOWN))
    out["drive_torque"] = float(np.mean(data["ring_drive_torque"]))
    out["drive_power"] = float(np.mean(np.asarray(data["ring_drive_torque"]) * np.asarray(data["inner_ring_speed"])))
    lp = data.get("external_load_power")
    out["load_power"] = float(np.mean(lp)) if lp is not None else 0.0
    e = data.get("mechanical_energy")
    if e is not None and t.size > 1 and t[-1] > t[0]:
        e = np.asarray(e, dtype=float)
        out["energy_rate"] = float((e[-1] - e[0]) / (t[-1] - t[0]))
        out["residual"] = out["drive_power"] + out["load_power"] - out["loss"] - out["energy_rate"]
    else:
        out["energy_rate"] = None
        out["residual"] = None
    return out
