"""Chaos-map pictures and the small map of `magrod reproduce` (drawing and writing; numerics in magrod.chaos.indicators).

build(out_dir, *, quick=False, progress=False) -> list[str]
    A lambdabar x gamma map around the Figure 4 panels (start rule of fig:poincare1) plus the indicators of the
    four Figure 4 orbits; writes chaos.png, chaos.npz and the sidecar chaos.json (read by magrod reproduce).
draw_map(fields, spec, path, *, title=None) -> Path
    PNG heat map of the growth exponent with colour bar, missing points grey, the paper's panels marked.
"""
from __future__ import annotations

import textwrap
import time
from pathlib import Path

import numpy as np

from ..chaos import AXIS_NAMES, GROWTH_THRESHOLD, MAPPABLE, OK, MapSpec, map_tiles, panel_base, parse_axis
from ..paper import panel_indicators
from ..core.io import atomic_savez, atomic_write_json, ensure_writable_dir, versions
from ..paper import PANELS
from ..core.progress import bar
from .common import atomic_savefig, label, pyplot

# the reproduce map: full and --quick sizes (grid points per axis, t_max)
REPRODUCE_GRID = {False: (24, 3000.0), True: (8, 2000.0)}
REPRODUCE_AXES = ("lam:0.12:0.2", "gamma:2.0:4.0")
PANEL_T_MAX = {False: 5000.0, True: 3000.0}


def panel_marks(spec: MapSpec) -> list[tuple]:
    """(key, x, y) of every paper panel that lies in the map's plane: its values of all non-axis parameters equal
    the map's base values and its axis values are inside the ranges."""
    marks = []
    for key in PANELS:
        v = panel_base(key)
        others = [k for k in AXIS_NAMES if k not in (spec.x.name, spec.y.name)]
        if all(np.isclose(v[k], spec.base.get(k, np.nan)) for k in others):
            x, y = v[spec.x.name], v[spec.y.name]
            if spec.x.lo <= x <= spec.x.hi and spec.y.lo <= y <= spec.y.hi:
                marks.append((key, x, y))
    return marks


FIELD_LABELS = {k: f.label for k, f in MAPPABLE.items()}
FIELD_NAMES = {k: f.name for k, f in MAPPABLE.items()}


def growth_norm(vmax: float, threshold: float):
    """Colour scale of the growth exponent that shows the chaos threshold: linear on [0, threshold] (the lower half
    of the colour map: regular, tangent growth at most a power t^p with p <= threshold), logarithmic from the
    threshold up to vmax (the upper half: chaotic, p ~ lyap T/(2 ln 2) can reach 1000).  A plain linear or
    TwoSlopeNorm scale up to ~1000 squeezes the threshold of 3 into the first percent of the bar."""
    import numpy as _np
    from matplotlib.colors import FuncNorm

    top = _np.log(max(vmax, 1.01 * threshold) / threshold)

    def forward(g):
        g = _np.asarray(g, float)
        with _np.errstate(divide="ignore", invalid="ignore"):
            hi = 0.5 + 0.5 * _np.log(_np.maximum(g, threshold) / threshold) / top
        return _np.where(g <= threshold, 0.5 * _np.clip(g, 0.0, None) / threshold, hi)

    def inverse(u):
        u = _np.asarray(u, float)
        return _np.where(u <= 0.5, 2 * u * threshold, threshold * _np.exp((2 * u - 1) * top))

    return FuncNorm((forward, inverse), vmin=0.0, vmax=max(vmax, 1.01 * threshold))


def growth_ticks(vmax: float, threshold: float) -> list:
    ticks = [0.0, threshold / 3, 2 * threshold / 3, threshold]
    for t in (10, 30, 100, 300, 1000, 3000, 10000):
        if threshold < t <= vmax:
            ticks.append(float(t))
    return ticks


