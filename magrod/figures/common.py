"""Shared plumbing of the figure builders: a non-interactive matplotlib and the output directory."""
from __future__ import annotations


def pyplot():
    """matplotlib.pyplot on the Agg backend (no screen needed; figures are written, never shown)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def rect(ax, box, **kw):
    """Outline the box ((x0, x1), (y0, y1)) on ax (used to mark the paper's axis ranges)."""
    (x0, x1), (y0, y1) = box
    ax.plot([x0, x1, x1, x0, x0], [y0, y0, y1, y1, y0], **{"color": "k", "ls": ":", "lw": 0.8, **kw})
