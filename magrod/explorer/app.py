"""The explorer page: a Panel app with a Bokeh section plot.

Layout: parameter widgets (m, mu, gamma, delta, lambdabar, h, iterates; each validated as `magrod poincare`
validates it, every wrong field's message shown under it) | the section sin(psi) = 0 in (theta, pbar_theta): each
branch (psi = 0, psi = pi) with its own energy-level boundary, no-root shading and marker, orbits coloured by their growth exponent on the chaos map's scale, the colour bar stating
the threshold | the orbit list (delete, clear, undo, export) and, for the selected orbit, its conservation errors
and the 3-D rod.

Threads: a click runs on the server's event loop (with the document lock): it solves Hbar = h for pbar_psi (a few
ms) and submits the orbit to the session's Worker.  The worker threads never touch the document: they put chunks
into a queue, which a periodic callback (every POLL_MS) drains into the plot's data sources.  Cancelling: every
job checks its event after each section crossing; a session whose page is closed (no websocket connection for
CLOSE_GRACE_S) cancels all its jobs, and the server cancels every session's jobs on Ctrl-C.
"""
from __future__ import annotations

import io
import itertools
import json
import queue
import tempfile
import threading
import time
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import panel as pn
from bokeh.events import DoubleTap, Tap
from bokeh.models import (CDSView, ColorBar, ColumnDataSource, FixedTicker, GlyphRenderer, GroupFilter, Legend,
                          LegendItem, LinearColorMapper, Range1d, Scatter)
from bokeh.plotting import figure

from ..core.errors import ParameterError
from ..core.printed import PANELS, panel as paper_panel
from . import model
from .worker import Job, Worker, solve_start

POLL_MS = 50
CLOSE_GRACE_S = 0.05  # a session without a connection for this long is closed (Bokeh does not reconnect a
# session's websocket: a reloaded page is a new session)
PENDING_COLOUR = "#555555"
N_SLOTS = 24  # orbit renderers made with the page (see _build_plot), and made again in one batch when few are left
SLOT_REFILL_AT = 4  # free slots left when the next batch is made (by poll(), while no orbit computes)
# Display-only decimation: an orbit shows at most this many of its points (every k-th, k fixed at launch from its
# iterate count), so that drawing stays fluid at 10^5 iterates; exports and results keep every point.
DISPLAY_CAP = 20_000
# The page receives an orbit's new points at most this often (the chunks in between are joined): every message
# re-renders the plot, and at 25 messages a second a tab without a GPU spent all its time drawing.
STREAM_INTERVAL_S = 0.25
# ... and less often the more points the plot holds: every message repaints every drawn point (canvas), so the
# repaint cost grows with the orbit count; messages at most every (points drawn) / PAINT_POINTS_PER_S seconds keep
# the page's share of time spent painting bounded (measured: a repaint of 30 orbits x 1000 points took 0.2-0.4 s
# in headless chromium at load ~4, and the time per click grew with the orbit count, 3.5 -> 4.9 s median)
PAINT_POINTS_PER_S = 20_000
DOUBLE_CLICK_PX = 4  # a DoubleTap this close (screen pixels) to the previous tap is a double click, not a new click
MARKER_SIZE = 3  # px, the page's marker-size control starts here
# the projections of the section sin psi = 0 (the level fixes the third coordinate; theta-pbar_theta is where a
# click or a typed start launches an orbit, and where the energy-level boundary is drawn)
PROJECTIONS = {"θ – p̄θ": ("theta", "ptheta"), "θ – p̄ψ": ("theta", "ppsi"), "p̄θ – p̄ψ": ("ptheta", "ppsi")}
AXIS_LABELS = {"theta": "θ", "ptheta": "p̄θ", "ppsi": "p̄ψ"}
# each branch of the section (psi = 0, psi = pi) has its own marker, boundary line and "no root" shading: an orbit
# crosses both, and a psi = pi point may lie where psi = 0 has no energy root (the two sections are overlaid)
BRANCH_MARKER = {"0": "circle", "pi": "triangle"}
BRANCH_STYLE = {"0": dict(line_color="black", line_dash="solid", fill_color="#c8c8c8", fill_alpha=0.75,
                          hatch_pattern=None),
                "pi": dict(line_color="#a6611a", line_dash="dashed", fill_color="#a6611a", fill_alpha=0.0,
                           hatch_pattern="/")}
PARAM_LABELS = {"m": "m", "mu": "μ", "gamma": "γ", "delta": "δ", "lam": "λ̄", "h": "h (level H̄ = h)",
                "iterates": "iterates per orbit"}


@dataclass
class Orbit:
    """One launched orbit as the page shows it."""

    id: int
    theta0: float
    ptheta0: float
    start: object = None  # worker.Start (None: no energy root at the current parameters)
    job: Job | None = None
    source: ColumnDataSource | None = None  # columns x, y and branch ("0" or "pi") of the drawn points
    renderer: object = None  # _Glyphs: one scatter per branch over the one source
    iterates: int = 0  # the iterate count of its run (extended by extend())
    stride: int = 1  # display decimation: every stride-th point is drawn (DISPLAY_CAP)
    skip: int = 0  # points already shown before an extension's rerun (its first points are these, bit for bit)
    shown: dict | None = None  # the drawn points of every projection coordinate (lists of arrays)
    pending: list | None = None  # points decimated but not yet sent to the page (joined into one message)
    last_stream: float = 0.0  # perf_counter of the last message to the page
    result: object = None  # PoincareResult when finished
    indicator: object = None  # LyapunovResult
    status: str = "pending"
    message: str = ""
    n_points: int = 0
    max_abs_dH: float = 0.0
    t_launch: float = 0.0  # perf_counter at the click (latency of the first points)
    rod_figure: object = None  # plotly figure of the rod, computed in the background
    rod_for: object = None  # the Start it was computed for

    def label(self, threshold: float) -> str:
        """The orbit list's row: the start to 4 digits (the details show the exact doubles), so that the growth
        exponent and the verdict fit the list's width."""
        g = getattr(self.indicator, "growth_exponent", None)
        verdict = "" if g is None else f", growth {g:.3g} → {'chaotic' if g > threshold else 'regular'}"
        state = "" if self.status == "done" else f" [{self.status}]"
        return f"#{self.id}: θ₀={self.theta0:.4g}, p̄θ₀={self.ptheta0:.4g}, {self.n_points} pts{verdict}{state}"


