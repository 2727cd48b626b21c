"""Shared plumbing of the figure builders: figures that are written to files without touching pyplot."""
from __future__ import annotations

import contextlib
import contextvars
from pathlib import Path

# the picture formats of `--format` (magrod figure, magrod reproduce) and of figures.build(formats=...)
FIGURE_FORMATS = ("png", "pdf", "svg")
_formats: contextvars.ContextVar = contextvars.ContextVar("magrod_figure_formats", default=("png",))


def parse_formats(value, name: str = "format") -> tuple:
    """"png", "pdf,svg", ("png", "pdf") -> a tuple of distinct FIGURE_FORMATS (ParameterError naming `name`)."""
    from ..core.errors import ParameterError

    items = [f.strip().lower() for f in (value.split(",") if isinstance(value, str) else value)]
    bad = [f for f in items if f not in FIGURE_FORMATS]
    if not items or bad or len(set(items)) != len(items) or "" in items:
        raise ParameterError(name, f"must be one or more distinct of {', '.join(FIGURE_FORMATS)} separated by "
                             f"commas, got {value!r}")
    return tuple(items)


@contextlib.contextmanager
def figure_formats(formats):
    """Inside this context every picture a builder saves is written in each of `formats` (in that order), in
    place of the suffix the builder named; atomic_savefig returns the first.  A context variable, not a global:
    a builder running elsewhere keeps its own choice."""
    token = _formats.set(parse_formats(formats))
    try:
        yield _formats.get()
    finally:
        _formats.reset(token)


def atomic_savefig(fig, path, **kw) -> Path:
    """core.io.atomic_savefig in each format chosen by figure_formats() (PNG outside it); returns the first path.
    SVG element ids come from a fixed hash salt (matplotlib's default is random per process), so that the same
    figure gives the same bytes."""
    import matplotlib

    from ..core import io

    path = Path(path)
    chosen = _formats.get()
    targets = [path] if chosen == ("png",) else [path.with_suffix("." + f) for f in chosen]
    written = []
    for target in targets:
        with matplotlib.rc_context({"svg.hashsalt": "magrod"}):
            written.append(io.atomic_savefig(fig, target, **kw))
    return written[0]


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
