"""Figures of localised rods across parameter space: bifurcation diagrams of symmetric homoclinic orbits (magrod.orbits.continuation) and the
Floquet data of the periodic saddle.  `build(out_dir, quick=False, progress=False) -> list[str]` writes:
  continuation_mu2lam.png/.npz/.json   the Fig 6 two-pulse orbit continued on mu = 2 lam as a curve in the
                                       (lam, m) plane; the printed m = 1.7 point (lam* of docs/errata.md) marked
  continuation_periodic.png/.npz/.json the two primary orbits to the periodic saddle at lam = 0.001 continued
                                       in mu towards mu = 2 lam (log scale in mu - 2 lam); T and launch angle
  continuation_fold.png/.npz/.json     a 2-pulse branch to the periodic saddle continued in mu across its fold
                                       (mu = 4.8614e-3), fold located and marked
Data as .npz + JSON sidecar (magrod.core.io atomic writers)."""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from ..core.io import atomic_savez, atomic_write_json, ensure_writable_dir, versions
from ..core.params import RodParams
from ..orbits import (find_periodic_multipulse, fold_summary, mu2lam_problem, on_level, periodic_problem, point_at,
                      pseudo_arclength, shoot_multipulse)
from ..paper import MULTIPULSE
from ..core.tolerances import FOLD_BRANCH_TOL
from .common import atomic_savefig, label, pyplot


def plot_branch(branch, path, title: str = ""):
    """Bifurcation diagram of one Branch: its first two unknowns (T and the second unknown of an orbit's branch; the
    first two state components that vary along a branch of equilibria) against the parameter (the last component
    of u), folds marked."""
    plt = pyplot()
    u = branch.u
    names = branch.names or (*(f"u{i}" for i in range(u.shape[1] - 1)), "par")
    shown = [j for j in range(u.shape[1] - 1) if np.ptp(u[:, j]) > 0][:2] if u.shape[1] > 3 else [0, 1]
    shown = (shown + [j for j in range(u.shape[1] - 1) if j not in shown])[:2]
    fig, axs = plt.subplots(1, 2, figsize=(9, 3.4))
    for ax, j in zip(axs, shown):
        ax.plot(u[:, -1], u[:, j], ".-", lw=1, ms=3, color="k")
        for f in branch.folds:
            if f["u"] is not None:
                ax.plot(f["u"][-1], f["u"][j], "o", mfc="none", color="r", label="fold")
        ax.set_xlabel(label(names[-1]))
        ax.set_ylabel(label(names[j]))
    axs[0].set_title(title, fontsize=7)
    fig.tight_layout()
    p = atomic_savefig(fig, Path(path), dpi=130)
    plt.close(fig)
    return p


