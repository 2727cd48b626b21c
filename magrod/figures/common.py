"""Shared plumbing of the figure builders: figures that are written to files without touching pyplot."""
from __future__ import annotations

import contextlib
import contextvars
from pathlib import Path

# the picture formats of `--format` (magrod figure, magrod reproduce) and of figures.build(formats=...)
FIGURE_FORMATS = ("png", "pdf", "svg")
_formats: contextvars.ContextVar = contextvars.ContextVar("magrod_figure_formats", default=("png",))


# the mathematical label of every name a figure puts on an axis (never the code name: `lam`, `ptheta`)
LABELS = {"theta": r"$\theta$", "psi": r"$\psi$", "ptheta": r"$\bar p_\theta$", "ppsi": r"$\bar p_\psi$",
          "lam": r"$\bar\lambda$", "gamma": r"$\gamma$", "mu": r"$\mu$", "delta": r"$\delta$", "m": r"$m$",
          "h": r"$h$", "theta0": r"$\theta_0$", "ptheta0": r"$\bar p_{\theta0}$", "psi0": r"$\psi_0$",
          "T": r"$T$", "eps": r"$\varepsilon$"}


def label(name: str) -> str:
    """The axis label of a parameter or coordinate name (LABELS), or the name itself if it has none."""
    return LABELS.get(name, name)


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


def pictures_of(path) -> list:
    """The files atomic_savefig(fig, path) writes in the current figure_formats() context (the first is the one
    it returns)."""
    path = Path(path)
    chosen = _formats.get()
    return [path] if chosen == ("png",) else [path.with_suffix("." + f) for f in chosen]


def atomic_savefig(fig, path, **kw) -> Path:
    """core.io.atomic_savefig in each format chosen by figure_formats() (PNG outside it); returns the first path.
    SVG element ids come from a fixed hash salt (matplotlib's default is random per process), so that the same
    figure gives the same bytes."""
    import matplotlib

    from ..core import io

    path = Path(path)
    no_offsets(fig)
    if clear_of_data(fig):
        kw.setdefault("bbox_inches", "tight")  # a legend moved outside its axes is in the picture, not cut off
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


def no_offsets(fig) -> None:
    """Plain tick labels on every axis: no "+2.645e1" offset with ticks like 0.00825, which a reader must add
    up in their head (ScalarFormatter(useOffset=False); scientific notation for large ranges stays)."""
    from matplotlib.ticker import ScalarFormatter

    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            f = axis.get_major_formatter()
            if isinstance(f, ScalarFormatter):
                f.set_useOffset(False)


def data_points(ax, step: float = 3.0):
    """The display coordinates (n, 2) of the data drawn on ax: the markers of its lines and scatter collections,
    and points every `step` pixels along the segments of lines drawn in data coordinates (a legend over a curve
    covers data even between two vertices).  Reference lines in axes coordinates (axhline, axvline) count only
    by their ends: they span the axes and no box could avoid them.  Images and contours are not data points."""
    import numpy as np
    from matplotlib.collections import PathCollection
    from matplotlib.lines import Line2D

    pts = []
    for art in ax.get_children():
        if not art.get_visible():
            continue
        if isinstance(art, Line2D) and len(art.get_xydata()):
            xy = np.asarray(art.get_xydata(), float)
            d = art.get_transform().transform(xy[np.isfinite(xy).all(axis=1)])
            pts.append(d)
            if art.get_linestyle() not in ("None", "", " ", "none") and len(d) > 1 and art.get_transform() == ax.transData:
                seg = np.diff(d, axis=0)
                n = np.minimum(np.ceil(np.hypot(seg[:, 0], seg[:, 1]) / step).astype(int), 2000)
                for i in np.flatnonzero(n > 1):
                    f = np.linspace(0.0, 1.0, n[i] + 1)[1:-1, None]
                    pts.append(d[i] + f * seg[i])
        elif isinstance(art, PathCollection):
            off = np.asarray(art.get_offsets(), float)
            if len(off):
                pts.append(art.get_offset_transform().transform(off[np.isfinite(off).all(axis=1)]))
    return np.concatenate(pts) if pts else np.empty((0, 2))


def _boxes(ax):
    """The legend and the non-empty visible texts of ax: the boxes that must not cover data or each other."""
    out = []
    leg = ax.get_legend()
    if leg is not None and leg.get_visible():
        out.append(("legend", leg))
    out += [(f"text {t.get_text()[:30]!r}", t) for t in ax.texts if t.get_visible() and t.get_text().strip()]
    return out


def _overlaps(ax, artist, renderer) -> int:
    """How many other boxes of ax (legend, texts) the artist's box overlaps."""
    bb = artist.get_window_extent(renderer)
    return sum(1 for _, other in _boxes(ax) if other is not artist and bb.overlaps(other.get_window_extent(renderer)))


