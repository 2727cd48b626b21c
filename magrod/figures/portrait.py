"""Pictures of many orbits: section portraits coloured by a chaos indicator, and orbit diagrams.

plot_portrait(res, ax=None)          SectionPortrait.plot: every orbit's section points, coloured by its indicator
plot_orbit_diagram(res, ax=None)     OrbitDiagram.plot: the section coordinate against the parameter, marks
build(out_dir, *, quick=False, progress=False) -> list[str]
    The `magrod reproduce` orbit diagram: lambdabar from 0.12 to 0.2 at Figure 4's start (h = 0.9, theta0 = 0.1,
    pbar_theta0 = 0.5), the four panels of fig:poincare1 marked, with the growth exponent of each orbit's start;
    writes orbitdiagram.png, .npz and the sidecar orbitdiagram.json (read by the report).
save_portrait / save_orbit_diagram   files of the CLI (npz + json + png, atomically)
"""
from __future__ import annotations

import numpy as np

from ..core.io import atomic_savez, atomic_write_json, ensure_writable_dir, versions
from ..paper import PANELS
from ..core.progress import bar
from ..core.tolerances import THRESHOLD_XTOL
from .common import LABELS, atomic_savefig, pyplot

# the reproduce diagram: (number of lambdabar values, iterates per value, indicator time) full and --quick
REPRODUCE = {False: (200, 500, 3000.0), True: (41, 150, 1000.0)}
RANGE = (0.12, 0.2)
PANEL_T = 3000.0  # indicator time of the four marked panels (Fig 4(a) is sticky: T <= 2000 is marginal)


def _norm(vmax, threshold):
    from .chaos import growth_norm

    return growth_norm(vmax, threshold)


def draw_portrait(ax, res, title=None):
    cmap = pyplot().get_cmap("viridis")
    vals = res.values
    ok = np.isfinite(vals)
    if res.indicator == "growth_exponent" and ok.any():
        norm = _norm(float(np.max(vals[ok])), res.threshold)
    else:
        from matplotlib.colors import Normalize

        norm = Normalize(float(np.min(vals[ok])) if ok.any() else 0.0, float(np.max(vals[ok])) if ok.any() else 1.0)
    for r, v in zip(res.orbits, vals):
        color = cmap(norm(v)) if np.isfinite(v) else "0.5"
        ax.plot(r.points[:, 0], r.points[:, 2], ",", color=color, rasterized=True)
    ax.set_xlim(0.0, np.pi)
    ax.set_xlabel(LABELS["theta"])
    ax.set_ylabel(LABELS["ptheta"])
    if res.indicator is not None and ok.any():
        from matplotlib.cm import ScalarMappable

        cb = ax.figure.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=ax)
        cb.set_label(res.indicator.replace("_", " ") + (f" (T = {res.t_indicator:g}; chaotic > {res.threshold:g})"
                                                        if res.indicator == "growth_exponent" else ""), fontsize=7)
    p = res.params
    ax.set_title(title or (f"{res.n_orbits} orbits on h = {res.h:g}: m={p.m:g}, $\\mu$={p.mu:g}, $\\gamma$={p.gamma:g},"
                           f" $\\delta$={p.delta:g}, $\\bar\\lambda$={p.lam:g}\nmax|$\\bar H$-h| = "
                           f"{res.max_abs_dH:.1e}"), fontsize=8)


def plot_portrait(res, ax=None, **kw):
    """SectionPortrait.plot: the orbits in (theta, pbar_theta), each coloured by its indicator (grey: none)."""
    from .plots import axes

    ax = axes(ax)
    draw_portrait(ax, res, **kw)
    return ax


def draw_orbit_diagram(ax, res, title=None, colors=None):
    y = res.coordinate_values()
    x = res.values[res.value_index]
    if colors is None or not np.isfinite(colors).any():
        ax.plot(x, y, ",", color="k", rasterized=True)
    else:
        from ..chaos import GROWTH_THRESHOLD
        from matplotlib.cm import ScalarMappable

        norm = _norm(float(np.nanmax(colors)), GROWTH_THRESHOLD)
        ax.scatter(x, y, s=0.4, c=colors[res.value_index], cmap="viridis", norm=norm, rasterized=True,
                   linewidths=0)
        cb = ax.figure.colorbar(ScalarMappable(norm=norm, cmap="viridis"), ax=ax)
        cb.set_label(f"growth exponent of the start (chaotic > {GROWTH_THRESHOLD:g})", fontsize=7)
    for label, val in res.marks.items():
        ax.axvline(val, color="tab:red", lw=0.7, ls="--")
        ax.annotate(label, (val, 1.0), xycoords=("data", "axes fraction"), xytext=(2, -10),
                    textcoords="offset points", color="tab:red", fontsize=8)
    ax.set_xlabel(LABELS.get(res.parameter, res.parameter))
    if getattr(res, "system", None) is not None and not res.system.is_paper:  # another model: its own section
        ax.set_ylabel(LABELS.get(res.coordinate, res.coordinate) + " on the model's section")
        ax.set_title(title or (f"orbit diagram of the model {res.system.model}: {res.n_values} values x "
                               f"{res.iterates} iterates from its reference state\nmax|H-h| = {res.worst_dH:.1e}"),
                     fontsize=8)
        return
    ax.set_ylabel(LABELS[res.coordinate] + " at sin$\\psi$ = 0")
    ax.set_title(title or (f"orbit diagram: {res.n_values} values x {res.iterates} iterates, h = {res.h:g}, start "
                           f"$\\theta_0$ = {res.theta0:g}, $\\bar p_{{\\theta 0}}$ = {res.ptheta0:g}\n"
                           f"max|$\\bar H$-h| = {res.worst_dH:.1e}"), fontsize=8)