def build(out_dir, *, quick: bool = False, progress: bool = False) -> list[str]:
    plt = pyplot()
    out = ensure_writable_dir(out_dir)
    paths = []
    # --- mu = 2 lam: Fig 6 two-pulse orbit as a curve in (lam, m)
    t0 = time.perf_counter()
    base = MULTIPULSE[6]["params"]
    lam0 = 0.0012620808  # Newton start near the Fig 6 2-pulse orbit (docs/errata.md); shoot() solves for lam
    r = shoot_multipulse(on_level(base, lam=lam0), 2)
    F, _ = mu2lam_problem(r.params, "m")
    scale = [r.T, 1e-3, 1.0]
    steps = 8 if quick else 60
    branches = []
    for d in (-1, 1):
        branches.append(pseudo_arclength(F, [r.T, r.params.lam, 1.7], scale=scale, ds=0.02, ds_max=0.1,
                                           steps=steps, par=2, direction=d, names=("T", "lam", "m"),
                                           bounds={2: (1.0, 2.8)}))
    u = np.vstack([branches[0].u[::-1], branches[1].u[1:]])
    folds = fold_summary(branches[0]) + fold_summary(branches[1])
    paths.append(str(atomic_savez(out / "continuation_mu2lam.npz", u=u)))
    paths.append(str(atomic_write_json(out / "continuation_mu2lam.json", {
        "what": "Fig 6 2-pulse orbit (fig:multimodal1) continued on mu = 2 lam in (lam, m), gamma = delta = 1",
        "columns": ["T", "lam", "m"], "folds": folds, "lam_star_at_m_1.7": r.params.lam,
        "max_residual": float(max(np.max(b.residuals) for b in branches)), "wall_time_s": time.perf_counter() - t0,
        "messages": [b.message for b in branches], "versions": versions()})))
    fig, ax = plt.subplots(figsize=(5, 3.6))
    ax.plot(u[:, 1], u[:, 2], "k-", lw=1.2, label="2-pulse symmetric orbit exists (mu = 2 lam)")
    ax.plot([r.params.lam], [1.7], "ro", label=f"Fig 6: m = 1.7, $\\bar\\lambda^*$ = {r.params.lam:.12g}")
    ax.axvline(0.001, ls=":", color="gray", label="printed lam = 0.001")
    for f in folds:
        ax.plot(f["lam"], f["m"], "bs", mfc="none")
    ax.set_xlabel(r"$\bar\lambda$  ($\mu = 2\bar\lambda$)")
    ax.set_ylabel(r"$m$")
    ax.set_title(r"codimension-one 2-pulse orbits: a curve in $(\bar\lambda, m)$; $\gamma = \delta = 1$", fontsize=8)
    ax.legend(fontsize=6)
    fig.tight_layout()
    paths.append(str(atomic_savefig(fig, out / "continuation_mu2lam.png", dpi=140)))
    plt.close(fig)
    # --- periodic saddle: the two primaries at lam = 0.001 continued in mu -> 2 lam
    t0 = time.perf_counter()
    P = RodParams(1.7, 0.0021, 1.0, 1.0, 0.001)
    prim = find_periodic_multipulse(P, 1, samples=91)
    fig, axs = plt.subplots(1, 2, figsize=(9, 3.4))
    data = {}
    for k, rr in enumerate(prim):
        Fp, _ = periodic_problem(P, "mu", 1)
        b = pseudo_arclength(Fp, [rr.T, rr.angle, P.mu], scale=[10, 1.0, 1e-4], ds=0.3, ds_max=1.0,
                               steps=10 if quick else 40, par=2, direction=-1, names=("T", "angle", "mu"),
                               bounds={2: (0.0020000001, 0.01)})
        data[f"primary{k}"] = b.u
        axs[0].semilogx(b.u[:, 2] - 2 * P.lam, b.u[:, 0], ".-", ms=3, label=f"primary {k}")
        axs[1].semilogx(b.u[:, 2] - 2 * P.lam, b.u[:, 1], ".-", ms=3)
    axs[0].set_xlabel(r"$\mu - 2\bar\lambda$")
    axs[0].set_ylabel(r"$T$ ($\varepsilon = 10^{-7}$)")
    axs[1].set_xlabel(r"$\mu - 2\bar\lambda$")
    axs[1].set_ylabel("launch angle")
    axs[0].legend(fontsize=7)
    axs[0].set_title(r"primary orbits to the periodic saddle, $\bar\lambda$ = 0.001, m = 1.7, $\gamma = \delta = 1$",
                     fontsize=7)
    fig.tight_layout()
    paths.append(str(atomic_savez(out / "continuation_periodic.npz", **data)))
    paths.append(str(atomic_write_json(out / "continuation_periodic.json", {
        "what": "primary symmetric homoclinic orbits to the periodic saddle continued in mu towards 2 lam",
        "columns": ["T", "angle", "mu"], "start": P.to_dict(), "wall_time_s": time.perf_counter() - t0,
        "versions": versions()})))
    paths.append(str(atomic_savefig(fig, out / "continuation_periodic.png", dpi=140)))
    plt.close(fig)
    # --- a fold: the 2-pulse branch (launch angle ~ 20.07) to the periodic saddle in mu (docs/errata.md)
    t0 = time.perf_counter()
    F2, _ = periodic_problem(P, "mu", 2)
    sc = np.array([40.0, 1.0, 1e-4])
    tol2 = FOLD_BRANCH_TOL  # long double noise floor of this branch's residual is 1e-13 .. 1e-12
    mu_start = 4.87e-3
    u0, _ = point_at(F2, [42.9, 20.07, mu_start], 2, mu_start, scale=sc, tol=tol2)
    b2 = pseudo_arclength(F2, u0, scale=sc, ds=0.1, ds_max=0.3, steps=6 if quick else 24, par=2, direction=-1,
                            tol=tol2, names=("T", "angle", "mu"))
    folds2 = fold_summary(b2)
    paths.append(str(atomic_savez(out / "continuation_fold.npz", u=b2.u, tangents=b2.tangents,
                                  residuals=b2.residuals)))
    paths.append(str(atomic_write_json(out / "continuation_fold.json", {
        "what": "symmetric 2-pulse orbits to the periodic saddle continued in mu across a fold (lam = 0.001, m = 1.7, "
                "gamma = delta = 1, long double, eps = 1e-9)", "columns": ["T", "angle", "mu"], "start": P.to_dict(),
        "folds": folds2, "max_residual": float(np.max(b2.residuals)), "tol": tol2, "message": b2.message,
        "wall_time_s": time.perf_counter() - t0, "versions": versions()})))
    paths.append(str(plot_branch(b2, out / "continuation_fold.png",
                                 title="2-pulse orbits to the periodic saddle in mu: a fold (red circle); lam = 0.001, "
                                       "m = 1.7, gamma = delta = 1")))
    return paths


def write_branch(branch, meta: dict, out_dir, stem: str) -> list[str]:
    """A continuation branch as <stem>.npz (u, tangents, residuals, iterations, names), <stem>.json (meta) and
    <stem>.png (bifurcation diagram), atomically."""
    out = ensure_writable_dir(out_dir)
    npz = atomic_savez(out / f"{stem}.npz", u=branch.u, tangents=branch.tangents, residuals=branch.residuals,
                       iterations=branch.iterations, names=np.array(branch.names))
    png = plot_branch(branch, out / f"{stem}.png", title=f"{meta.get('kind', '')}, N = {meta.get('pulses')}, "
                                                           f"start {meta.get('start_params')}")
    paths = [str(npz), str(out / f"{stem}.json"), str(png)]
    atomic_write_json(out / f"{stem}.json", {**meta, "paths": paths, "versions": versions()})
    return paths