class Explorer(pn.viewable.Viewer):
    """The interactive section explorer of one page (session); see `magrod.explore`."""

    def __init__(self, panel: str = "4a", *, iterates: int = 1000, psi0: float = 0.0, direction: str = "positive",
                 rod_length: float = 100.0, max_workers: int = 2, out_dir=None, registry=None, **params):
        super().__init__(**params)
        P = paper_panel(panel)
        from ..chaos import GROWTH_THRESHOLD

        self.threshold = GROWTH_THRESHOLD
        self.panel_key = P.key
        self.psi0 = float(psi0)
        self.direction = direction
        self.rod_length = float(rod_length)
        self.out_dir = Path(out_dir) if out_dir is not None else None
        self.params, self.h, self.iterates = P.params, P.h, int(iterates)
        self.orbits: list[Orbit] = []
        self._undo: list[tuple] = []
        self._next_id = 1
        self._pending_select = None
        self._served = False
        self._lost_wall = None
        self.closed_wall = None
        self._job_ids = itertools.count(1)
        self._queue: queue.SimpleQueue = queue.SimpleQueue()
        self._worker = Worker(max_workers=max_workers)
        self._lock = threading.Lock()
        self._closed = False
        self._connected_once = False
        self._callback = None
        self.latencies: list[float] = []  # click -> first chunk handed to the page (s), for the status endpoint
        self.tap_handler_s: list[float] = []  # time spent in the click handler on the event loop (s)
        self.tap_wall: list[float] = []  # wall-clock times the click handler started
        self._last_tap_px: tuple | None = None  # screen position of the last tap (a DoubleTap there is ignored)
        self.stream_wall: list[float] = []  # wall-clock times first points were streamed
        self._registry = registry
        if registry is not None:
            registry.add(self)
        self._build_widgets(P)
        self._build_plot()
        self._set_boundary()
        self._layout = self._build_layout()
        self.warmed = self._worker.warm(solve_start(P.params, P.h, P.theta0, P.ptheta0, P.psi0), direction)

    # ------------------------------------------------------------------------------------------------------
    # widgets and plot
    # ------------------------------------------------------------------------------------------------------
    def _build_widgets(self, P):
        values = {**P.params.to_dict(), "h": P.h, "iterates": self.iterates}
        self.inputs, self.errors = {}, {}
        for name in model.FIELDS:
            w = pn.widgets.TextInput(label=PARAM_LABELS[name], value=f"{values[name]:g}", width=150,
                                     css_classes=[f"magrod-input-{name}"])
            w.param.watch(self._deferred(self._on_input), "value")
            self.inputs[name] = w
            self.errors[name] = _Text("", f"magrod-error-{name}", width=150,
                                      styles={"color": "#b00020", "font-size": "11px"}, margin=(0, 10, 0, 10))
        self.panel_select = pn.widgets.Select(label="paper panel", options=list(PANELS), value=P.key, width=150,
                                             css_classes=["magrod-panel"])
        self.panel_select.param.watch(self._deferred(self._on_panel), "value")
        # a fixed height: a status line that wrapped to another line changed the page's layout, and a relayout
        # repaints the plot's every point (measured: a repaint per status change)
        self.status = _Text("Click inside the boundary to launch an orbit.", "magrod-status",
                            sizing_mode="stretch_width", styles={"font-size": "13px", "overflow-y": "auto"},
                            height=40)
        # the orbit list lives outside the plot and scrolls: the plot keeps its size whatever the number of orbits
        self.orbit_list = pn.widgets.Select(label="orbits (select one for its details and rod)", options={}, size=10,
                                            width=400, css_classes=["magrod-orbit-list"])
        self.start_inputs = {
            "theta0": pn.widgets.TextInput(label="θ₀", value="", placeholder="e.g. 0.1", width=120,
                                           css_classes=["magrod-start-theta0"]),
            "ptheta0": pn.widgets.TextInput(label="p̄θ₀", value="", placeholder="e.g. 0.5", width=120,
                                            css_classes=["magrod-start-ptheta0"])}
        self.b_launch = pn.widgets.Button(label="Launch", width=80, css_classes=["magrod-launch"], align="end")
        self.b_launch.on_click(self._deferred(lambda e: self._launch_typed()))
        self.extend_input = pn.widgets.TextInput(label="extend selected by (iterates)", value="1000", width=170,
                                                 css_classes=["magrod-extend-n"])
        self.b_extend = pn.widgets.Button(label="Extend", width=80, css_classes=["magrod-extend"], align="end")
        self.b_extend.on_click(self._deferred(lambda e: self._extend_clicked()))
        self.marker_size = pn.widgets.IntSlider(label="marker size (px)", start=1, end=10, value=MARKER_SIZE,
                                                width=180, css_classes=["magrod-marker-size"])
        self.marker_size.param.watch(self._deferred(lambda e: self.set_marker_size(e.new)), "value")
        self.projection = pn.widgets.Select(label="projection", options=list(PROJECTIONS), value="θ – p̄θ",
                                            width=180, css_classes=["magrod-projection"])
        self.projection.param.watch(self._deferred(lambda e: self.set_projection(e.new)), "value")
        self._branches_shown = set(model.BRANCH_PSI)  # shared with every orbit's _Glyphs
        self.branch_toggle = pn.widgets.CheckButtonGroup(
            name="section branches", options={f"{model.BRANCH_LABEL[k]} {'●' if k == '0' else '▲'}": k
                                              for k in model.BRANCH_PSI},
            value=list(model.BRANCH_PSI), width=180, css_classes=["magrod-branches"])
        self.branch_toggle.param.watch(self._deferred(lambda e: self.show_branches(e.new)), "value")
        self.orbit_list.param.watch(self._deferred(self._on_select), "value")
        self.b_delete = pn.widgets.Button(label="Delete", width=80, css_classes=["magrod-delete"])
        self.b_clear = pn.widgets.Button(label="Clear", width=80, css_classes=["magrod-clear"])
        self.b_undo = pn.widgets.Button(label="Undo", width=80, css_classes=["magrod-undo"])
        self.b_export = pn.widgets.Button(label="Export to --out", width=120, color="primary",
                                          css_classes=["magrod-export"], visible=self.out_dir is not None)
        self.b_delete.on_click(self._deferred(lambda e: self.delete(self.orbit_list.value)))
        self.b_clear.on_click(self._deferred(lambda e: self.clear()))
        self.b_undo.on_click(self._deferred(lambda e: self.undo()))
        self.b_export.on_click(self._deferred(lambda e: self._export_clicked()))
        self.download = pn.widgets.FileDownload(callback=self._export_zip, filename="magrod-explore.zip",
                                                label="Download PNG + data (.zip)", color="success",
                                                width=240, css_classes=["magrod-download"])
        self.details = _Text("", "magrod-details", sizing_mode="stretch_width", styles={"font-size": "12px"})
        # the rod gets a full-width row of its own under the plot, with room for plotly's title and toolbar
        self.rod_pane = pn.pane.Plotly(None, height=520, min_height=520, sizing_mode="stretch_width", visible=False,
                                       css_classes=["magrod-rod"])

    def _build_plot(self):
        f = figure(width=760, height=600, x_range=Range1d(0.0, np.pi), y_range=Range1d(-1.5, 1.5),
                   tools="tap,pan,wheel_zoom,box_zoom,reset,save", active_scroll="wheel_zoom",
                   # canvas, not webgl: without a GPU, WebGL is software-rendered and every renderer's frame is read
                   # back (drawImage + readPixels) on each redraw, so the cost grew with the orbit count (profiled: 30
                   # clicks took 52 s of the page's main thread under webgl, 15 s under canvas)
                   output_backend="canvas", x_axis_label="θ", y_axis_label="p̄θ", name="section")
        f.toolbar.logo = None
        f.title.text_font_size = "12px"
        f.axis.axis_label_text_font_size = "16px"
        f.axis.major_label_text_font_size = "12px"
        # per branch: the "no root" region (|p̄θ| beyond the boundary) shaded, and the boundary H̄ = h
        self.forbidden, self._branch_shading, boundary_line = {}, {}, {}
        for key in model.BRANCH_PSI:
            st = BRANCH_STYLE[key]
            src = ColumnDataSource({"x": [], "top": [], "up": [], "lo": [], "bottom": []}, name=f"forbidden-{key}")
            hatch = {} if st["hatch_pattern"] is None else dict(hatch_pattern=st["hatch_pattern"],
                                                                hatch_color=st["line_color"], hatch_alpha=0.55,
                                                                hatch_scale=9.0)
            areas = [f.varea("x", a, b, source=src, fill_color=st["fill_color"], fill_alpha=st["fill_alpha"],
                             name=f"no-root-{key}", **hatch) for a, b in (("up", "top"), ("bottom", "lo"))]
            lines = [f.line("x", c, source=src, color=st["line_color"], line_dash=st["line_dash"], line_width=1.5)
                     for c in ("up", "lo")]
            self.forbidden[key], self._branch_shading[key], boundary_line[key] = src, areas + lines, lines[0]
        self.start_marker = ColumnDataSource({"x": [], "y": []})
        f.scatter("x", "y", source=self.start_marker, marker="x", size=12, line_width=2, color="black")
        mapper = LinearColorMapper(palette=model.palette(self.threshold), low=0.0, high=1.0)
        ticks = model.colorbar_ticks(self.threshold)
        cb = ColorBar(color_mapper=mapper, ticker=FixedTicker(ticks=list(ticks)),
                      major_label_overrides={k: v for k, v in ticks.items()}, width=14, label_standoff=6,
                      # the definition (FLI(T) - FLI(T/2))/ln 2 and the scale are in the orbit's details
                      title=f"growth exponent: chaotic > {self.threshold:g}", title_text_font_size="11px",
                      major_label_text_font_size="10px")
        f.add_layout(cb, "right")
        # one fixed legend item: the orbits are listed outside the plot (a legend item per orbit grew the legend
        # inside the plot's fixed height and squeezed the frame to a sliver after ~20 orbits)
        key_src = ColumnDataSource({"x": [], "y": []})  # legend keys only: the markers of the two branches
        marks = {k: f.scatter("x", "y", source=key_src, marker=BRANCH_MARKER[k], size=7, color="#555555")
                 for k in model.BRANCH_PSI}
        items = []
        for k in model.BRANCH_PSI:
            shade = "grey" if k == "0" else "hatched"
            items.append(LegendItem(label=f"{model.BRANCH_LABEL[k]} crossings; boundary H̄ = h, {shade}: no root",
                                    renderers=[marks[k], boundary_line[k], self._branch_shading[k][0]]))
        self.legend = Legend(items=items, location="top_left", label_text_font_size="10px",
                             background_fill_alpha=0.7, spacing=0, padding=4, orientation="horizontal")
        f.add_layout(self.legend, "below")
        # Renderers made before the page exists: adding a renderer to a live document makes Bokeh walk every
        # model (~0.3 s, on the event loop, before the first points could be sent); a slot only changes data,
        # colour and visibility.  Orbits beyond N_SLOTS get new renderers (the slow path).
        self._free_slots = [self._new_slot(f, k) for k in range(N_SLOTS)]
        self._n_slots = N_SLOTS
        self.slow_slots = 0  # renderers added to the live page during a click (the slow path: should stay 0)
        f.on_event(Tap, self._on_tap)
        # Bokeh turns a second click within 300 ms of the first into a DoubleTap and sends no Tap: a quick second
        # click elsewhere was lost.  A DoubleTap away from the last tap is a click; on the same spot it is the
        # second half of a double click and launches nothing
        f.on_event(DoubleTap, self._on_double_tap)
        self.fig = f
        self.plot_pane = pn.pane.Bokeh(f, css_classes=["magrod-section"])

    def _new_slot(self, f, k, attach: bool = True):
        """An orbit's source (columns x, y, branch) and its _Glyphs: one scatter per branch, each showing the
        source's rows of its branch (a CDSView), with the branch's marker.  attach=False: the renderers are not
        added to the figure yet (a batch is added in one change: _refill_slots)."""
        src = ColumnDataSource(_EMPTY_POINTS(), name=f"slot-src-{k}")
        size = self.marker_size.value if hasattr(self, "marker_size") else MARKER_SIZE
        rs = {b: GlyphRenderer(data_source=src, visible=False,
                               glyph=Scatter(x="x", y="y", size=size + (1 if b == "pi" else 0), line_width=0,
                                             marker=BRANCH_MARKER[b], fill_color=PENDING_COLOUR,
                                             line_color=PENDING_COLOUR),
                               view=CDSView(filter=GroupFilter(column_name="branch", group=b)))
              for b in BRANCH_MARKER}
        if attach:
            f.renderers.extend(rs.values())
        return src, _Glyphs(rs, self._branches_shown)

    def _take_slot(self, o: Orbit):
        if self._free_slots:
            o.source, o.renderer = self._free_slots.pop(0)
        else:
            self.slow_slots += 1
            o.source, o.renderer = self._new_slot(self.fig, f"extra-{o.id}")
        o.source.name = f"orbit-src-{o.id}"
        o.renderer.visible = True

    def _build_layout(self):
        side = pn.Column("### Parameters (eq:nondim_1)", self.panel_select,
                         *[pn.Column(self.inputs[k], self.errors[k].pane, margin=0) for k in model.FIELDS], width=200)
        orbits = pn.Column("### Orbits",
                           pn.Row(self.start_inputs["theta0"], self.start_inputs["ptheta0"], self.b_launch),
                           self.orbit_list, pn.Row(self.b_delete, self.b_clear, self.b_undo),
                           pn.Row(self.extend_input, self.b_extend), pn.Row(self.download, self.b_export),
                           self.details.pane, width=440)
        view = pn.Row(self.marker_size, self.projection,
                      pn.Column(pn.pane.HTML("section branches shown", styles={"font-size": "12px"}, margin=(0, 5)),
                                self.branch_toggle, margin=0))
        return pn.Column(pn.pane.HTML("<b>magrod explore</b>: Poincaré section sin ψ = 0 of the conducting rod "
                                      "(Sinden &amp; van der Heijden, sec. 8). Click, or type a start, to launch "
                                      "an orbit from (θ, p̄θ); p̄ψ solves H̄ = h.", styles={"font-size": "14px"}),
                         self.status.pane, pn.Row(side, pn.Column(self.plot_pane, view), orbits), self.rod_pane,
                         sizing_mode="stretch_width")

    def _refill_slots(self) -> None:
        """Add N_SLOTS renderers in one batch when few are left, between clicks: a renderer added to a live
        document makes Bokeh walk every model (~0.3-1 s on the event loop); made in a click, that delayed the
        click's first points from the 25th orbit on (measured: tap handler 0.01-0.08 s for orbits 1-24, 0.5-1.1 s
        after).  The batch is one change of the figure's renderers: one walk, one message."""
        if len(self._free_slots) >= SLOT_REFILL_AT or any(o.status == "running" for o in self.orbits):
            return
        new = [self._new_slot(self.fig, k, attach=False)
               for k in range(self._n_slots, self._n_slots + N_SLOTS)]
        # one change of the figure's renderers (one message, one rebuild of the page's renderer views)
        self.fig.renderers = [*self.fig.renderers, *[r for _, g in new for r in g.renderers.values()]]
        self._free_slots.extend(new)
        self._n_slots += N_SLOTS

    def _deferred(self, fn):
        """A Panel widget callback that edits the page's Bokeh models.  Served, Panel runs widget callbacks
        without the document lock, and Bokeh refuses model changes made there: the call is queued and run by
        poll() (a periodic callback, which holds the lock) within POLL_MS.  Unserved (tests, Jupyter) it runs
        at once."""

        def handler(*args, **kwargs):
            if self._served:
                self._queue.put(("call", None, None, lambda: fn(*args, **kwargs)))
            else:
                fn(*args, **kwargs)

        return handler

    def __panel__(self):
        doc = pn.state.curdoc
        if doc is not None and getattr(doc, "session_context", None) is not None:
            self._served = True
        if self._callback is None and not self._closed:
            self._callback = pn.state.add_periodic_callback(self.poll, period=POLL_MS)
            pn.state.on_session_destroyed(lambda ctx: self.close())
        return self._layout

    # ------------------------------------------------------------------------------------------------------
    # the energy level
    # ------------------------------------------------------------------------------------------------------
    def _set_boundary(self):
        """Each branch's boundary |p̄θ| = pmax(θ) at the current level and its "no root" region beyond it."""
        bounds = model.section_boundaries(self.params, self.h)
        top = max(1.15 * max(float(b["pmax"].max()) for b in bounds.values()), 0.1)
        self.fig.y_range.start, self.fig.y_range.end = -top, top
        for key, b in bounds.items():
            pmax = b["pmax"]
            x = np.concatenate([[0.0], b["theta"], [np.pi]])
            up = np.concatenate([[pmax[0]], pmax, [pmax[-1]]])
            self.forbidden[key].data = {"x": x, "top": np.full_like(x, 10 * top), "up": up, "lo": -up,
                                        "bottom": np.full_like(x, -10 * top)}
        p = self.params
        self.fig.title.text = (f"m = {p.m:g}, μ = {p.mu:g}, γ = {p.gamma:g}, δ = {p.delta:g}, λ̄ = {p.lam:g}, "
                               f"h = {self.h:g};  section sin ψ = 0 (ψ₀ = {self.psi0:g}), crossings with d/ds sin ψ "
                               f"{'> 0' if self.direction == 'positive' else self.direction}")

    # ------------------------------------------------------------------------------------------------------
    # inputs
    # ------------------------------------------------------------------------------------------------------
    def _values(self) -> dict:
        return {k: w.value for k, w in self.inputs.items()}

    def _on_panel(self, event):
        P = paper_panel(event.new)
        self.panel_key = P.key
        vals = {**P.params.to_dict(), "h": P.h}
        self._suspend = True
        try:
            for k, v in vals.items():
                self.inputs[k].value = f"{v:g}"
        finally:
            self._suspend = False
        self._on_input(None)

    def _on_input(self, event):
        """Apply the widgets' values, or show every wrong field's message under it and, under each other field
        whose typed value differs from the one in use, that it is not applied yet (never a silently stale box)."""
        if getattr(self, "_suspend", False):
            return
        for e in self.errors.values():
            e.object = ""
        parsed, errors = model.input_errors(self._values())
        if errors:
            for name, msg in errors.items():
                self.errors[name].object = f"⚠ {_escape(msg)}"
            in_use = {**self.params.to_dict(), "h": self.h, "iterates": self.iterates}
            for name, w in self.inputs.items():
                if name not in errors and not _same_number(w.value, in_use[name]):
                    self.errors[name].object = (f"not applied until {', '.join(errors)} "
                                                f"{'is' if len(errors) == 1 else 'are'} fixed; in use: "
                                                f"{in_use[name]:g}")
            self._say("Not applied: " + "; ".join(errors.values()), error=True)
            return
        params, h, iterates = parsed
        changed = (params, h) != (self.params, self.h)
        new_iterates = iterates != self.iterates
        self.iterates = iterates
        if changed:
            self.params, self.h = params, h
            self._set_boundary()
            self._say(f"Parameters applied; relaunching {len(self.orbits)} orbit(s) from their starts.")
            for o in self.orbits:
                self._launch(o)
        elif new_iterates:
            self._say(f"iterates per orbit = {iterates} (new orbits)")

    def set_input(self, name: str, value) -> str:
        """Type `value` into the widget `name` (as a user would); returns the message shown next to it (as text:
        the page's HTML escapes what the user typed)."""
        import html

        self.inputs[name].value = str(value)
        return html.unescape(self.errors[name].object)

    # ------------------------------------------------------------------------------------------------------
    # orbits
    # ------------------------------------------------------------------------------------------------------
    def _on_tap(self, event):
        doc = self.fig.document
        if doc is None:
            return self._tap(event)
        from panel.io.document import hold

        with hold(doc, policy="combine"):  # the launch's changes (marker, slot, colour, status): one message
            return self._tap(event)

    def _tap(self, event):
        self.tap_wall.append(time.time())
        self._last_tap_px = (event.sx, event.sy)
        t = time.perf_counter()
        if PROJECTIONS[self.projection.value] != ("theta", "ptheta"):
            self._say("Orbits are launched in the θ – p̄θ projection (where the energy level is drawn): switch "
                      "back to it, or type a start.", error=True)
        else:
            self.launch(event.x, event.y)
        self.tap_handler_s.append(time.perf_counter() - t)

    def _on_double_tap(self, event):
        last = self._last_tap_px
        if last is not None and abs(event.sx - last[0]) <= DOUBLE_CLICK_PX and abs(event.sy - last[1]) <= DOUBLE_CLICK_PX:
            return
        self._on_tap(event)

    def _launch_typed(self):
        """The typed start, exactly: the decimal strings are parsed as Python floats, as `magrod poincare
        --theta0 0.1` parses them, so the orbit equals poincare_section's for the same numbers to the last bit."""
        vals = {}
        for name, w in self.start_inputs.items():
            try:
                vals[name] = float(str(w.value).strip())
            except ValueError:
                self._say(f"{name}: type a number (e.g. 0.1), got {str(w.value)[:30]!r}", error=True)
                return None
            if not np.isfinite(vals[name]):
                self._say(f"{name}: must be finite, got {w.value!r}", error=True)
                return None
        return self.launch(vals["theta0"], vals["ptheta0"])

    def _extend_clicked(self):
        o = self.selected()
        try:
            n = int(float(str(self.extend_input.value).strip()))
        except ValueError:
            self._say(f"extend: type a number of iterates, got {str(self.extend_input.value)[:30]!r}", error=True)
            return
        self.extend(o.id if o is not None else None, n)

    def extend(self, orbit_id, iterates: int) -> bool:
        """Extend a finished orbit by `iterates` more section points.  The run is repeated to the new length with
        the same integrator from the same start (so that its points are poincare_section's for the longer run,
        to the last bit); the points already drawn stay and only the new ones are streamed."""
        o = next((o for o in self.orbits if o.id == orbit_id), None)
        if o is None:
            self._say("Select an orbit in the list to extend it.")
            return False
        if o.status != "done" or o.start is None:
            self._say(f"#{o.id} is {o.status}: only a finished orbit can be extended.", error=True)
            return False
        if not 1 <= iterates <= model.ITERATES_MAX - o.n_points:
            self._say(f"extend: between 1 and {model.ITERATES_MAX - o.n_points} iterates, got {iterates}", error=True)
            return False
        o.skip, o.iterates = o.n_points, o.n_points + int(iterates)
        o.t_launch = time.perf_counter()
        o.status, o.result = "running", None
        self._submit(o)
        self._say(f"#{o.id}: extending from {o.n_points} to {o.iterates} iterates …")
        return True

    def set_marker_size(self, size: int) -> None:
        """Marker size (px) of every orbit's points."""
        for src_r in [*self._free_slots, *[(o.source, o.renderer) for o in self.orbits if o.renderer is not None]]:
            src_r[1].set_size(int(size))

    def show_branches(self, branches) -> None:
        """Show the points, boundary and shading of these branches of the section only ("0": psi = 0, "pi":
        psi = pi)."""
        self._branches_shown.clear()
        self._branches_shown.update(b for b in branches if b in model.BRANCH_PSI)
        on_section_plane = PROJECTIONS[self.projection.value] == ("theta", "ptheta")
        for key, rs in self._branch_shading.items():
            for r in rs:
                r.visible = on_section_plane and key in self._branches_shown
        for _, g in [*self._free_slots, *[(o.source, o.renderer) for o in self.orbits if o.renderer is not None]]:
            g.update()

    def set_projection(self, name: str) -> None:
        """Show the orbits in another projection of the section (PROJECTIONS); the energy-level boundary belongs
        to θ – p̄θ and is hidden in the others."""
        xk, yk = PROJECTIONS[name]
        for key, rs in self._branch_shading.items():
            for r in rs:
                r.visible = (xk, yk) == ("theta", "ptheta") and key in self._branches_shown
        self.legend.visible = (xk, yk) == ("theta", "ptheta")
        self.fig.xaxis.axis_label, self.fig.yaxis.axis_label = AXIS_LABELS[xk], AXIS_LABELS[yk]
        xs, ys = [], []
        for o in self.orbits:
            if o.source is None or not o.shown:
                continue
            x = np.concatenate(o.shown[xk]) if o.shown[xk] else np.empty(0)
            y = np.concatenate(o.shown[yk]) if o.shown[yk] else np.empty(0)
            br = np.concatenate(o.shown["branch"]) if o.shown["branch"] else np.empty(0, dtype="<U2")
            o.source.data = {"x": x, "y": y, "branch": br}
            o.pending = None  # included: o.shown holds every point decimated so far
            xs.append(x)
            ys.append(y)
        if (xk, yk) == ("theta", "ptheta"):
            self._set_boundary()
            return
        for rng, vals in ((self.fig.x_range, xs), (self.fig.y_range, ys)):
            v = np.concatenate(vals) if vals else np.empty(0)
            v = v[np.isfinite(v)]
            if len(v):
                lo, hi = float(v.min()), float(v.max())
                pad = 0.05 * max(hi - lo, 1e-6)
                rng.start, rng.end = lo - pad, hi + pad

    def launch(self, theta0: float, ptheta0: float) -> Orbit | None:
        """Launch an orbit from (theta0, pbar_theta0) on the section (what a click does).  Returns the Orbit, or
        None with the reason in the status line (no energy root, theta0 outside (0, pi), ...)."""
        if self._closed:
            return None
        o = Orbit(self._next_id, float(theta0), float(ptheta0), t_launch=time.perf_counter(), iterates=self.iterates)
        if not self._launch(o):
            return None
        self._next_id += 1
        self.orbits.append(o)
        self._undo.append(("add", o))
        self._pending_select = o.id  # the list is refreshed by the next poll, after the first points went out
        self.start_marker.data = {"x": [o.theta0], "y": [o.ptheta0]}
        return o

    def _launch(self, o: Orbit) -> bool:
        """(Re)start `o` at the current parameters; False (and a message) if its start has no energy root."""
        if o.job is not None:
            self._worker.cancel(o.job.id)
            o.t_launch = time.perf_counter()
        try:
            start = solve_start(self.params, self.h, o.theta0, o.ptheta0, self.psi0)
        except ParameterError as exc:
            msg = self._no_root_message(exc, o)
            if o in self.orbits:  # a relaunch at new parameters: keep the start, say why it has no points
                o.start, o.status, o.message, o.n_points, o.result, o.indicator = None, "no root", msg, 0, None, None
                if o.source is not None:
                    o.source.data = _EMPTY_POINTS()
                self._style(o)
            else:
                self._say(msg, error=True)
            return False
        o.start, o.status, o.message, o.result, o.indicator, o.n_points = start, "running", start.describe(), None, \
            None, 0
        if o.renderer is None:
            self._take_slot(o)
        o.source.data = _EMPTY_POINTS()
        o.iterates = o.iterates or self.iterates
        o.stride = max(1, -(-o.iterates // DISPLAY_CAP))
        o.skip, o.shown, o.pending = 0, {k: [] for k in (*AXIS_LABELS, "branch")}, None
        self._style(o)
        self._submit(o)
        self._say(f"#{o.id}: {start.describe()}; integrating {o.iterates} iterates in the background …")
        return True

    def _submit(self, o: Orbit) -> None:
        job = Job(next(self._job_ids), o.start, o.iterates, self.direction)
        job.submitted = o.t_launch
        o.job = job
        self._worker.submit(job, on_chunk=lambda j, c: self._queue.put(("chunk", o, j, c)),
                            on_done=lambda j, r, ind: self._queue.put(("done", o, j, (r, ind))))

    def _no_root_message(self, exc: ParameterError, o: Orbit) -> str:
        where = f"(θ, p̄θ) = ({o.theta0:.4f}, {o.ptheta0:.4f})"
        if exc.name == "h":
            return (f"No orbit at {where}: H̄ = {self.h:g} has no real root p̄ψ there (the point lies outside the "
                    f"energy-level boundary of ψ = {self.psi0:g}, in its no-root region). {exc.message}")
        if exc.name == "mu":
            return f"No orbit at {where}: the radicand μ − 2λ̄p̄ψ of H̄ is negative for every p̄ψ. {exc.message}"
        return f"No orbit at {where}: {exc}"

    def _style(self, o: Orbit):
        g = getattr(o.indicator, "growth_exponent", None)
        colour = PENDING_COLOUR if g is None or not np.isfinite(g) else model.growth_colour(g, self.threshold)
        if o.renderer is not None:
            o.renderer.set_colour(colour)

    def _remove(self, o: Orbit):
        if o.job is not None:
            self._worker.cancel(o.job.id)
            if o.status == "running":
                o.status = "cancelled"
        if o.renderer is not None:  # the slot stays with the orbit: undo shows it again
            o.renderer.visible = False
        self.orbits.remove(o)

    def _restore(self, o: Orbit, index: int):
        self.orbits.insert(min(index, len(self.orbits)), o)
        if o.renderer is not None:
            o.renderer.visible = True
        if o.start is None or o.start.params != self.params or o.start.h != self.h or o.status == "cancelled":
            self._launch(o)

    def delete(self, orbit_id) -> None:
        """Delete an orbit (undoable)."""
        o = next((o for o in self.orbits if o.id == orbit_id), None)
        if o is None:
            self._say("Select an orbit in the list to delete it.")
            return
        i = self.orbits.index(o)
        self._remove(o)
        self._undo.append(("delete", o, i))
        self._refresh_list()
        self._say(f"Deleted #{o.id} (Undo restores it).")

    def clear(self) -> None:
        """Delete every orbit (undoable)."""
        if not self.orbits:
            return
        gone = list(self.orbits)
        for o in gone:
            self._remove(o)
        self._undo.append(("clear", gone))
        self._refresh_list()
        self._say(f"Cleared {len(gone)} orbit(s) (Undo restores them).")

    def undo(self) -> None:
        """Undo the last launch, delete or clear."""
        if not self._undo:
            self._say("Nothing to undo.")
            return
        action = self._undo.pop()
        if action[0] == "add":
            self._remove(action[1])
            self._say(f"Undid the launch of #{action[1].id}.")
        elif action[0] == "delete":
            self._restore(action[1], action[2])
            self._say(f"Restored #{action[1].id}.")
        else:
            for i, o in enumerate(action[1]):
                self._restore(o, i)
            self._say(f"Restored {len(action[1])} orbit(s).")
        self._refresh_list()

    def _refresh_list(self, select=None):
        opts = {o.label(self.threshold): o.id for o in self.orbits}
        keep = select if select is not None else self.orbit_list.value
        self.orbit_list.options = opts
        self.orbit_list.value = keep if keep in opts.values() else (next(iter(opts.values())) if opts else None)

    def _on_select(self, event):
        self._show_details()

    # ------------------------------------------------------------------------------------------------------
    # data from the workers
    # ------------------------------------------------------------------------------------------------------
    def poll(self) -> int:
        """Move the workers' output onto the page (the periodic callback; call it by hand without a server).
        Returns the number of messages handled.  Served, the poll's changes reach the page as one message (a
        document hold): every message repaints every drawn point, and a poll makes several changes (points, colour,
        list, status) that were painted one by one."""
        doc = self.fig.document if self._served else None
        if doc is None:
            return self._poll()
        from panel.io.document import hold  # nests safely with Panel's own holds (it releases only its own)

        with hold(doc, policy="combine"):
            return self._poll()

    def _poll(self) -> int:
        self._watch_connection()
        n = 0
        relabel = streamed_first = False
        while True:
            try:
                kind, o, job, payload = self._queue.get_nowait()
            except queue.Empty:
                break
            n += 1
            if kind == "call":
                payload()
                continue
            if kind == "rod":
                if job is not o.start:
                    continue
                if isinstance(payload, Exception):  # a drawing problem is a message, never a broken page
                    self.details.object += f"<br>rod not drawn: {_escape(str(payload))}"
                    continue
                o.rod_figure, o.rod_for = payload, job
                if self.selected() is o:
                    self.rod_pane.object, self.rod_pane.visible = payload, True
                continue
            if o.job is not job:  # output of a cancelled, superseded run
                continue
            if kind == "chunk":
                self._stream(o, payload)
                first = o.n_points == 0
                self._flush(o, force=first)
                if first:
                    self.latencies.append(time.perf_counter() - job.submitted)
                    streamed_first = True
                    self.stream_wall.append(time.time())
                o.n_points, o.max_abs_dH = max(o.skip, payload.n_total), payload.max_abs_dH
            else:
                self._flush(o, force=True)
                res, ind = payload
                o.result = res
                if res is None:
                    o.status, o.message = "failed", f"internal error: {ind}"
                else:
                    o.status = "done" if res.success else ("cancelled" if "cancelled" in res.message else "failed")
                    o.n_points = res.n_points
                    if isinstance(ind, Exception):
                        o.message = f"indicator not computed: {ind}"
                    else:
                        o.indicator = ind
                self._style(o)
                relabel = True
                if o.status == "failed":
                    self._say(f"#{o.id}: {res.message if res is not None else o.message}", error=True)
                else:
                    g = getattr(o.indicator, "growth_exponent", float("nan"))
                    self._say(f"#{o.id}: {o.n_points} iterates in {res.wall_s:.2f} s, max |H̄ − h| = "
                              f"{res.max_abs_dH:.1e}; growth exponent {g:.3g} "
                              f"({'chaotic' if g > self.threshold else 'regular'}: threshold {self.threshold:g}).")
        for o in self.orbits:  # the joined points of running orbits whose interval has passed
            if o.pending:
                self._flush(o)
        if self._pending_select is not None and not streamed_first:  # not in the poll that sends first points
            select, self._pending_select = self._pending_select, None
            self._refresh_list(select=select)
        if relabel:
            self._refresh_list()
            # the rod of an orbit selected because it was launched is drawn once no orbit computes: a 3-D tube is
            # the page's most expensive picture (software WebGL on a machine without a GPU), and drawing one per
            # finished orbit during a burst of clicks delayed every later click's first points
            self._show_details(rod=not any(q.status == "running" for q in self.orbits))
        self._refill_slots()
        return n

    def _stream(self, o: Orbit, c) -> None:
        """Append a chunk's points to the orbit's plot: those not drawn yet (an extension's rerun repeats the
        first o.skip points), decimated for display to every o.stride-th point of the orbit."""
        k = len(c.theta)
        idx = np.arange(c.n_total - k, c.n_total)
        keep = (idx >= o.skip) & (idx % o.stride == 0)
        if not keep.any():
            return
        cols = {"theta": c.theta[keep], "ptheta": c.ptheta[keep],
                "ppsi": c.ppsi[keep] if c.ppsi is not None else np.full(int(keep.sum()), np.nan),
                "branch": model.branch_of(c.psi[keep])}
        for name, v in cols.items():
            o.shown[name].append(v)
        o.pending = (o.pending or []) + [cols]

    def _flush(self, o: Orbit, force: bool = False) -> bool:
        """Send the orbit's pending points to the page in one message, if STREAM_INTERVAL_S has passed since the
        last one (or `force`: the first points, the end of the run)."""
        if not o.pending or o.source is None:
            return False
        now = time.perf_counter()
        if not force and now - o.last_stream < self._stream_interval():
            return False
        xk, yk = PROJECTIONS[self.projection.value]
        o.source.stream({"x": np.concatenate([c[xk] for c in o.pending]),
                         "y": np.concatenate([c[yk] for c in o.pending]),
                         "branch": np.concatenate([c["branch"] for c in o.pending])})
        o.pending, o.last_stream = None, now
        return True

    def _stream_interval(self) -> float:
        """Seconds between two messages of one orbit: STREAM_INTERVAL_S, longer when the plot holds many points
        (PAINT_POINTS_PER_S)."""
        drawn = sum(len(o.source.data["x"]) for o in self.orbits if o.source is not None)
        return max(STREAM_INTERVAL_S, drawn / PAINT_POINTS_PER_S)

    def wait(self, timeout: float = 60.0) -> bool:
        """Poll until no orbit is computing (for scripts and tests); True if all finished in time."""
        deadline = time.perf_counter() + timeout
        while time.perf_counter() < deadline:
            self.poll()
            if self._worker.running == 0 and all(o.status != "running" for o in self.orbits):
                self.poll()
                return True
            time.sleep(0.01)
        return False

    @property
    def running(self) -> int:
        """Orbits submitted and not finished (queued, computing their section or their indicator)."""
        return self._worker.running

    def _watch_connection(self):
        doc = pn.state.curdoc
        ctx = getattr(doc, "session_context", None) if doc is not None else None
        session = getattr(ctx, "session", None) if ctx is not None else None
        if session is None:
            return
        try:
            count = session.connection_count
        except Exception:  # the session is being destroyed
            return
        if count > 0:
            self._connected_once, self._lost_wall = True, None
        elif self._connected_once:
            # Bokeh stamps the moment the page's connection went away (monotonic clock); measuring from there,
            # not from this poll, makes the recorded reaction time include the poll's own delay.
            gone_s = session.milliseconds_since_last_unsubscribe / 1000
            if self._lost_wall is None:
                self._lost_wall = time.time() - gone_s
            if gone_s > CLOSE_GRACE_S:
                self.close()

    def close(self) -> None:
        """Stop every computation of this page (page closed or server stopping) and the periodic callback."""
        if self._closed:
            return
        self._closed = True
        cancelled = time.time()
        if self._callback is not None:
            try:
                self._callback.stop()
            except Exception:
                pass
        self._worker.shutdown(timeout=0.5)
        # (connection lost at the server, cancel issued, worker threads joined): wall-clock times, for /status
        self.closed_wall = (self._lost_wall, cancelled, time.time())
        if self._registry is not None:
            self._registry.discard(self)

    # ------------------------------------------------------------------------------------------------------
    # the selected orbit
    # ------------------------------------------------------------------------------------------------------
    def selected(self) -> Orbit | None:
        return next((o for o in self.orbits if o.id == self.orbit_list.value), None)

    def _show_details(self, rod: bool = True):
        """The selected orbit's details, and its rod (rod=True) or, while orbits compute, a line saying when the
        rod comes (rod=False; a selection by the user always draws it)."""
        o = self.selected()
        if o is None:
            self.details.object, self.rod_pane.visible = "", False
            return
        shown = sum(len(v) for v in (o.shown or {}).get("theta", []))
        rows = [f"<b>#{o.id}</b> start θ₀ = {o.theta0!r}, p̄θ₀ = {o.ptheta0!r}, ψ₀ = {self.psi0:g} (exact doubles)",
                o.message, f"{o.n_points} iterates computed, {shown} drawn"
                + (f" (every {o.stride}th: display only; exports keep every point)" if o.stride > 1 else "")]
        r = o.result
        if r is not None:
            rows.append(f"{r.n_points} iterates to s = {r.final_time:.6g} in {r.wall_s:.2f} s "
                        f"(body frame, tol = machine ε)")
            rows.append(f"conservation: max |H̄ − h| = {r.max_abs_dH:.2e}, Casimir drift "
                        f"{(r.casimir_drift or 0):.2e} (gates {r.accuracy_checks()['energy_tol']:g}); "
                        f"max |section residual| = {float(np.max(np.abs(r.section_residual))) if r.n_points else 0:.1e}")
        ind = o.indicator
        if ind is not None:
            rows.append(f"chaos indicator (T = {ind.t_max:g}): growth exponent {ind.growth_exponent:.4g} → "
                        f"{'chaotic' if ind.chaotic else 'regular'} (threshold {ind.threshold:g}); "
                        f"finite-time Lyapunov exponent {ind.lyap:.3g}; conservation along it "
                        f"|dH| {ind.max_abs_dH:.1e}, Casimirs {ind.casimir_drift:.1e}")
        if not rod and o.status == "done":
            rows.append("rod: drawn when no orbit is computing (or select the orbit); the rod shown names its orbit")
        self.details.object = "<br>".join(rows)
        if rod:
            self._show_rod(o)
        # else the rod shown stays (its title names its orbit): hiding and showing the pane relayouted the page,
        # and every relayout repaints every point of the plot

    def _show_rod(self, o: Orbit):
        """Compute the rod of `o` on a worker thread (it integrates the frame: never on the page's event loop);
        poll() shows it when it arrives, if `o` is still the selected orbit."""
        if o.start is None or o.status != "done":  # not while the orbit computes: its first points come first
            return  # the rod shown (titled with its orbit) stays: a hidden pane relayouts the page
        if getattr(o, "rod_figure", None) is not None and o.rod_for is o.start:
            self.rod_pane.object, self.rod_pane.visible = o.rod_figure, True
            return
        start = o.start
        self._worker.call(lambda: rod_figure(start, self.rod_length, label=f"#{o.id}"),
                          lambda fig: self._queue.put(("rod", o, start, fig)))

    # ------------------------------------------------------------------------------------------------------
    # export
    # ------------------------------------------------------------------------------------------------------
    def export(self, out_dir) -> dict:
        """Write the picture (section.png) and, per finished orbit, orbitNN.npz/.json/.png with the schema of
        `magrod poincare --out` (magrod.figures.poincare.save_result), plus explore.json (the index)."""
        from .export import export_orbits

        return export_orbits(self, out_dir)

    def _export_zip(self):
        with tempfile.TemporaryDirectory(prefix="magrod-explore-") as d:
            paths = self.export(d)
            buf = io.BytesIO()
            with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
                for p in sorted(Path(d).iterdir()):
                    z.write(p, p.name)
        buf.seek(0)
        self._queue.put(("call", None, None, lambda: self._say(f"Prepared {len(paths['files'])} file(s) for "
                                                               f"download.")))
        return buf

    def _export_clicked(self):
        try:
            paths = self.export(self.out_dir)
        except (OSError, ParameterError) as exc:
            self._say(f"Export failed: {exc}", error=True)
            return
        self._say(f"Exported {len(paths['files'])} file(s) to {self.out_dir}")

    def _say(self, text: str, error: bool = False):
        colour = "#b00020" if error else "#222222"
        self.status.object = f'<span style="color:{colour}">{_escape(text)}</span>'

    def summary(self) -> dict:
        return {"panel": self.panel_key, "parameters": self.params.to_dict(), "h": self.h, "psi0": self.psi0,
                "direction": self.direction, "iterates": self.iterates, "threshold": self.threshold,
                "orbits": [{"id": o.id, "theta0": o.theta0, "ptheta0": o.ptheta0, "status": o.status,
                            "n_points": o.n_points, "message": o.message,
                            "growth_exponent": getattr(o.indicator, "growth_exponent", None)} for o in self.orbits]}

    def __repr__(self) -> str:
        return (f"Explorer(panel={self.panel_key!r}, params={self.params}, h={self.h:g}, "
                f"orbits={len(self.orbits)}, running={self.running})")


def _EMPTY_POINTS() -> dict:
    return {"x": [], "y": [], "branch": []}


class _Glyphs:
    """The scatters of one orbit, one per branch of the section, shown as one: visible when the orbit is and its
    branch is among the branches shown (`shown`, the page's set); one size and one colour (its growth exponent)."""

    def __init__(self, renderers: dict, shown: set):
        self.renderers, self._shown, self._visible = renderers, shown, False

    @property
    def visible(self) -> bool:
        return self._visible

    @visible.setter
    def visible(self, value: bool) -> None:
        self._visible = bool(value)
        self.update()

    def update(self) -> None:
        for b, r in self.renderers.items():
            r.visible = self._visible and b in self._shown

    @property
    def glyph(self):
        """The psi = 0 scatter's glyph (size, colour: those of the orbit)."""
        return self.renderers["0"].glyph

    def set_size(self, size: int) -> None:
        for b, r in self.renderers.items():  # the triangle one px larger: same visual weight as the circle
            r.glyph.size = size + (1 if b == "pi" else 0)

    def set_colour(self, colour: str) -> None:
        for r in self.renderers.values():
            r.glyph.fill_color = colour
            r.glyph.line_color = colour


class _Text:
    """A text line of the page as a bare Bokeh Div: setting `.object` changes one string property.  (A Panel HTML
    pane re-renders its model, and Bokeh then re-walks the whole document: ~0.3-2 s on the event loop.)"""

    def __init__(self, text, css_class, **kw):
        from bokeh.models import Div

        margin = kw.pop("margin", None)
        self.div = Div(text=text, css_classes=[css_class], **({"margin": margin} if margin else {}),
                       **{k: v for k, v in kw.items()})
        self.pane = pn.pane.Bokeh(self.div, sizing_mode=kw.get("sizing_mode"))

    @property
    def object(self) -> str:
        return self.div.text

    @object.setter
    def object(self, text: str) -> None:
        self.div.text = text


def _same_number(text, value) -> bool:
    try:
        return float(str(text).strip()) == float(value)
    except ValueError:
        return False


def _escape(s: str) -> str:
    return s.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def rod_figure(start, length: float, label: str = ""):
    """A plotly figure of the rod from `start`: the centreline over [0, length] as a tube (transverse
    displacements magnified, factor in the title), coloured by arclength."""
    import plotly.graph_objects as go

    rod = model.rod_of(start, length)
    c = rod["r_drawn"][:: max(1, len(rod["r_drawn"]) // 800)]
    s = rod["s"][:: max(1, len(rod["s"]) // 800)]
    ext = float(np.max(c.max(0) - c.min(0))) or 1.0
    mesh = model.tube_mesh(c, radius=0.006 * ext)
    v = mesh["vertices"]
    k = v.shape[0] // len(c)
    fig = go.Figure(go.Mesh3d(x=v[:, 0], y=v[:, 1], z=v[:, 2], i=mesh["i"], j=mesh["j"], k=mesh["k"],
                              intensity=np.repeat(s, k), colorscale="Viridis", showscale=True,
                              colorbar=dict(title="s", len=0.6), flatshading=False))
    M = rod["magnification"]
    fig.update_layout(title=dict(text=f"rod {label + ' ' if label else ''}centreline, s ∈ [0, {length:g}] (units B/m3), "
                                      f"z along the field; "
                                      f"transverse displacements magnified ×{M:g}"
                                      f"{' (true scale)' if M == 1 else ''}<br>frame checks: |DᵀD − I| "
                                      f"{rod['orthonormality']:.0e}, |Dᵀz − e3| {rod['field_consistency']:.0e}",
                                 font=dict(size=11)),
                      # true proportions (aspectmode "data"); plotly's default eye (1.25, 1.25, 1.25) is so close
                      # that a long rod's ends leave the picture: the eye backs off along the long axis
                      scene=dict(aspectmode="data", xaxis_title="x", yaxis_title="y", zaxis_title="z (field)",
                                 camera=dict(eye=_rod_eye(c))),
                      margin=dict(l=0, r=0, t=50, b=0))
    return fig


def _rod_eye(c: np.ndarray) -> dict:
    """A camera eye that keeps the whole rod in view: plotly scales the scene so that its longest side is 1; at
    the default distance (|eye| = 2.2) a scene whose longest side is many times the others is cut at both ends.
    The eye moves back in proportion to the elongation (at most 3.5x) and looks from low elevation."""
    ext = np.maximum(c.max(0) - c.min(0), 1e-12)
    elong = float(ext.max() / max(np.sort(ext)[-2], 1e-12))
    k = float(np.clip(0.9 + 0.25 * elong, 1.0, 3.5))
    return dict(x=1.25 * k, y=1.25 * k, z=0.35 * k)


class Registry:
    """The live explorer sessions of one server (what /status reports and Ctrl-C stops)."""

    def __init__(self):
        self._items: set = set()
        self._lock = threading.Lock()
        self.latencies: list[float] = []
        self.closed: list = []  # (connection lost, cancelled, threads joined) wall-clock times of closed sessions

    def add(self, e: Explorer):
        with self._lock:
            self._items.add(e)

    def discard(self, e: Explorer):
        with self._lock:
            self.closed.append(e.closed_wall)
            self.latencies.extend(e.latencies)
            self._items.discard(e)

    def status(self) -> dict:
        with self._lock:
            items = list(self._items)
        threads = [t.name for t in threading.enumerate() if t.name.startswith("magrod-explore")]
        return {"sessions": len(items), "running": sum(e.running for e in items),
                "warm": bool(items) and all(e.warmed.is_set() for e in items),
                "worker_threads_alive": len(threads), "first_points_s": self.latencies + [x for e in items
                                                                                       for x in e.latencies],
                "tap_handler_s": [x for e in items for x in e.tap_handler_s],
                "tap_wall": [x for e in items for x in e.tap_wall],
                "stream_wall": [x for e in items for x in e.stream_wall], "closed": list(self.closed)}

    def close_all(self, timeout: float = 0.8) -> None:
        with self._lock:
            items = list(self._items)
        for e in items:
            e.close()


def status_json(registry: Registry) -> str:
    return json.dumps(registry.status())
