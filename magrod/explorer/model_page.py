"""The explorer's page for a rod model other than the paper's: what the engine offers for every model, drawn.

The paper's page (app.py) launches an orbit where the user clicks on the section sin(psi) = 0, drawn in the paper's
reduced Euler chart (theta, pbar_theta), and solves Hbar = h for pbar_psi at the click.  That needs the chart; a
model without it (every model of the registry but the paper's rod, and every model file) gets this page: the
engine's energy-level section of several orbits in the model's body frame (`magrod.poincare_section` with the
model), computed in a background thread, drawn in two state coordinates the user picks, with the conservation
achieved (max |H - h|, max |C - C0|).  The page says, by name, what it cannot do for the model and why.
"""
from __future__ import annotations

import threading
import time

import numpy as np
import panel as pn

N_ORBITS = 6  # orbits of the section: the engine's seeded starts around the model's reference state
COLOURS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2")


def limitation(model: str) -> str:
    """What the page cannot do for `model`, and why (the structure the model lacks, by name)."""
    return (f"launching an orbit by a click needs the paper's reduced Euler chart (theta, pbar_theta) of the section, "
            f"and the model {model!r} has none: this page draws the engine's section of {N_ORBITS} orbits from its "
            "seeded starts on one level of H and the Casimirs, in the model's body frame")


class SectionView:
    """The page's view of a model's section, whichever way the engine returns it: `points` (N, iterates, dim), NaN
    where an orbit stopped early; `energy_error` = max |H - h| and `casimir_error` = the largest Casimir drift over
    the orbits; `success` and `message` (the first failing orbit's)."""

    def __init__(self, success, message, points, energy_error, casimir_error):
        self.success, self.message, self.points = bool(success), str(message), points
        self.energy_error, self.casimir_error = float(energy_error), float(casimir_error)

    @classmethod
    def of_runs(cls, runs, iterates: int) -> "SectionView":
        """From one result per orbit (each with `points` (n, dim), `max_abs_dH`, `casimir_drift`)."""
        dim = max(np.asarray(r.points).shape[-1] for r in runs)
        pts = np.full((len(runs), iterates, dim), np.nan)
        for k, r in enumerate(runs):
            q = np.asarray(r.points, float)[:iterates]
            pts[k, :len(q)] = q
        bad = [r for r in runs if not r.success]
        return cls(not bad, bad[0].message if bad else "ok", pts, max(float(r.max_abs_dH) for r in runs),
                   max(float(r.casimir_drift or 0.0) for r in runs))


def model_section(system, iterates: int) -> SectionView:
    """The engine's section of `system` (a System of any model): N_ORBITS orbits from its seeded starts on one
    level of H and the Casimirs, in the model's body frame."""
    from .. import poincare_sections

    return SectionView.of_runs(poincare_sections(system, starts=N_ORBITS, iterates=iterates), iterates)