def plot_orbit_diagram(res, ax=None, **kw):
    """OrbitDiagram.plot: the chosen section coordinate against the parameter, marks as dashed lines."""
    from .plots import axes

    ax = axes(ax, figsize=(7.0, 4.0))
    draw_orbit_diagram(ax, res, **kw)
    return ax


def save_portrait(res, out_dir, stem: str) -> dict:
    plt = pyplot()
    out = ensure_writable_dir(out_dir)
    paths = {"npz": str(atomic_savez(out / f"{stem}.npz", **res.arrays()))}
    fig, ax = plt.subplots(figsize=(6.0, 4.6), dpi=150, layout="constrained")
    draw_portrait(ax, res)
    paths["png"] = str(atomic_savefig(fig, out / f"{stem}.png"))
    meta = {**res.summary(), "versions": versions(), "files": dict(paths),
            "axes": "theta (horizontal) vs pbar_theta (vertical), colour: indicator of the start"}
    paths["json"] = str(atomic_write_json(out / f"{stem}.json", meta))
    return paths


def save_orbit_diagram(res, out_dir, stem: str, *, extra=None, colors=None, band=None) -> dict:
    plt = pyplot()
    out = ensure_writable_dir(out_dir)
    arrays = res.arrays()
    if colors is not None:
        arrays["indicator"] = colors
    paths = {"npz": str(atomic_savez(out / f"{stem}.npz", **arrays))}
    fig, ax = plt.subplots(figsize=(7.5, 4.4), dpi=150, layout="constrained")
    draw_orbit_diagram(ax, res, colors=colors)
    if band is not None and band[1] > band[0]:
        ax.axvspan(*band, color="0.85", zorder=0)
        ax.annotate("level not reached\nfrom this start", (0.5 * (band[0] + band[1]), 0.5),
                    xycoords=("data", "axes fraction"), ha="center", fontsize=7, color="0.3")
        ax.set_xlim(band[0], max(band[1], float(np.max(res.values))))
    paths["png"] = str(atomic_savefig(fig, out / f"{stem}.png"))
    meta = {**res.summary(), **(extra or {}), "versions": versions(), "files": dict(paths)}
    paths["json"] = str(atomic_write_json(out / f"{stem}.json", meta))
    return paths


def accessible_threshold(base="4a", parameter="lam", lo=0.12, hi=0.2, xtol=THRESHOLD_XTOL):
    """The smallest value of `parameter` in [lo, hi] at which the base panel's start reaches its level (Hbar = h
    has a real root pbar_psi), by bisection on the existence of a root (assumed monotone on [lo, hi]: checked at
    the grid values by the caller); lo if the level is reached there already."""
    from ..chaos import solve_p_psi
    from ..core.errors import ParameterError
    from ..paper import panel

    P = panel(base)

    def ok(x):
        try:
            solve_p_psi(P.params.replace(**{parameter: x}), P.h, P.theta0, P.ptheta0, P.psi0)
            return True
        except ParameterError:
            return False

    if ok(lo):
        return lo
    a, b = lo, hi
    while b - a > xtol:
        c = 0.5 * (a + b)
        a, b = (a, c) if ok(c) else (c, b)
    return b


def build(out_dir, *, quick=False, progress=False) -> list[str]:
    """The reproduce orbit diagram (module docstring).  At Figure 4's start the level h = 0.9 is reached only for
    lambdabar above ~0.1305 (Hbar(theta0, psi0, pbar_theta0, .) > 0.9 for every pbar_psi below): the values under
    that threshold have no orbit and are drawn as a grey band; the threshold is in the sidecar."""
    from ..chaos import GROWTH_THRESHOLD
    from ..paper import panel_indicators
    from .. import orbit_diagram
    from ..chaos import start_indicators

    n, iterates, t_ind = REPRODUCE[bool(quick)]
    marks = {f"4({k[1]})": PANELS[k]["vary"][1] for k in ("4a", "4b", "4c", "4d")}
    grid = np.linspace(*RANGE, n)
    lam_min = accessible_threshold("4a", "lam", *RANGE)
    values = grid[grid >= lam_min]
    with bar(values.size * iterates, "orbit diagram", progress) as update:
        od = orbit_diagram("4a", "lam", values, iterates=iterates, marks=marks, progress=update)
    ind = start_indicators(od.orbits, t_max=t_ind)
    g = np.where(ind["status"] == 0, ind["growth_exponent"], np.nan)
    # the four panels themselves, on the same footing (same start rule, same indicator time)
    pn = panel_indicators(("4a", "4b", "4c", "4d"), t_max=PANEL_T)
    chaotic = g > GROWTH_THRESHOLD
    extra = {"indicator": {"name": "growth_exponent", "t_max": t_ind, "panel_t_max": PANEL_T,
                           "threshold": GROWTH_THRESHOLD,
                           "fraction_chaotic": float(np.mean(chaotic[np.isfinite(g)])),
                           "largest_chaotic_value": float(values[chaotic].max()) if chaotic.any() else None,
                           "panels": {k: {"lam": PANELS[k]["vary"][1], "growth_exponent": v["growth_exponent"],
                                          "chaotic": v["chaotic"]} for k, v in pn.items()}},
             "range": list(RANGE), "grid_values": int(n), "accessible_from": lam_min,
             "no_orbit_values": int((grid < lam_min).sum()), "label": "fig:poincare1 (orbit diagram)"}
    paths = save_orbit_diagram(od, ensure_writable_dir(out_dir), "orbitdiagram", extra=extra, colors=g,
                               band=(RANGE[0], lam_min))
    return list(paths.values())