def covering(fig, renderer=None) -> list[tuple]:
    """(axes title or label, what, number of data points) for every legend or annotation of fig whose box covers
    data points of its axes.  tests/test_figure_labels.py asserts this is empty for the saved figures."""

    if renderer is None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)
        canvas.draw()
        renderer = canvas.get_renderer()
    bad = []
    for ax in fig.axes:
        for what, artist in _boxes(ax):
            n = _covered(ax, artist, renderer)  # only points within the axes count: outside, nothing is covered
            if n:
                bad.append((ax.get_title()[:40] or ax.get_label(), what, n))
            k = _overlaps(ax, artist, renderer)
            if k:
                bad.append((ax.get_title()[:40] or ax.get_label(), what + " over another label", k))
    return bad


def clear_of_data(fig) -> bool:
    """Move every legend or annotation that covers data points off them: a legend to a free corner of its axes
    if one exists, otherwise outside, right of the axes; a label that marks a data point to a clear offset
    around its point; any other text to a clear place in the axes, otherwise above them.  Applied by
    atomic_savefig to every figure a builder writes, so that no builder places boxes by hand.  Returns True if
    something now lies outside its axes (the picture is then saved with a tight bounding box)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    if not covering(fig):
        return False
    canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)
    renderer = canvas.get_renderer()
    outside = False
    for ax in fig.axes:
        leg = ax.get_legend()
        if leg is not None and leg.get_visible() and _cost(ax, leg, renderer):
            for loc in ("upper right", "upper left", "lower left", "lower right", "center right", "center left",
                        "upper center", "lower center"):
                leg.set_loc(loc)
                _settle(canvas)
                if not _cost(ax, leg, renderer):
                    break
            else:
                leg.set_loc("upper left")
                leg.set_bbox_to_anchor((1.02, 1.0), transform=ax.transAxes)
                outside = True
                _settle(canvas)
        for t in list(ax.texts):
            if t.get_visible() and t.get_text().strip() and _cost(ax, t, renderer):
                outside |= _move_text_clear(ax, t, canvas, renderer)
    return outside


def _settle(canvas) -> None:
    """What a trial placement needs before its boxes are measured: the figure's layout (its layout engine places
    the axes around what lies outside them), not a rendering.  Text, annotation and legend boxes are computed from
    their positions on demand (a legend's offset from its loc); covering() drew the figure once before."""
    fig = canvas.figure
    engine = fig.get_layout_engine()
    if engine is not None:
        engine.execute(fig)


def _cost(ax, artist, renderer) -> int:
    """Data points covered plus, heavily weighted, other labels overlapped."""
    return _covered(ax, artist, renderer) + 1000 * _overlaps(ax, artist, renderer)


def _covered(ax, artist, renderer) -> int:
    """How many data points of ax (inside the axes) the artist's box covers."""
    import numpy as np

    pts = data_points(ax)
    if not len(pts):
        return 0
    bb = artist.get_window_extent(renderer)
    ab = ax.get_window_extent(renderer)
    inside = ((pts[:, 0] > bb.x0) & (pts[:, 0] < bb.x1) & (pts[:, 1] > bb.y0) & (pts[:, 1] < bb.y1)
              & (pts[:, 0] >= ab.x0) & (pts[:, 0] <= ab.x1) & (pts[:, 1] >= ab.y0) & (pts[:, 1] <= ab.y1))
    return int(np.count_nonzero(inside))


def _move_text_clear(ax, t, canvas, renderer) -> bool:
    """A label anchored at a data point (an Annotation in data coordinates) tries offsets around its point and
    keeps the one covering the fewest points; any other text tries a grid of places in the axes, else goes above
    them (returns True then)."""
    anchored = hasattr(t, "xyann") and t.xycoords == "data"
    if anchored:
        t.set_anncoords("offset points")
        best = None
        for dx, dy in ((6, 6), (6, -12), (-6, 6), (-6, -12), (12, 14), (12, -20), (-12, 14), (-12, -20),
                       (0, 22), (0, -28), (24, 0), (-24, 0), (30, 30), (30, -36), (-30, 30), (-30, -36)):
            t.xyann = (dx, dy)
            t.set_ha("left" if dx >= 0 else "right")
            _settle(canvas)
            n = _cost(ax, t, renderer)
            if best is None or n < best[0]:
                best = (n, dx, dy)
            if n == 0:
                return False
        t.xyann = best[1:]
        t.set_ha("left" if best[1] >= 0 else "right")
        return False
    places = [((x, y), ha, "top" if y > 0.5 else "bottom") for y in (0.97, 0.86, 0.5, 0.14, 0.03)
              for x, ha in ((0.03, "left"), (0.97, "right"), (0.5, "center"))]
    if hasattr(t, "xyann"):
        t.xycoords = "axes fraction"
        t.set_anncoords("axes fraction")
        if t.arrow_patch is not None:
            t.arrow_patch.set_visible(False)
    else:
        t.set_transform(ax.transAxes)
    for xy, ha, va in places:
        t.set_ha(ha)
        t.set_va(va)
        if hasattr(t, "xyann"):
            t.xy = xy
            t.xyann = xy
        else:
            t.set_position(xy)
        _settle(canvas)
        if not _cost(ax, t, renderer):
            return False
    t.set_ha("center")
    t.set_va("bottom")
    if hasattr(t, "xyann"):
        t.xy = t.xyann = (0.5, 1.01)
    else:
        t.set_position((0.5, 1.01))
    return True