class ModelExplorer(pn.viewable.Viewer):
    """The page of one session for a model other than the paper's rod; see `magrod.explore`."""

    def __init__(self, system, *, iterates: int = 1000, out_dir=None, registry=None, **params):
        super().__init__(**params)
        from bokeh.models import ColumnDataSource
        from bokeh.plotting import figure

        self.system = system
        self.iterates = int(iterates)
        self.out_dir = out_dir
        self.limited = limitation(system.model)
        self.result, self.error = None, None
        self.latencies, self.tap_handler_s, self.tap_wall, self.stream_wall = [], [], [], []
        self.warmed = threading.Event()
        self.closed_wall = None
        self._closed = False
        self._done = threading.Event()
        self._doc = None
        # the hand-off between the computing thread and the page: the section is drawn either before a live page
        # exists (in the computing thread, while no session can show the models) or on the page's own thread
        self._lock = threading.Lock()
        self._registry = registry
        if registry is not None:
            registry.add(self)
        names = tuple(system.code.names.STATE)
        self.x_select = pn.widgets.Select(label="horizontal", options=list(names), value=names[0], width=140)
        self.y_select = pn.widgets.Select(label="vertical", options=list(names), value=names[min(1, len(names) - 1)],
                                          width=140)
        self.fig = figure(width=640, height=520, name="model-section", title=f"{system.model}: section in the body frame",
                          x_axis_label=self.x_select.value, y_axis_label=self.y_select.value)
        self.sources = [ColumnDataSource({"x": [], "y": []}, name=f"model-src-{k}") for k in range(N_ORBITS)]
        for k, src in enumerate(self.sources):
            self.fig.scatter("x", "y", source=src, size=2, color=COLOURS[k % len(COLOURS)])
        params_text = ", ".join(f"{k} = {v:g}" for k, v in system.params.items())
        self.status = pn.pane.Markdown(f"computing {N_ORBITS} orbits x {self.iterates} crossings ...",
                                       css_classes=["magrod-model-status"])
        self.notice = pn.pane.Markdown(f"**What this page offers for this model.** {self.limited}.",
                                       css_classes=["magrod-model-notice"])
        self._drawing = False
        self.x_select.param.watch(lambda e: None if self._drawing else self._draw(), "value")
        self.y_select.param.watch(lambda e: None if self._drawing else self._draw(), "value")
        self._layout = pn.Column(pn.pane.Markdown(f"## magrod explore: model `{system.model}`\n{params_text}"),
                                 self.notice, pn.Row(self.x_select, self.y_select), self.fig, self.status)
        self._thread = threading.Thread(target=self._compute, name="magrod-explore-model", daemon=True)
        self._t0 = time.perf_counter()
        self._thread.start()

    @property
    def running(self) -> int:
        """1 while the section is being computed, then 0."""
        return int(not self._done.is_set())

    def _compute(self):
        try:
            self.result = model_section(self.system, self.iterates)
        except Exception as exc:  # shown on the page, one line (the server keeps running)
            self.error = f"{type(exc).__name__}: {exc}"
        self.latencies.append(time.perf_counter() - self._t0)
        try:
            with self._lock:  # __panel__ cannot attach a page while this decides where to draw
                doc = self._doc
                live = doc is not None and getattr(doc, "session_context", None) is not None
                if not self._closed and not live:
                    self._first_draw()  # no live page yet: drawn before any session shows the models
            if live and not self._closed:
                doc.add_next_tick_callback(self._first_draw)  # Bokeh models change on the document's own thread
        finally:
            self.warmed.set()
            self._done.set()

    def _first_draw(self):
        """Draw in the two coordinates that vary most over the section (never the coordinate the section fixes),
        ties broken by state order; the user's choice afterwards is kept."""
        if self.result is not None and self.error is None:
            pts = np.asarray(self.result.points, float)
            with np.errstate(invalid="ignore"):
                spread = np.array([np.nanmax(pts[..., i]) - np.nanmin(pts[..., i]) if np.isfinite(pts[..., i]).any()
                                   else 0.0 for i in range(pts.shape[-1])])
            order = sorted(range(len(spread)), key=lambda i: (-spread[i], i))
            names = list(self.x_select.options)
            self._drawing = True
            self.x_select.value, self.y_select.value = names[order[0]], names[order[min(1, len(order) - 1)]]
            self._drawing = False
        self._draw()

    def _draw(self):
        names = list(self.x_select.options)
        ix, iy = names.index(self.x_select.value), names.index(self.y_select.value)
        self.fig.xaxis.axis_label, self.fig.yaxis.axis_label = self.x_select.value, self.y_select.value
        r = self.result
        if self.error is not None:
            self.status.object = f"**error:** {self.error}"
            return
        if r is None:
            return
        pts = np.asarray(r.points)
        for k, src in enumerate(self.sources):
            if k < pts.shape[0]:
                ok = np.isfinite(pts[k, :, ix]) & np.isfinite(pts[k, :, iy])
                src.data = {"x": pts[k, ok, ix], "y": pts[k, ok, iy]}
        verdict = "ok" if r.success else f"**failed:** {r.message}"
        self.status.object = (f"{pts.shape[0]} orbits x {pts.shape[1]} crossings; max |H - h| = "
                              f"{r.energy_error:.1e}, max |C - C0| = {r.casimir_error:.1e}; {verdict}")

    def wait(self, timeout: float = 60.0) -> bool:
        """True once the section is computed (for scripts and tests)."""
        return self._done.wait(timeout)

    def __panel__(self):
        with self._lock:  # after a draw in the computing thread, or before its hand-off (then on this page's thread)
            self._doc = pn.state.curdoc
        if self._doc is not None and getattr(self._doc, "session_context", None) is not None:
            pn.state.on_session_destroyed(lambda ctx: self.close())
        return self._layout

    def close(self) -> None:
        """Drop the page; a section still computing finishes in its daemon thread and is discarded."""
        if self._closed:
            return
        self._closed = True
        cancelled = time.time()
        self.closed_wall = (None, cancelled, time.time())
        if self._registry is not None:
            self._registry.discard(self)
