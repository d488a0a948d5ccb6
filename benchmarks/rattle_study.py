"""The balls' rattle of the paper's steady scene at the design clearance (issue 46, item 1;
docs/design_clearance_rattle.md).

Writes short-window variants of scenes/paper_steady_rigid.toml (0.12 s, dense output every 20 µs),
runs them, and reads from each: the integrator's steps, the balls' radial/axial velocity p99 after
0.05 s, the third contact's (inner_right) closed fraction and peak load, contact-stress statistics,
the spectral peak of the balls' motion, the envelope of the whirl's band (BAND: growth, then saturation)
and the mode shape (phase of every ball at the peak, direction of motion in the ball's plane, the
inner ring's tilt and radial amplitude). `soft_mode` is the analytic estimate of the mode.

    python benchmarks/rattle_study.py run [--variants base,fr0,...] [--dir out/rattle]
    python benchmarks/rattle_study.py analyse [--variants ...] [--dir out/rattle]
    python benchmarks/rattle_study.py estimate
    python benchmarks/rattle_study.py tilt --variants base --window 0.018:0.036

Variants (VARIANTS): the scene as it is (base); Fr = 0 (ball-pass excitation through the radial
load); pocket diameter 23.0 mm instead of 22.5 (pocket impacts); integrator tolerance 1e-6 and the
Bogacki–Shampine 3(2) method (the integrator); contact damping ratio 0 and 0.2 (the model's normal
damping); transverse traction off, the EHL law at film strength 1 and 0.5, traction off (the
traction–spin coupling); inner ring +10 kg (the ring's share in the mode) and +1000 kg (the ring in
effect held); the clearance the inner
ring's centrifugal growth leaves at 14,000 rpm (32 um).
"""
from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "scenes" / "paper_steady_rigid.toml"

# name -> dict(fr, tol, method, cage, model, bearing): overrides of the scene; band: the frequency band
# (Hz) of the growth envelope where the mode is not the base's 1.3–1.9 kHz
VARIANTS = {
    "base": {},
    "fr0": {"fr": 0.0},
    "pocket_23mm": {"cage": "pocket_diameter = 23.0e-3"},
    "tol_1e-6": {"tol": 1e-6},
    "bs32": {"method": "bs32"},
    "zeta_0": {"model": "damping_ratio = 0.0"},
    "zeta_0.2": {"model": "damping_ratio = 0.2"},
    "transverse_off": {"model": "transverse_traction = false"},
    "ehl": {"model": 'traction_law = "ehl"'},
    "ehl_half": {"model": 'traction_law = "ehl"\ntraction_scale = 0.5'},
    "traction_off": {"model": "traction = false"},
    "ring_plus_10kg": {"model": "inner_ring_added_mass = 10.0", "band": (400.0, 900.0)},
    "ring_plus_1000kg": {"model": "inner_ring_added_mass = 1000.0", "band": (3800.0, 4600.0)},  # the ring in effect held
    # the design clearance less twice the inner ring's centrifugal growth at 14,000 rpm (28.1 um
    # radial by the external code of docs/equilibrium_check.md; the model has no ring growth)
    "clearance_32um": {"bearing": "radial_clearance = 32.2e-6"},
}
DURATION, SAMPLE = 0.12, 2e-5
WINDOW_START = 0.05          # s: statistics after the growth (the band saturates by ~0.04 s)


