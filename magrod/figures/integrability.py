"""Picture of the integrability report: which brackets among H, I1, I2 and the Casimirs vanish, per regime."""
from __future__ import annotations

import numpy as np


def plot_involution(rep, ax=None, **kw):
    """IntegrabilityReport.plot: a table of the involution brackets (columns) per regime (rows), dark where the
    bracket vanishes identically, light where it does not."""
    from .plots import axes

    tables = rep.involution()
    if not tables:
        raise ValueError("this report has no involution table")
    regimes = list(tables)
    brackets = sorted({b for t in tables.values() for b in t})
    Z = np.array([[0.0 if tables[r].get(b, "?") == "0" else 1.0 for b in brackets] for r in regimes])
    ax = axes(ax, figsize=(1.0 + 0.7 * len(brackets), 0.8 + 0.45 * len(regimes)))
    ax.imshow(Z, cmap="Greys_r", vmin=-0.3, vmax=1.3, aspect="auto", **kw)
    for i in range(len(regimes)):
        for j in range(len(brackets)):
            ax.text(j, i, "0" if Z[i, j] == 0 else "≠0", ha="center", va="center",
                    color="w" if Z[i, j] == 0 else "k", fontsize=8)
    ax.set_xticks(range(len(brackets)), brackets, rotation=45, ha="right", fontsize=8)
    ax.set_yticks(range(len(regimes)), regimes, fontsize=8)
    ax.set_title(f"involution brackets ({rep.source})", fontsize=9)
    return ax


def plot_kernel(res, ax=None, **kw):
    """RegimeSearch / FirstIntegralSearch .plot: dim ker L (polynomial first integrals of degree <= d, mod p) against
    the dimension of the algebra of the known integrals, per degree d (a certificate where the two coincide)."""
    from .plots import axes

    r = getattr(res, "main", res)
    d = np.arange(len(r.kernel_dims))
    ax = axes(ax)
    ax.plot(d, r.kernel_dims, "o-", label="dim ker L (mod p)", **kw)
    ax.plot(d, r.algebra_dims, "s--", label="known algebra (" + ", ".join(r.known) + ")")
    if r.candidates_found:
        ax.plot(d, r.algebra_with_candidates_dims, "^:", label="with " + ", ".join(r.candidates_found))
    ax.set_yscale("log")
    ax.set_xlabel("degree d")
    ax.set_ylabel("dimension (degree <= d)")
    ax.set_title(f"{r.name}: {'certified' if r.certified else 'not certified'}", fontsize=9)
    ax.legend(fontsize=7)
    return ax
