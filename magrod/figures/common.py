"""Shared plumbing of the figure builders: figures that are written to files without touching pyplot."""
from __future__ import annotations


class _Figures:
    """pyplot's figure-making calls, on plain matplotlib.figure.Figure objects.

    A builder writes files; it must not switch matplotlib's backend (that would take a Jupyter kernel off
    `inline`) nor register figures with pyplot (they would pile up, or pop up on a desktop).  A bare Figure needs
    neither: savefig renders it with Agg for PNG and PDF whatever the process's backend is."""

    @staticmethod
    def subplots(nrows=1, ncols=1, *, sharex=False, sharey=False, squeeze=True, width_ratios=None,
                 height_ratios=None, subplot_kw=None, gridspec_kw=None, **fig_kw):
        from matplotlib.figure import Figure

        fig = Figure(**fig_kw)
        ax = fig.subplots(nrows, ncols, sharex=sharex, sharey=sharey, squeeze=squeeze, width_ratios=width_ratios,
                          height_ratios=height_ratios, subplot_kw=subplot_kw, gridspec_kw=gridspec_kw)
        return fig, ax

    @staticmethod
    def figure(**fig_kw):
        from matplotlib.figure import Figure

        return Figure(**fig_kw)

    @staticmethod
    def close(fig=None):
        """Nothing to release: the figure is not known to pyplot and goes away with its last reference."""

    @staticmethod
    def get_cmap(name):
        import matplotlib

        return matplotlib.colormaps[name]


def pyplot():
    """The figure-making part of pyplot's interface for builders (see _Figures): never a backend switch."""
    return _Figures()


def rect(ax, box, **kw):
    """Outline the box ((x0, x1), (y0, y1)) on ax (used to mark the paper's axis ranges)."""
    (x0, x1), (y0, y1) = box
    ax.plot([x0, x1, x1, x0, x0], [y0, y0, y1, y1, y0], **{"color": "k", "ls": ":", "lw": 0.8, **kw})