def scene_text(name: str, v: dict) -> str:
    """The scene file of a variant: the paper steady scene with the overrides of `v`."""
    s = SCENE.read_text()
    s = s.replace('name = "paper_steady_rigid"', f'name = "{name}"')
    s = s.replace("duration = 0.6 ", f"duration = {DURATION} ")
    s = s.replace("duration = 0.6,", f"duration = {DURATION},")
    s = s.replace("radial_load = 4e3 ", f"radial_load = {v.get('fr', 4e3)} ")
    s = s.replace("tolerance = 1e-4", f"tolerance = {v.get('tol', 1e-4)}" +
                  (f'\nmethod = "{v["method"]}"' if "method" in v else ""))
    s = s.replace("sample_interval = 1e-4 ", f"sample_interval = {SAMPLE} ")
    s = s.replace('record = ["contact_stress", "ball_loads", "contact_angles", "pocket_force", "guiding_force",\n'
                  '          "cage_speed", "slip", "film_thickness", "cage_orbit", "power_loss", "kinematics"]',
                  'record = ["contact_stress", "ball_loads", "contact_angles", "pocket_force", "cage_speed", "kinematics"]')
    s = s.replace("checkpoint_every = 200 ", "checkpoint_every = 100000 ")
    if "bearing" in v:
        s = s.replace("[bearing]            # paper preset (flexbearing.multibody.bearing.PAPER_BEARING); only overrides go here",
                      "[bearing]\n" + v["bearing"])
    if "cage" in v:
        s = s.replace('model = "rigid"', 'model = "rigid"\n' + v["cage"])
    if "model" in v:
        s += "\n[model]\n" + v["model"] + "\n"
    if f"duration = {DURATION}" not in s or "kinematics" not in s:
        raise RuntimeError("scenes/paper_steady_rigid.toml changed: update rattle_study.scene_text")
    return s


def run(names, directory: Path) -> None:
    directory.mkdir(parents=True, exist_ok=True)
    for name in names:
        path = directory / f"{name}.toml"
        path.write_text(scene_text(name, VARIANTS[name]))
        subprocess.run([sys.executable, "-m", "flexbearing", "run", str(path), "-o", str(directory / f"{name}.h5")],
                       check=True, stdout=subprocess.DEVNULL)


def band_envelope(t, y, lo=1300.0, hi=1900.0, window=2e-3):
    """RMS over balls and `window` of y band-passed to [lo, hi] Hz (FFT mask): (times, envelope)."""
    dt = t[1] - t[0]
    y = y - y.mean(axis=0)
    f = np.fft.rfftfreq(len(y), dt)
    Y = np.fft.rfft(y, axis=0)
    Y[(f < lo) | (f > hi)] = 0.0
    b = np.fft.irfft(Y, n=len(y), axis=0)
    n = int(round(window / dt))
    starts = range(0, len(t) - n, n)
    return np.array([t[k] for k in starts]), np.array([math.sqrt(float(np.mean(b[k:k + n] ** 2))) for k in starts])


def growth_rate(t, env, hi=0.5):
    """Exponential growth rate (1/s) of the envelope: a straight-line fit of log(env) over the last
    monotonic rise that ends where the envelope first reaches hi·(its largest value); nan if none."""
    final = float(np.max(env))
    above = np.nonzero(env >= hi * final)[0]
    if len(above) == 0 or above[0] < 3:
        return float("nan")
    i1 = int(above[0])
    i0 = i1
    while i0 > 0 and env[i0 - 1] < env[i0]:
        i0 -= 1
    if i1 - i0 < 3:
        return float("nan")
    return float(np.polyfit(t[i0:i1 + 1], np.log(env[i0:i1 + 1]), 1)[0])


BAND = (1300.0, 1900.0)      # Hz: the whirl while it grows (1.55–1.65 kHz), before the third contact detunes it


