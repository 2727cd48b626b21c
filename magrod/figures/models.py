"""Pictures of the rod family: a model's section, its Lyapunov history, its first-integral search, and
the landscape of sec. 1 (magrod/integrability/landscape.py) with its figure builder."""
from __future__ import annotations

import numpy as np


_GREEK = {"theta", "psi", "phi", "gamma", "delta", "mu", "lambda", "epsilon", "rho", "kappa", "omega"}


def math_name(name: str) -> str:
    """A state or parameter name in mathematics: "m2" -> $m_{2}$, "e31" -> $e_{31}$, "theta" -> $\\theta$,
    "ptheta" -> $p_{\\theta}$ (axis labels of a paper's figure, never code names)."""
    import re

    m = re.fullmatch(r"([A-Za-z]+?)(\d+)", name)
    if m:
        return f"${m.group(1)}_{{{m.group(2)}}}$"
    if name in _GREEK:
        return f"$\\{name}$"
    if name in ("eps", "epsilon"):
        return r"$\varepsilon$"
    if name.startswith("p") and name[1:] in _GREEK:
        return f"$p_{{\\{name[1:]}}}$"
    return f"${name}$" if len(name) == 1 else name


def plot_model_section(secs, ax=None, x=None, y=None, **kw):
    """The section of a model (a PoincareResult, or a list of them: one colour per orbit) projected on two state
    coordinates (default: the two after the section's own)."""
    from ..core import systems
    from .plots import axes

    secs = list(secs) if isinstance(secs, (list, tuple)) else [secs]
    ax = axes(ax)
    names = list(systems.model_body(secs[0].system).state)
    i = names.index(x) if x else 1
    j = names.index(y) if y else 2
    for s in secs:
        ax.plot(s.points[:, i], s.points[:, j], ".", ms=1.5, **kw)
    ax.set_xlabel(math_name(names[i]))
    ax.set_ylabel(math_name(names[j]))
    # its conservation (|dH|, |dC|) is in the result's summary and the figure's sidecar, not in the picture
    ax.set_title(f"{secs[0].system.model} rod: Poincaré section", fontsize=9)
    return ax


def plot_model_lyapunov(ly, ax=None, **kw):
    """ModelLyapunov.plot: the running estimate against t, with the regular bound 10 ln t / t."""
    from .plots import axes

    ax = axes(ax)
    ax.loglog(ly.times, np.abs(ly.lyap_history), "k-", lw=1, **kw)
    t = ly.times
    ax.loglog(t, 10 * np.log(np.maximum(t, 2.0)) / t, "r--", lw=0.8, label="10 ln t / t")
    ax.set_xlabel("t")
    ax.set_ylabel("lyapunov estimate")
    ax.set_title(f"{ly.system.model}: lyap = {ly.lyap:.3g} ({'chaotic' if ly.chaotic else 'regular'})", fontsize=8)
    ax.legend(fontsize=7)
    return ax


def plot_model_search(r, ax=None, **kw):
    """ModelSearch.plot: dim of the integrals of degree <= d against the known algebra's."""
    from .plots import axes

    ax = axes(ax)
    d = np.arange(len(r.kernel_dims))
    ax.plot(d, r.kernel_dims, "o-", color="k", label="dim ker {F, H}")
    ax.plot(d, r.algebra_dims, "s--", color="C3", mfc="none", label="known algebra")
    ax.set_xlabel("degree")
    ax.set_ylabel("dimension")
    ax.set_title(f"{r.model} {r.level or ''}: new {len(r.new_integrals)} (certified: {r.certified})", fontsize=8)
    ax.legend(fontsize=7)
    return ax


def plot_model_chaos_map(cm, ax=None, **kw):
    """ModelChaosMap.plot: the Lyapunov estimate over the parameter plane."""
    from .plots import axes

    ax = axes(ax)
    im = ax.pcolormesh(cm.x, cm.y, cm.lyap, shading="nearest", cmap="viridis", **kw)
    ax.figure.colorbar(im, ax=ax, label=f"lyap (t = {cm.t_max:g})")
    ax.set_xlabel(cm.x_name)
    ax.set_ylabel(cm.y_name)
    ax.set_title(f"{cm.model}: {int(cm.chaotic.sum())} of {cm.lyap.size} chaotic", fontsize=8)
    return ax


