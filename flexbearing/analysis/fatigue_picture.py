"""A picture of the cage's fatigue damage field, unrolled (matplotlib only): the report's
`fatigue_damage.png`.

The same three panels as the von Mises picture (flexbearing.analysis.stress_picture: the outside
surface and the bore unrolled over the azimuth, and one pocket wall about its axis: here the
pocket of the worst node), coloured by log10 of the damage per hour of every mesh node
(flexbearing.analysis.cage_fatigue), over four decades below the worst node. Nodes screened out
of the count (their bound below 1e-4 of the worst damage) fall below the colour scale's floor.
The worst node is starred and labelled with its life and safety factor.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from flexbearing.analysis.plots import plot_style
from flexbearing.analysis.stress_picture import _panel, _triangles, _unroll, cage_skin

PICTURE = "fatigue_damage.png"
DECADES = 4


def write_damage_picture(result, rc, out_dir) -> Path:
    """<out_dir>/fatigue_damage.png of a CageFatigue result on its reduced cage rc."""
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    HOUR = 3600.0
    per_hour = result.damage_rate * HOUR
    worst = int(np.argmax(per_hour))
    top = math.log10(per_hour[worst]) if per_hour[worst] > 0 else 0.0
    with np.errstate(divide="ignore"):
        val = np.log10(np.maximum(per_hour, 1e-300))
    X = np.asarray(rc.vertices, dtype=np.float64)
    skin = cage_skin(rc)
    faces, wall, j, pa = skin["faces"], skin["wall"], skin["pocket"], skin["pocket_azimuth"]
    Z = len(pa)
    pitch = 2.0 * math.pi / Z
    theta0 = -0.5 * pitch
    theta = np.degrees(np.mod(np.arctan2(X[:, 2], X[:, 1]) - theta0, 2 * math.pi) + theta0)
    r = np.hypot(X[:, 1], X[:, 2])
    on = np.any(faces == worst, axis=1)
    hot = int(j[on & wall][0]) if (on & wall).any() else int(j[on][0]) if on.any() else 0

    plt = plot_style()
    cmap = plt.get_cmap("magma_r")
    norm = Normalize(top - DECADES, top)
    fig = plt.figure(figsize=(10.0, 8.4), layout="constrained")
    gs = fig.add_gridspec(3, 2, height_ratios=[1.0, 1.0, 1.25], width_ratios=[1.0, 0.5])
    axes = [fig.add_subplot(gs[0, :]), fig.add_subplot(gs[1, :]), fig.add_subplot(gs[2, 0])]
    lo = math.degrees(theta0)
    for ax, name in zip(axes[:2], ("outside", "bore")):
        tri = _triangles(faces[skin[name]])
        U, tri2 = _unroll(theta, tri, lo)
        _panel(ax, U, X[:, 0][tri2] * 1e3, tri2, val, norm, cmap)
        ax.set_xlim(lo, lo + 360.0)
        ax.set_xticks(np.arange(0.0, 360.0 + lo, 2 * math.degrees(pitch)))
        sec = ax.secondary_xaxis("top")
        sec.set_xticks(np.degrees(np.mod(pa - theta0, 2 * math.pi) + theta0), [str(p) for p in range(Z)])
        sec.tick_params(labelsize=7, length=2)
        ax.set_ylabel("Axial position x (mm)")
        ax.set_xlabel("Azimuth θ (°)")
        ax.set_title(f"{name.capitalize()} surface, unrolled; pocket numbers on top", loc="left", fontsize=9)
        ax.grid(False)
        if (on & skin[name]).any():
            ax.plot([theta[worst]], [X[worst, 0] * 1e3], marker="*", ms=14, mfc="none", mec="c", mew=1.2)
    ax = axes[2]
    tj = pa[hot]
    tri = _triangles(faces[wall & (j == hot)])
    t_n = -X[:, 1] * math.sin(tj) + X[:, 2] * math.cos(tj)
    alpha = np.degrees(np.arctan2(t_n, X[:, 0]))
    U, tri2 = _unroll(alpha, tri, -180.0)
    _panel(ax, U, r[tri2] * 1e3, tri2, val, norm, cmap)
    ax.set_xlim(-180.0, 180.0)
    ax.set_xticks(np.arange(-180.0, 181.0, 45.0))
    ax.set_xlabel("Angle about the pocket axis α (°):\n0 towards +x, 90 towards increasing θ")
    ax.set_ylabel("Radius r (mm)")
    ax.set_title(f"Wall of pocket {hot} (θ = {math.degrees(tj) % 360:.0f}°), the worst node's pocket",
                 loc="left", fontsize=9)
    ax.grid(False)
    if (on & wall & (j == hot)).any():
        ax.plot([alpha[worst]], [r[worst] * 1e3], marker="*", ms=14, mfc="none", mec="c", mew=1.2)
    cb = fig.colorbar(ScalarMappable(norm, cmap), ax=axes[:2], location="right", fraction=0.03, pad=0.01)
    cb.set_label("log10 damage per hour")
    cax = fig.add_subplot(gs[2, 1])
    cax.axis("off")
    life_h = result.life[worst] / HOUR
    cax.text(0.02, 0.5, f"★ worst node {worst}\n"
             f"damage {per_hour[worst]:.3g} per hour\nlife {life_h:.3g} h\n"
             f"safety factor {result.safety_factor[worst]:.3g}\n  (design life {result.settings.design_life / HOUR:,.0f} h)\n"
             f"x = {X[worst, 0] * 1e3:.2f} mm, θ = {theta[worst] % 360:.1f}°, r = {r[worst] * 1e3:.2f} mm\n"
             f"{result.settings.material}, {result.settings.correction}, signed von Mises",
             transform=cax.transAxes, va="center", ha="left", fontsize=9,
             bbox=dict(boxstyle="round", fc="white", ec="0.6"))
    fig.suptitle("Cage fatigue damage per hour at the run's duty cycle (Palmgren–Miner; every mesh node, "
                 "cage body frame)", fontsize=10)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    png = out_dir / PICTURE
    fig.savefig(png, dpi=120)
    plt.close(fig)
    return png