def analyse_run(path: Path, band=BAND) -> dict:
    import h5py
    summ = json.loads(path.with_suffix(".summary.json").read_text())
    with h5py.File(path, "r") as f:
        o = f["outputs"]
        t = o["time"][:]
        m = t >= WINDOW_START
        vr, vx = o["ball_radial_velocity"][:], o["ball_axial_velocity"][:]
        q, s = o["contact_load"][:][m], o["contact_stress"][:][m]
        tilt, ring = o["inner_ring_tilt"][:][m], o["inner_ring_position"][:][m]
    dt = t[1] - t[0]
    y = vx[m] - vx[m].mean(axis=0)
    P = (np.abs(np.fft.rfft(y * np.hanning(len(y))[:, None], axis=0)) ** 2).mean(axis=1)
    fr = np.fft.rfftfreq(len(y), dt)
    k = int(np.argmax(np.where(fr > 300.0, P, 0.0)))
    f0 = float(fr[k])
    tm = t[m]
    e = np.exp(-2j * math.pi * f0 * tm)
    ph = 2.0 * (y * e[:, None]).mean(axis=0)
    yr = vr[m] - vr[m].mean(axis=0)
    phr = 2.0 * (yr * e[:, None]).mean(axis=0)
    ratio = float(np.mean(phr / ph).real)          # radial over axial velocity amplitude, in phase or not
    direction = math.degrees(math.atan2(ratio, 1.0)) % 180.0   # from +x towards +r
    te, env = band_envelope(t, vx, *band)
    ring_amp = [abs(2.0 * ((c - c.mean()) * e).mean()) for c in (ring[:, 1], ring[:, 2])]
    tilt_amp = [abs(2.0 * ((c - c.mean()) * e).mean()) for c in (tilt[:, 0], tilt[:, 1])]
    return dict(run=path.stem, steps=summ["n_steps"], rejected=summ["n_rejected"],
                radial_velocity_p99=float(np.percentile(np.abs(vr[m]), 99)),
                axial_velocity_p99=float(np.percentile(np.abs(vx[m]), 99)),
                third_closed_fraction=float(np.mean(q[:, :, 2] > 0)), third_max_N=float(q[:, :, 2].max()),
                outer_stress_mean_MPa=float(s[:, :, 0].mean() / 1e6), outer_stress_max_MPa=float(s[:, :, 0].max() / 1e6),
                inner_stress_max_MPa=float(s[:, :, 1:].max() / 1e6),
                peak_Hz=f0, phase_step_deg=float(np.degrees(np.angle(np.mean(ph[1:] / ph[:-1])))),
                motion_direction_deg=direction,
                band_envelope=[float(v) for v in env[::5]], growth_rate_per_s=growth_rate(te, env),
                ring_radial_amplitude_um=[a * 1e6 for a in ring_amp], ring_tilt_amplitude_urad=[a * 1e6 for a in tilt_amp],
                mean_loads_N=[float(v) for v in q.mean(axis=(0, 1))])


def ring_tilt_peak(path: Path, t0: float, t1: float) -> float:
    """Spectral peak (Hz, fixed frame, > 200 Hz) of the inner ring's tilt about y in [t0, t1): the
    whirl's frequency while it grows (docs: 0.018–0.036 s for the base, 0.03–0.08 s for +10 kg)."""
    import h5py
    with h5py.File(path, "r") as f:
        t = f["outputs"]["time"][:]
        y = f["outputs"]["inner_ring_tilt"][:][:, 0]
    m = (t >= t0) & (t < t1)
    y = y[m] - y[m].mean()
    n = 16 * len(y)                                  # zero padding: a finer grid, not more resolution
    spec = np.abs(np.fft.rfft(y * np.hanning(len(y)), n=n))
    f = np.fft.rfftfreq(n, t[1] - t[0])
    return float(f[f > 200.0][np.argmax(spec[f > 200.0])])