def plot_landscape(land, ax=None, **kw):
    """Landscape.plot: one row per line of sec. 1: the claim (integrable or not) and magrod's verdict."""
    from .plots import axes

    rows = land.lines
    ax = axes(ax, figsize=(8.0, 0.6 + 0.45 * len(rows)))
    for i, r in enumerate(rows):
        col = {"agrees": "C2", "disagrees": "C3"}.get(r["agreement"], "0.6")
        ax.barh(i, 1, color=col, alpha=0.35)
        ax.text(0.01, i, f"{r['model']}: cited {'integrable' if r['claim_integrable'] else 'non-integrable'} "
                         f"[{r['reference']}]; magrod: {r['verdict']}", va="center", fontsize=7)
    ax.set_xlim(0, 1)
    ax.set_yticks([])
    ax.set_xticks([])
    ax.invert_yaxis()
    ax.set_title(f"the landscape of sec. 1, re-derived (exact search to degree {land.degree})", fontsize=9)
    return ax


def plot_model_splitting(d, ax=None, **kw):
    """ModelSplitting.plot (d: its to_dict(), or a list of them): the relative difference of the measured splitting
    coefficient from the Mel'nikov one against eps (log-log), with the expected slope (1 or 2) drawn through the
    smallest eps."""
    from .plots import axes

    ax = axes(ax)
    items = d if isinstance(d, list) else [d]
    for k, sp in enumerate(x.to_dict() if hasattr(x, "to_dict") else x for x in items):
        e = np.array([r["eps"] for r in sp["rows"]])
        rel = np.array([r["relative_difference"] for r in sp["rows"]])
        order = 2 if sp["harmonic"] == 1 else 1
        ax.loglog(e, rel, "o-", color=f"C{k}", label=f"{sp['model']} [{sp['reference']}]", **kw)
        ax.loglog(e, rel[-1] * (e / e[-1]) ** order, ":", color=f"C{k}", label=f"slope {order}")
    ax.set_xlabel(r"$\varepsilon$")
    ax.set_ylabel(r"$|c - c_{\mathrm{M}}|\,/\,|c_{\mathrm{M}}|$ (Mel'nikov: $c_{\mathrm{M}}$)")
    ax.set_title("homoclinic splitting vs Mel'nikov (numerical)", fontsize=8)
    ax.legend(fontsize=6)
    return ax


def build(out_dir, *, quick: bool = False, progress: bool = False) -> list[str]:
    """The landscape figure: (a) a section of the integrable Kirchhoff rod, (b) one of the anisotropic rod on the
    same kind of level, (c) the homoclinic splitting of the anisotropic and curved rods against Mel'nikov; sidecar
    landscape.json (every line of sec. 1 with its labelled evidence and verdict, the anisotropic scan, the
    sections' conservation).  The table of the lines is REPORT.md's, not the figure's."""
    from .. import poincare_sections
    from ..core.io import atomic_savefig, atomic_write_json, ensure_writable_dir, versions
    from ..integrability import rod_landscape as landscape
    from .common import pyplot

    plt = pyplot()
    out = ensure_writable_dir(out_dir)
    land = landscape(4, quick=quick)
    iters = 150 if quick else 600
    secs = [poincare_sections(m, starts=6, iterates=iters) for m in ("kirchhoff", "anisotropic")]
    splits = [ln["splitting"] for ln in land.to_dict()["lines"] if "splitting" in ln]
    # figures only: the landscape's table (every line of sec. 1 and its verdict) is in REPORT.md and landscape.json
    fig, axs = plt.subplots(1, 3 if splits else 2, figsize=(13 if splits else 9, 4.2), layout="constrained")
    for k, (s, ax) in enumerate(zip(secs, axs)):
        plot_model_section(s, ax, x="m2", y="n2")
        ax.set_title(f"({'ab'[k]}) " + ax.get_title(), fontsize=9)
    if splits:  # (c) the homoclinic splitting of the anisotropic and curved rods against Mel'nikov
        plot_model_splitting(splits, axs[2])
        axs[2].set_title("(c) " + axs[2].get_title(), fontsize=9)
    d = land.to_dict()
    d["sections"] = [{"model": s[0].system.model, "counts": [r.n_points for r in s],
                      "energy_error": max(r.max_abs_dH for r in s),
                      "casimir_error": max(r.casimir_drift or 0.0 for r in s),
                      "success": all(r.success for r in s)} for s in secs]
    d["quick"] = bool(quick)
    d["versions"] = versions()
    return [str(atomic_write_json(out / "landscape.json", d)), str(atomic_savefig(fig, out / "landscape.png", dpi=110))]