def map_axes(ax, fields: dict, spec: MapSpec, *, indicator="growth", threshold=GROWTH_THRESHOLD,
             title=None, colorbar=True):
    """Draw one indicator of a map on `ax` ("growth", "fli" or "lyap"); missing points grey; the classification
    boundary growth = threshold as a contour; paper panels starred.  Returns the QuadMesh."""
    g = np.where(np.asarray(fields["status"]) == OK, fields[FIELD_NAMES[indicator]], np.nan)
    import matplotlib

    cmap = matplotlib.colormaps["RdYlBu_r" if indicator == "growth" else "magma"].with_extremes(bad="0.8")
    norm = None
    if indicator == "growth":
        vmax = max(float(np.nanmax(g)) if np.isfinite(g).any() else 2 * threshold, 2 * threshold)
        norm = growth_norm(vmax, threshold)
    im = ax.pcolormesh(spec.x.values(), spec.y.values(), np.ma.masked_invalid(g), cmap=cmap, shading="nearest",
                       norm=norm)
    inferred = np.asarray(fields["inferred"]) != 0 if "inferred" in fields else None
    if inferred is not None and inferred.any():
        # a refined map: the points never computed under a white veil, so that what was integrated and
        # what was inferred from its cell can be told apart (the class is the same; the shade is paler)
        from matplotlib.colors import ListedColormap

        ax.pcolormesh(spec.x.values(), spec.y.values(), np.ma.masked_where(~inferred, np.ones(inferred.shape)),
                      cmap=ListedColormap([(1, 1, 1, 0.55)]), shading="nearest", vmin=0, vmax=1)
    ge = np.ma.masked_invalid(np.asarray(fields["growth_exponent"], float))
    contour = None
    if spec.x.n > 1 and spec.y.n > 1 and (ge > threshold).any() and (ge <= threshold).any():
        # the classification boundary (masked where missing), whatever indicator is coloured; the colour-bar label
        # says what the line is (a drawn line nobody explains is a question for the reader)
        contour = "black" if indicator == "growth" else "cyan"
        ax.contour(spec.x.values(), spec.y.values(), ge, levels=[threshold], linewidths=0.8,
                   colors="k" if indicator == "growth" else "c")
    if colorbar:
        cb = ax.figure.colorbar(im, ax=ax, ticks=growth_ticks(norm.vmax, threshold) if norm is not None else None)
        # the label runs along the bar: wrapped to the figure's height, so that it is never cut off
        chars = max(20, int(0.8 * ax.figure.get_figheight() * 72 / (0.55 * 8)))
        nb = "\u00a0"  # no line break inside "chaotic > 3"
        if indicator == "growth":
            cb.ax.axhline(threshold, color="k", lw=1.2)
            text = f"growth exponent (chaotic{nb}>{nb}{threshold:g})"
        else:
            text = FIELD_LABELS[indicator]
        cb.set_label(textwrap.fill(text, chars), fontsize=8)
        # what the marks on the map mean: a key under the map (the colour-bar label stays one short line)
        from matplotlib.lines import Line2D
        from matplotlib.patches import Patch

        keys = [Patch(facecolor="0.8", edgecolor="0.5", lw=0.5, label="missing")]
        if inferred is not None and inferred.any():
            keys.append(Patch(facecolor=(1, 1, 1, 0.55), edgecolor="0.5", lw=0.5,
                              label=f"pale: inferred ({100 * inferred.mean():.0f} % of the points)"))
        if contour:
            keys.append(Line2D([], [], color="k" if contour == "black" else "c", lw=0.8,
                               label=f"growth exponent{nb}={nb}{threshold:g} (chaotic/regular boundary)"))
        ax.legend(handles=keys, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=len(keys), fontsize=7,
                  frameon=False, handlelength=1.5, columnspacing=1.0)
    for key, x, y in panel_marks(spec):
        ax.plot(x, y, "k*", ms=10, mec="w", label="_paper panel")
        ax.annotate(key, (x, y), textcoords="offset points", xytext=(4, 4), fontsize=9)
    ax.set_xlabel(label(spec.x.name))
    ax.set_ylabel(label(spec.y.name))
    # "name = value" never broken across lines (no-break spaces; textwrap breaks at ASCII whitespace only)
    fixed = ", ".join(f"{label(k)}\u00a0=\u00a0{v:g}" for k, v in sorted(spec.base.items())
                      if k not in (spec.x.name, spec.y.name))
    # the fixed values wrapped to the width the axes get (~70% of the figure beside the colour bar), so that the
    # title is never cut off at the figure's edge (tests/test_figure_labels.py)
    chars = max(24, int(0.7 * ax.figure.get_figwidth() * 72 / (0.6 * 8)))
    ax.set_title(title or f"chaos map, T = {spec.t_max:g}\n" + textwrap.fill(fixed, chars, break_long_words=False),
                 fontsize=8)
    return im


def draw_map(fields: dict, spec: MapSpec, path, *, indicator="growth", title=None,
             threshold=GROWTH_THRESHOLD) -> Path:
    """PNG heat map of one indicator ("growth", "fli" or "lyap") written to `path` (map_axes)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 5.0), layout="constrained")
    map_axes(ax, fields, spec, indicator=indicator, threshold=threshold, title=title)
    return atomic_savefig(fig, path, dpi=120)


def plot_map(res, ax=None, *, indicator="growth", **kw):
    """ChaosMap.plot: the map on ax (a new figure if None); returns the Axes."""
    from .plots import axes

    ax = axes(ax, figsize=(6.4, 5.0))
    map_axes(ax, res.fields, res.spec, indicator=indicator, **kw)
    return ax


def plot_lyapunov(res, ax=None, **kw):
    """LyapunovResult.plot: the finite-time exponent L(t)/t against t (log-log), the threshold line of the
    growth exponent's power law would need two samples; the verdict and growth exponent are in the title."""
    from .plots import axes

    ax = axes(ax)
    ax.loglog(res.times, np.abs(res.lyap_history), "k-", lw=1, **kw)
    ax.set_xlabel("t (scaled arclength)")
    ax.set_ylabel(r"$|\ln|w(t)|\,/\,t|$")
    where = f"panel {res.panel}" if res.panel else ", ".join(f"{k}={v:g}" for k, v in res.params.to_dict().items())
    ax.set_title(f"{where}: {'chaotic' if res.chaotic else 'regular'} (growth exponent "
                 f"{res.growth_exponent:.3g}, threshold {res.threshold:g}; $T = {res.t_max:g}$)", fontsize=8)
    return ax