def soft_mode(q_outer: float, q_inner: float, soft_direction_deg: float, added_mass: float = 0.0,
              speed_rpm: float = 14000.0, bearing=None) -> dict:
    """Analytic estimate of the rattle's mode (docs/design_clearance_rattle.md, "The mode").

    A ball between two concave grooves whose normals nearly line up is held across the contact line
    only by the grooves' curvature: a normal load Q through a groove centre at distance
    (f − 1/2)·Dw turns with the ball, k = Q/((f − 1/2)·Dw) per contact (the geometric stiffness of a
    loaded two-force member). One ball between fixed grooves: f = sqrt((k_o + k_i)/m_b)/(2·pi).
    The inner ring's conical whirl: the ring tilts by theta and moves radially by w so that every
    inner groove centre moves along the balls' soft direction s = (cos phi, sin phi) (x, r) by
    q·cos(psi_j): theta = cos(phi)·q/R, w = sin(phi)·q, R the groove-centre radius. The ring's
    generalised mass is I_d·(cos phi/R)² + m_r·sin² phi; the balls b_j = b·cos(psi_j) give Z/2
    times m_b, k_o (to the outer ring) and k_i (to the inner ring). Two whirl planes with the
    ring's gyroscopic coupling I_p·Omega·(cos phi/R)² split it into backward and forward whirl.
    Ring mass and inertia as flexbearing.multibody.model (annulus to dm − Dw/2, 15 % off)."""
    from flexbearing.multibody.bearing import PAPER_BEARING
    b = PAPER_BEARING if bearing is None else bearing
    dw, dm, z, mb = b.ball_diameter, b.pitch_diameter, b.n_balls, b.ball_mass
    ko, ki = q_outer / ((b.fe - 0.5) * dw), q_inner / ((b.fi - 0.5) * dw)
    ro, ri, w = 0.5 * (dm - 0.5 * dw), 0.5 * b.bore_diameter, b.width
    mr = 0.85 * b.ring_material.density * math.pi * (ro ** 2 - ri ** 2) * w + added_mass
    i_d, i_p = mr * (3.0 * (ro ** 2 + ri ** 2) + w ** 2) / 12.0, 0.5 * mr * (ro ** 2 + ri ** 2)
    big_r = 0.5 * dm + (b.fi - 0.5) * dw * math.cos(b.shim_angle) - 0.5 * b.radial_clearance
    c, s = math.cos(math.radians(soft_direction_deg)), math.sin(math.radians(soft_direction_deg))
    n = 0.5 * z
    m_ring = i_d * (c / big_r) ** 2 + mr * s ** 2
    M = np.diag([n * mb, m_ring] * 2)
    kp = np.array([[n * (ko + ki), -n * ki], [-n * ki, n * ki]])
    K = np.zeros((4, 4))
    K[:2, :2] = K[2:, 2:] = kp
    G = np.zeros((4, 4))
    G[1, 3] = i_p * speed_rpm * math.pi / 30.0 * (c / big_r) ** 2
    G[3, 1] = -G[1, 3]
    A = np.block([[np.zeros((4, 4)), np.eye(4)], [-np.linalg.solve(M, K), -np.linalg.solve(M, G)]])
    whirl = sorted({round(abs(v.imag) / (2.0 * math.pi), 1) for v in np.linalg.eigvals(A)})
    plane = np.sqrt(np.sort(np.linalg.eigvals(np.linalg.solve(M[:2, :2], kp)).real)) / (2.0 * math.pi)
    return dict(single_ball_Hz=math.sqrt((ko + ki) / mb) / (2.0 * math.pi), k_outer=ko, k_inner=ki,
                ring_mode_Hz=float(plane[0]), whirl_Hz=whirl[:2], ring_mass=mr)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", choices=("run", "analyse", "estimate", "tilt"))
    ap.add_argument("--window", default="0.018:0.036", help="tilt: T0:T1 (s) of the growth")
    ap.add_argument("--variants", default=",".join(VARIANTS))
    ap.add_argument("--dir", default="out/rattle")
    a = ap.parse_args(argv)
    names = a.variants.split(",")
    if a.what == "run":
        run(names, Path(a.dir))
    elif a.what == "analyse":
        for name in names:
            print(json.dumps(analyse_run(Path(a.dir) / f"{name}.h5", VARIANTS[name].get("band", BAND))))
    elif a.what == "tilt":
        t0, t1 = (float(v) for v in a.window.split(":"))
        for name in names:
            print(name, f"{ring_tilt_peak(Path(a.dir) / f'{name}.h5', t0, t1):.0f} Hz")
    else:
        # mean loads of the base run after 0.05 s (analyse: mean_loads_N) and its direction of motion
        print(json.dumps(soft_mode(5705.0, 4344.0, 150.3)))
        print(json.dumps(soft_mode(5705.0, 4344.0, 150.3, added_mass=10.0)))


if __name__ == "__main__":
    main()
