"""3-D rod shapes (directors and extensible centreline) of computed orbits: PNG views and a centreline CSV."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..core.io import atomic_write_text, ensure_writable_dir, load_orbit_file
from ..orbits import rod_from_orbit as from_orbit
from .common import atomic_savefig, pyplot


def rod_from_orbit_file(path, n: int = 3001) -> dict:
    """magrod.orbits.rod.from_orbit of an orbit .npz written by `magrod multipulse` (validated by io.load_orbit_file)."""
    return from_orbit(load_orbit_file(path), n)


def magnification(r: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """Transverse magnification for drawing a long, slender localised rod: (factor, chord unit vector u,
    transverse displacements r_perp from the chord through the end points).  The factor is the 1-2-5 number
    at or below length / (4 max|r_perp|), at least 1: the magnified excursions then span about a quarter of
    the length, so the pulses are visible next to the (true-scale) straight tails."""
    d = r - r[0]
    chord = d[-1]
    L = float(np.linalg.norm(chord))
    u = chord / L if L > 0 else np.array([0.0, 0.0, 1.0])
    perp = d - np.outer(d @ u, u)
    amp = float(np.max(np.linalg.norm(perp, axis=1)))
    if amp <= 0 or L <= 0:
        return 1.0, u, perp
    target = L / (4.0 * amp)
    if target <= 1:
        return 1.0, u, perp
    e = 10.0 ** math.floor(math.log10(target))
    factor = max(m * e for m in (1, 2, 5) if m * e <= target)
    return float(factor), u, perp


def plot_rod(rod: dict, out_dir, stem: str, title: str = "",
             scale: str = "lengths in units of B/m3 (B = C = m3 = 1), z along the field") -> list[str]:
    """Rod picture (PNG) and centreline CSV (s, x, y, z).  Panels: the true-scale 3-D view (equal axes over the
    whole length: a localised rod looks nearly straight), the same centreline with the transverse displacements
    from the end-to-end chord magnified by a stated factor (`magnification`; drawn as a thick tube coloured by
    arclength), the magnified side view (along-chord vs transverse) and the view along the chord (equal
    scales, zoomed)."""
    plt = pyplot()
    out_dir = ensure_writable_dir(out_dir)
    r = rod["r"]
    c = 0.5 * (r.max(0) + r.min(0))
    half = 0.5 * float(np.max(r.max(0) - r.min(0))) * 1.05
    M, u, perp = magnification(r)
    along = (r - r[0]) @ u
    rm = r[0] + np.outer(along, u) + M * perp  # magnified centreline
    s = rod["s"]
    fig = plt.figure(figsize=(12, 9))
    ax = fig.add_subplot(2, 2, 1, projection="3d")
    ax.plot(r[:, 0], r[:, 1], r[:, 2], "k-", lw=1)
    ax.set_xlim(c[0] - half, c[0] + half)
    ax.set_ylim(c[1] - half, c[1] + half)
    ax.set_zlim(c[2] - half, c[2] + half)
    ax.set_box_aspect((1, 1, 1))
    ax.set_title("true scale (equal axes)", fontsize=9)
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z (field)")
    ax = fig.add_subplot(2, 2, 2, projection="3d")
    cm = 0.5 * (rm.max(0) + rm.min(0))
    hm = 0.5 * float(np.max(rm.max(0) - rm.min(0))) * 1.05
    ax.scatter(rm[:, 0], rm[:, 1], rm[:, 2], c=s, cmap="viridis", s=6, depthshade=False)
    ax.plot(rm[:, 0], rm[:, 1], rm[:, 2], "k-", lw=0.4)
    ax.set_xlim(cm[0] - hm, cm[0] + hm)
    ax.set_ylim(cm[1] - hm, cm[1] + hm)
    ax.set_zlim(cm[2] - hm, cm[2] + hm)
    ax.set_box_aspect((1, 1, 1))
    ax.set_title(f"transverse displacements (from the end-to-end chord) magnified x{M:g}", fontsize=9,
                 color="tab:red")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z (field)")
    e1 = perp[np.argmax(np.linalg.norm(perp, axis=1))]
    e1 = e1 / (np.linalg.norm(e1) or 1.0)
    e2 = np.cross(u, e1)
    a2 = fig.add_subplot(2, 2, 3)
    a2.plot(along, M * (perp @ e1), "k-", lw=1.2, label="transverse 1")
    a2.plot(along, M * (perp @ e2), "-", color="tab:blue", lw=0.8, label="transverse 2")
    a2.set_aspect("equal")
    a2.set_xlabel("along the chord")
    a2.set_ylabel(f"transverse x{M:g}")
    a2.set_title(f"side view, transverse axis magnified x{M:g}", fontsize=9, color="tab:red")
    a2.legend(fontsize=7)
    a3 = fig.add_subplot(2, 2, 4)
    a3.plot(perp @ e1, perp @ e2, "k-", lw=1)
    a3.set_aspect("equal")
    a3.set_title("looking along the chord (true scale, zoomed)", fontsize=9)
    a3.set_xlabel("transverse 1")
    a3.set_ylabel("transverse 2")
    fig.suptitle(title + f"\n{scale}; right and bottom-left panels: transverse scale x{M:g}", fontsize=9)
    fig.tight_layout()
    png = atomic_savefig(fig, Path(out_dir) / f"{stem}_rod.png", dpi=120)
    plt.close(fig)
    lines = ["s,x,y,z"] + [f"{si:.17g},{a:.17g},{b:.17g},{z:.17g}" for si, (a, b, z) in zip(s, r)]
    csv = atomic_write_text(Path(out_dir) / f"{stem}_centreline.csv", "\n".join(lines) + "\n")
    return [str(png), str(csv)]