def build(out_dir, *, quick=False, progress=False) -> list[str]:
    """The reproduce map (REPRODUCE_GRID) and the Figure 4 panel indicators; see the module docstring."""
    out = ensure_writable_dir(out_dir)
    n, t_max = REPRODUCE_GRID[bool(quick)]
    spec = MapSpec(parse_axis("x", f"{REPRODUCE_AXES[0]}:{n}"),
                   parse_axis("y", f"{REPRODUCE_AXES[1]}:{n}"), base=panel_base("4a"),
                   panel="4a", t_max=t_max)
    with bar(sum(t.n_points for t in map_tiles(spec)), "chaos map", progress, unit="point") as update:
        from .. import chaos_map

        res = chaos_map(spec, progress=update)
    t0 = time.perf_counter()
    panels = panel_indicators(("4a", "4b", "4c", "4d"), t_max=PANEL_T_MAX[bool(quick)])
    png = draw_map(res.fields, spec, out / "chaos.png")
    npz = atomic_savez(out / "chaos.npz", **{k: np.asarray(v) for k, v in res.fields.items()},
                       x=spec.x.values(), y=spec.y.values())
    side = atomic_write_json(out / "chaos.json", {
        "label": "fig:poincare1 (chaos map)", "spec": spec.to_dict(), "summary": res.summary(),
        "panels": panels, "panel_t_max": PANEL_T_MAX[bool(quick)], "quick": bool(quick),
        "wall_s": res.wall_s + time.perf_counter() - t0, "versions": versions()})
    return [str(png), str(npz), str(side)]


def plot_spectrum(res, ax=None, **kw):
    """LyapunovSpectrum.plot: every running exponent lambda_i(t) against t (log t), the final values in the legend."""
    from .plots import axes

    ax = axes(ax)
    for i in range(res.history.shape[1]):
        ax.plot(res.times, res.history[:, i], lw=1, label=f"$\\lambda_{i + 1}$ = {res.exponents[i]:+.3g}", **kw)
    ax.axhline(0.0, color="0.5", lw=0.6)
    ax.set_xscale("log")
    ax.set_xlabel("t (scaled arclength)")
    ax.set_ylabel(r"running exponent $\lambda_i(t)$")
    where = f"panel {res.panel}" if res.panel else (res.system.model if res.system is not None else res.control)
    ax.set_title(f"Lyapunov spectrum, {where}, T = {res.t_max:g}\nmax |lambda_i + lambda_(n+1-i)| = "
                 f"{res.accuracy['max_pairing']:.2g}, sum = {res.accuracy['sum']:.1e}", fontsize=8)
    ax.legend(fontsize=6, ncol=3)
    return ax


def plot_gali(res, ax=None, **kw):
    """GaliResult.plot: GALI_k against t, log-log (a power law is a line; an exponential decay bends down)."""
    from .plots import axes

    ax = axes(ax)
    for i, k in enumerate(res.orders):
        g = np.where(res.gali[:, i] > 0, res.gali[:, i], np.nan)
        ax.loglog(res.times, g, lw=1, label=f"GALI$_{k}$", **kw)
    ax.axhline(1e-15, color="0.5", lw=0.6, ls=":")
    ax.set_xlabel("t (scaled arclength)")
    ax.set_ylabel("GALI$_k$")
    where = f"panel {res.panel}" if res.panel else (res.system.model if res.system is not None else res.control)
    ax.set_title(f"GALI, {where}, T = {res.t_max:g} (dotted: rounding level)", fontsize=8)
    ax.legend(fontsize=7)
    return ax


def draw_spectrum(spectrum, gali_result, path) -> Path:
    """PNG of the running spectrum, and beside it GALI if given (magrod spectrum --out)."""
    plt = pyplot()
    n = 1 if gali_result is None else 2
    fig, axs = plt.subplots(1, n, figsize=(6.0 * n, 4.6), layout="constrained", squeeze=False)
    plot_spectrum(spectrum, axs[0, 0])
    if gali_result is not None:
        plot_gali(gali_result, axs[0, 1])
    return atomic_savefig(fig, path, dpi=120)
