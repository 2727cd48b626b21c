"""Export of the explorer's picture and data.

Per finished (or cancelled, partial) orbit: orbitNN.npz, orbitNN.json, orbitNN.png written by
magrod.figures.poincare.save_result -- the files and schema of `magrod poincare --out` (arrays of PoincareResult;
sidecar with the summary, versions, axes, section) -- with the explorer's context added to the sidecar under
"explorer" (orbit id, growth exponent and verdict, the threshold).  Plus section.png, the picture as shown (all
orbits coloured by growth exponent on the chaos map's scale, the energy-level boundary, the colour bar with the
threshold), and explore.json, the index of what was written.  Every file is written atomically.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..core.io import atomic_savefig, atomic_write_json, ensure_writable_dir, versions
from . import model


def export_orbits(app, out_dir) -> dict:
    from ..figures.poincare import save_result

    out = ensure_writable_dir(out_dir)
    files, orbits = [], []
    key = app.panel_key if _is_panel_level(app) else None
    for o in app.orbits:
        res = o.result
        if res is None or res.n_points == 0:
            continue
        stem = f"orbit{o.id:02d}"
        res.panel = key
        res.extra = {"explorer": {"orbit": o.id, "status": o.status, "threshold": app.threshold,
                                  "growth_exponent": getattr(o.indicator, "growth_exponent", None),
                                  "chaotic": getattr(o.indicator, "chaotic", None),
                                  "lyap": getattr(o.indicator, "lyap", None),
                                  "indicator_t_max": getattr(o.indicator, "t_max", None),
                                  "root_rule": "smallest root pbar_psi of Hbar = h (fig:poincare1)"}}
        paths = save_result(res, out, stem, key=key, label=None)
        files += list(paths.values())
        orbits.append({"id": o.id, "stem": stem, "n_points": res.n_points, "files": paths})
    png = section_picture(app, out / "section.png")
    files.append(str(png))
    index = atomic_write_json(out / "explore.json", {**app.summary(), "exported": orbits, "versions": versions(),
                                                     "picture": str(png)})
    files.append(str(index))
    return {"files": files, "orbits": orbits}


def _is_panel_level(app) -> bool:
    from ..core.printed import panel

    P = panel(app.panel_key)
    return P.params == app.params and P.h == app.h


def section_picture(app, path) -> Path:
    """The section as the page shows it, drawn with matplotlib for print: each branch's boundary and no-root region,
    every orbit in its growth-exponent colour, colour bar on the chaos map's scale with the threshold marked."""
    from ..figures.chaos import growth_ticks
    from ..figures.common import pyplot

    plt = pyplot()
    bounds = model.section_boundaries(app.params, app.h)
    norm, cmap = model.growth_scale(app.threshold)
    fig, ax = plt.subplots(figsize=(7.0, 5.4), layout="constrained")
    top = max(1.15 * max(float(b["pmax"].max()) for b in bounds.values()), 0.1)
    # each branch of the section with its own boundary and "no root" shading (the page's BRANCH_STYLE)
    for key, b in bounds.items():
        label = {"0": r"$\psi = 0$ ($\circ$)", "pi": r"$\psi = \pi$ ($\triangle$)"}[key]
        shade = dict(color="0.8", alpha=0.75, lw=0) if key == "0" else dict(facecolor="none", hatch="///",
                                                                            edgecolor="#a6611a", lw=0)
        ax.fill_between(b["theta"], b["pmax"], top, **shade)
        ax.fill_between(b["theta"], -top, -b["pmax"], **shade)
        style = dict(color="k", ls="-") if key == "0" else dict(color="#a6611a", ls="--")
        ax.plot(b["theta"], b["pmax"], lw=0.8, label=label + r": $\bar H = h$, no root beyond", **style)
        ax.plot(b["theta"], -b["pmax"], lw=0.8, **style)
    for o in app.orbits:
        r = o.result
        if r is None or r.n_points == 0:
            continue
        g = getattr(o.indicator, "growth_exponent", np.nan)
        colour = cmap(float(norm(min(max(g, 0.0), model.GROWTH_VMAX)))) if np.isfinite(g) else "0.3"
        br = model.branch_of(r.points[:, 1])
        for key, marker in (("0", "o"), ("pi", "^")):
            m = br == key
            ax.plot(r.points[m, 0], r.points[m, 2], marker, ms=1.2, mew=0, ls="none", color=colour, rasterized=True)
    from matplotlib.cm import ScalarMappable

    sm = ScalarMappable(norm=norm, cmap=cmap)
    cb = fig.colorbar(sm, ax=ax, ticks=growth_ticks(norm.vmax, app.threshold))
    cb.ax.axhline(app.threshold, color="k", lw=1.2)
    cb.set_label(f"growth exponent (chaotic > {app.threshold:g})", fontsize=8)
    ax.set_xlim(0, np.pi)
    ax.set_ylim(-top, top)
    ax.set_xlabel(r"$\theta$")
    ax.set_ylabel(r"$\bar p_\theta$")
    p = app.params
    ax.set_title(f"$m = {p.m:g}$, $\\mu = {p.mu:g}$, $\\gamma = {p.gamma:g}$, $\\delta = {p.delta:g}$, "
                 f"$\\bar\\lambda = {p.lam:g}$, $h = {app.h:g}$: section $\\sin\\psi = 0$, "
                 f"{sum(o.result is not None for o in app.orbits)} orbit(s)", fontsize=9)
    ax.legend(loc="upper right", fontsize=7)
    out = atomic_savefig(fig, path, dpi=150)
    plt.close(fig)
    return out


def load_export(directory) -> dict:
    """{stem: (arrays, sidecar)} of an export directory (for tests and notebooks)."""
    d = Path(directory)
    out = {}
    for j in sorted(d.glob("orbit*.json")):
        with np.load(j.with_suffix(".npz")) as z:
            arrays = {k: z[k] for k in z.files}
        out[j.stem] = (arrays, json.loads(j.read_text()))
    return out
