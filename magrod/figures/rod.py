"""3-D rod shapes (directors and extensible centreline) of computed orbits: PNG views and a centreline CSV."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..io import atomic_savefig, atomic_write_text, ensure_writable_dir, load_orbit_file
from ..rod import from_orbit
from .common import pyplot


def rod_from_orbit_file(path, n: int = 3001) -> dict:
    """magrod.rod.from_orbit of an orbit .npz written by `magrod multipulse` (validated by io.load_orbit_file)."""
    return from_orbit(load_orbit_file(path), n)


def plot_rod(rod: dict, out_dir, stem: str, title: str = "") -> list[str]:
    """3-D view and three projections with equal axis scales (PNG), centreline CSV (s, x, y, z)."""
    plt = pyplot()
    out_dir = ensure_writable_dir(out_dir)
    r = rod["r"]
    c = 0.5 * (r.max(0) + r.min(0))
    half = 0.5 * float(np.max(r.max(0) - r.min(0))) * 1.05
    fig = plt.figure(figsize=(11, 8))
    ax = fig.add_subplot(2, 2, 1, projection="3d")
    ax.plot(r[:, 0], r[:, 1], r[:, 2], "k-", lw=1)
    ax.set_xlim(c[0] - half, c[0] + half)
    ax.set_ylim(c[1] - half, c[1] + half)
    ax.set_zlim(c[2] - half, c[2] + half)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z (field)")
    for k, (i, j, lab) in enumerate([(0, 2, "x-z"), (1, 2, "y-z"), (0, 1, "x-y, looking along the field (zoomed)")]):
        a2 = fig.add_subplot(2, 2, k + 2)
        a2.plot(r[:, i], r[:, j], "k-", lw=1)
        if k < 2:
            a2.set_xlim(c[i] - half, c[i] + half)
            a2.set_ylim(c[j] - half, c[j] + half)
        else:  # the transverse excursions are small compared with the length: zoom, still equal scales
            hz = 0.5 * float(np.max(r[:, :2].max(0) - r[:, :2].min(0))) * 1.1 + 1e-12
            a2.set_xlim(c[0] - hz, c[0] + hz)
            a2.set_ylim(c[1] - hz, c[1] + hz)
        a2.set_aspect("equal")
        a2.set_title(lab, fontsize=9)
        a2.set_xlabel("xyz"[i])
        a2.set_ylabel("xyz"[j])
    fig.suptitle(title + "\nlengths in units of B/m3 (B = C = m3 = 1), z along the field", fontsize=9)
    fig.tight_layout()
    png = atomic_savefig(fig, Path(out_dir) / f"{stem}_rod.png", dpi=120)
    plt.close(fig)
    lines = ["s,x,y,z"] + [f"{s:.17g},{a:.17g},{b:.17g},{z:.17g}" for s, (a, b, z) in zip(rod["s"], r)]
    csv = atomic_write_text(Path(out_dir) / f"{stem}_centreline.csv", "\n".join(lines) + "\n")
    return [str(png), str(csv)]
