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
from flexbearing.analysis.stress_picture import cage_skin, draw_unrolled_cage

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
    faces, wall, j = skin["faces"], skin["wall"], skin["pocket"]
    on = np.any(faces == worst, axis=1)
    hot = int(j[on & wall][0]) if (on & wall).any() else int(j[on][0]) if on.any() else 0

    plt = plot_style()
    cmap = plt.get_cmap("magma_r")
    norm = Normalize(top - DECADES, top)
    fig, gs, axes, theta, r = draw_unrolled_cage(plt, rc, skin, val, norm, cmap, worst, hot,
                                                 "the worst node's pocket", "pocket numbers on top", "c")
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
