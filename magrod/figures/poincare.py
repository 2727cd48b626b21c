"""Figures of sec. 8, Poincare sections: fig:poincare1 (Figure 4) and fig:poincare2 (Figure 5).

Each panel writes <stem>.npz (the arrays of PoincareResult), <stem>.json (its summary, versions, axes, and the
axial stretch v3 along the orbit under "stretch": poincare.orbit_stretch) and <stem>.png; the figure adds
fig4.png / fig5.png with the four panels."""
from __future__ import annotations

import numpy as np

from ..core.io import atomic_savez, atomic_write_json, ensure_writable_dir, versions
from ..paper import PANELS
from ..core.progress import bar
from .common import atomic_savefig, pictures_of, pyplot


def panel_title(key, res) -> str:
    """The panel's parameters in mathematics; its diagnostics (iterates, max |Hbar - h|) are in its sidecar and in
    the result's summary, not in the picture."""
    p = res.params
    pars = (f"$m = {p.m:g}$, $\\mu = {p.mu:g}$, $\\gamma = {p.gamma:g}$, $\\delta = {p.delta:g}$, "
            f"$\\bar\\lambda = {p.lam:g}$, $h = {res.h:g}$")
    head = f"Fig. {key[0]}({key[1]}): " if key else ""
    return f"{head}{pars}"


def marker_size(n: int) -> float:
    """Dot size (points) readable at print size: ~2 pt for a few hundred section points, down to 0.8 pt for
    10^5 (a 1-px "," marker disappears in print and in PDF viewers)."""
    return float(np.clip(2.2 - 0.35 * np.log10(max(n, 1) / 300), 0.8, 2.2))


def plot_points(ax, res, title=None):
    """theta on the horizontal axis, pbar_theta on the vertical one: the two coordinates of the section
    sin(psi) = 0 that are free at fixed h (pbar_psi follows from Hbar = h, psi is 0 or pi).  The paper's
    panels are not labelled in the source; theta-pbar_theta is the natural choice for this section."""
    ax.plot(res.points[:, 0], res.points[:, 2], ".", color="k", ms=marker_size(len(res.points)), mew=0,
            rasterized=True)
    ax.set_xlim(0.0, np.pi)
    ax.set_xlabel(r"$\theta$")
    ax.set_ylabel(r"$\bar p_\theta$")
    if title:
        ax.set_title(title, fontsize=8)


def plot_section(res, ax=None, **kw):
    """PoincareResult.plot: the section points in (theta, pbar_theta) on ax (a new figure if None)."""
    from .plots import axes

    if res.points.ndim == 2 and res.points.shape[1] != 4:  # a model's states at the crossings (not the chart)
        from .models import plot_model_section

        return plot_model_section(res, ax, **kw)
    ax = axes(ax)
    plot_points(ax, res, panel_title(res.panel, res))
    return ax


def save_result(res, out_dir, stem: str, *, key=None, label=None, formats=("png",)) -> dict:
    """Write <stem>.npz (arrays), <stem>.json (metadata, versions) and <stem>.png atomically; returns the paths."""
    plt = pyplot()
    out = ensure_writable_dir(out_dir)
    paths = {"npz": str(atomic_savez(out / f"{stem}.npz", **res.arrays()))}
    meta = {"panel": key, "label": label, **res.summary(), "versions": versions(),
            "axes": "theta (horizontal) vs pbar_theta (vertical)",
            "section": "sin(psi) = 0, direction = sign of d/dt sin(psi) at the crossing"}
    for fmt in formats:
        fig, ax = plt.subplots(figsize=(5.0, 4.2), dpi=150)
        plot_points(ax, res, panel_title(key, res))
        fig.tight_layout()
        atomic_savefig(fig, out / f"{stem}.{fmt}")
        for p in pictures_of(out / f"{stem}.{fmt}"):  # by the suffix actually written (--format pdf: .pdf)
            paths[p.suffix.lstrip(".")] = str(p)
        plt.close(fig)
    meta["files"] = dict(paths)
    paths["json"] = str(atomic_write_json(out / f"{stem}.json", meta))
    return paths


def _figure(fig_no: str, out_dir, quick=False, progress=False, iterates=None, workers=2) -> list[str]:
    from ..chaos import DEFAULT_FORMULATION, STRETCH_DT
    from ..paper import run_panels

    plt = pyplot()
    out = ensure_writable_dir(out_dir)
    n = iterates or (500 if quick else 10_000)
    keys = [f"{fig_no}{c}" for c in "abcd"]
    with bar(n * len(keys), "poincare", progress) as update:
        results = run_panels(keys, iterates=n, workers=workers, progress=update, formulation=DEFAULT_FORMULATION,
                             stretch_dt=STRETCH_DT)
    written = []
    for k in keys:
        written += list(save_result(results[k], out, f"fig{k}", key=k, label=PANELS[k]["label"]).values())
    fig = panels_figure(results, keys, fig_no, n)
    written.append(str(atomic_savefig(fig, out / f"fig{fig_no}.png")))
    plt.close(fig)
    return written


def panels_figure(results: dict, keys, fig_no: str, n: int):
    """The four panels of Figure 4 or 5 on one Figure (2 x 2).  The panels are compared with each other, so they
    share one theta range (0, pi) and one pbar_theta range (the union of the four, 4 % margin)."""
    plt = pyplot()
    # the four panels are compared with each other: one theta range (0, pi) and one pbar_theta range for all
    fig, axes = plt.subplots(2, 2, figsize=(10, 8.4), dpi=150, sharex=True, sharey=True)
    for ax, k in zip(axes.flat, keys):
        var, val = PANELS[k]["vary"]
        sym = {"lam": r"$\bar\lambda$", "gamma": r"$\gamma$"}[var]
        # the diagnostics (max |Hbar - h|, iterates) are in each panel's sidecar fig<key>.json, not in its title
        plot_points(ax, results[k], f"({k[1]}) {sym[:-1]} = {val:g}$")
    pt = np.concatenate([results[k].points[:, 2] for k in keys])
    pt = pt[np.isfinite(pt)]
    if len(pt):
        pad = 0.04 * max(float(pt.max() - pt.min()), 1e-3)
        axes.flat[0].set_ylim(float(pt.min()) - pad, float(pt.max()) + pad)  # shared: every panel gets it
    for ax in axes.flat:
        ax.label_outer()  # shared axes: tick labels once per row and column
    p = results[keys[0]].params
    common = (f"$m = {p.m:g}$, $\\mu = {p.mu:g}$, $\\gamma = {p.gamma:g}$, $\\delta = {p.delta:g}$" if fig_no == "4"
              else f"$m = {p.m:g}$, $\\delta = {p.delta:g}$, $\\bar\\lambda = {p.lam:g}$, $\\mu = {p.mu:g}$")
    fig.suptitle(f"Fig. {fig_no}: Poincaré sections $\\sin\\psi = 0$ at $h = {results[keys[0]].h:g}$ ({common}), "
                 f"{n} iterates each", fontsize=10)
    fig.tight_layout()
    return fig


def figure_4(out_dir, *, quick=False, progress=False) -> list[str]:
    """fig:poincare1: four panels (lam = 0.135, 0.1575, 0.175, 0.186), per-panel .png/.npz/.json and fig4.png.
    quick=True uses 500 iterates per panel instead of the paper's 10 000."""
    return _figure("4", out_dir, quick, progress)


def figure_5(out_dir, *, quick=False, progress=False) -> list[str]:
    """fig:poincare2: four panels (gamma = 0.15, 0.205, 0.208, 0.24), per-panel files and fig5.png."""
    return _figure("5", out_dir, quick, progress)
