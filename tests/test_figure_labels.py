"""Figures people read at a glance: the chaos map's colour bar (label, ticks, threshold mark) and every other text
lies inside the saved picture at any figure size, and the scale puts the threshold at the middle of the bar."""
from __future__ import annotations

import numpy as np
import pytest

from magrod.chaos import maps
from magrod.figures.chaos import growth_norm, map_axes


def _fields(n=6, seed=1):
    g = np.random.default_rng(seed).uniform(0.5, 400.0, (n, n))
    return {"growth_exponent": g, "fli": g, "lyap": g / 100, "status": np.zeros((n, n), int)}


@pytest.mark.parametrize("size", [(3.2, 2.6), (4.0, 3.2), (6.4, 5.0), (9.0, 4.0), (12.0, 9.0)])
@pytest.mark.parametrize("indicator", ["growth", "fli"])
def test_nothing_clipped(size, indicator):
    from matplotlib.figure import Figure

    spec = maps.MapSpec(maps.parse_axis("x", "lam:0.12:0.2:6"), maps.parse_axis("y", "gamma:2:4:6"),
                        base=maps.panel_base("4a"), panel="4a", t_max=3000.0)
    fig = Figure(figsize=size, layout="constrained")
    ax = fig.add_subplot()
    map_axes(ax, _fields(), spec, indicator=indicator)
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig).draw()  # the layout engine runs at draw time
    box = fig.bbox
    renderer = fig.canvas.get_renderer()
    assert len(fig.axes) == 2  # the map and its colour bar
    for a in fig.axes:  # everything drawn for an axes: title, labels, tick labels, annotations, colour-bar label
        e = a.get_tightbbox(renderer)
        assert e.x0 >= box.x0 - 0.5 and e.y0 >= box.y0 - 0.5 and e.x1 <= box.x1 + 0.5 and e.y1 <= box.y1 + 0.5, \
            (a.get_label(), a.get_title(), a.get_ylabel(), e, box, size)
    label = fig.axes[1].get_ylabel().replace("\u00a0", " ")
    assert "chaotic > 3" in label or indicator != "growth"


def test_threshold_is_the_middle_of_the_bar():
    norm = growth_norm(1000.0, 3.0)
    assert float(norm(3.0)) == pytest.approx(0.5) and float(norm(0.0)) == 0.0 and float(norm(1000.0)) == 1.0
    assert float(norm(30.0)) == pytest.approx(0.5 + 0.5 * np.log(10) / np.log(1000 / 3))


# ---- figures for a paper (issue 29) ------------------------------------------------------------------------------
def _agg(fig):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig).draw()
    return fig


def test_covering_finds_a_legend_and_a_label_on_the_data_and_saving_clears_them(tmp_path):
    """A legend pinned on a curve and a label written over it are found by covering(); atomic_savefig moves both
    off the data (and off each other) and keeps them.  Seen to fail with clear_of_data's call removed from
    figures.common.atomic_savefig (the saved figure still had both boxes on the curve)."""
    from matplotlib.figure import Figure

    from magrod.figures.common import atomic_savefig, covering

    fig = Figure(figsize=(4, 3))
    ax = fig.add_subplot()
    x = np.linspace(0, 1, 200)
    ax.plot(x, 1 - x, "-", label="descending")
    ax.plot(x, 0.05 + 0 * x, ".", ms=2, label="floor")
    ax.legend(loc="upper left")                      # on the curve's start (0, 1)
    ax.annotate("p = 2.013", (0.5, 0.5), fontsize=9)  # on the curve's middle
    before = covering(_agg(fig))
    assert {w for _, w, _ in before} >= {"legend", "text 'p = 2.013'"}, before
    atomic_savefig(fig, tmp_path / "f.png")
    assert covering(_agg(fig)) == []
    assert ax.get_legend() is not None and ax.texts[0].get_text() == "p = 2.013"


def test_a_real_figure_is_saved_clear_of_its_data(tmp_path, monkeypatch):
    """Figure 2 (--quick) as built: every saved picture has no legend or label over its data.  Its left panel's
    legend covered 57 points of the derived integrand before (measured with this hook)."""
    import magrod.figures.common as common
    from magrod.figures import build

    seen = []
    orig = common.clear_of_data

    def hooked(fig):
        before = common.covering(fig)
        moved = orig(fig)
        seen.append((before, common.covering(fig)))
        return moved

    monkeypatch.setattr(common, "clear_of_data", hooked)
    build("2", tmp_path, quick=True)
    assert seen and all(after == [] for _, after in seen), seen
    assert any(before for before, _ in seen)  # the check ran on a figure that needed it


def test_a_legend_with_no_free_corner_goes_outside_and_stays_in_the_picture(tmp_path):
    """Data everywhere: the legend moves right of the axes and the saved picture grows to hold it (bbox tight).
    Seen to fail on Figure 6 before (its legend, moved outside under a layout engine, was cut at the edge)."""
    import matplotlib.image as mpimg
    from matplotlib.figure import Figure

    from magrod.figures.common import atomic_savefig, covering

    for layout in (None, "constrained", "tight_layout()"):  # Figure 6 calls tight_layout() before saving
        fig = Figure(figsize=(4, 3), dpi=100, layout=None if layout == "tight_layout()" else layout)
        ax = fig.add_subplot()
        g = np.linspace(0, 1, 40)
        X, Y = np.meshgrid(g, g)
        ax.plot(X.ravel(), Y.ravel(), ".", ms=2, label="a dense grid of points")
        ax.legend(loc="center")
        if layout == "tight_layout()":
            fig.tight_layout()
        path = atomic_savefig(fig, tmp_path / f"g{layout}.png")
        assert covering(_agg(fig)) == []
        leg = ax.get_legend().get_window_extent(fig.canvas.get_renderer())
        assert leg.x0 >= ax.get_window_extent(fig.canvas.get_renderer()).x1  # outside, on the right
        width_px = mpimg.imread(path).shape[1]
        assert width_px >= leg.x1 - fig.bbox.x0 - 2, (layout, width_px, leg)  # the picture holds the legend


def test_no_offset_tick_labels(tmp_path):
    """Ticks like 26.45008, 26.45012 are written out, never as "+2.645e1" and 0.00008.  Seen to fail without
    no_offsets() in atomic_savefig (the offset text read '+2.645e1')."""
    from matplotlib.figure import Figure

    from magrod.figures.common import atomic_savefig

    fig = Figure(figsize=(4, 3))
    ax = fig.add_subplot()
    ax.plot([0, 1, 2], [26.45008, 26.45010, 26.45012], "o")
    atomic_savefig(fig, tmp_path / "f.png")
    _agg(fig)
    assert ax.yaxis.get_offset_text().get_text() == ""
    assert any("26.45" in t.get_text() for t in ax.get_yticklabels())


def test_chaos_map_axes_are_mathematical_and_its_contour_explained():
    """The map's axes read lambda-bar and gamma (never lam, gamma as code names), and the colour-bar label says
    what the black line is.  Seen to fail before (labels 'lam', 'gamma'; no word on the contour), and the key under
    the map says it (the colour-bar label was four lines of prose)."""
    from matplotlib.figure import Figure

    spec = maps.MapSpec(maps.parse_axis("x", "lam:0.12:0.2:6"), maps.parse_axis("y", "gamma:2:4:6"),
                        base=maps.panel_base("4a"), panel="4a", t_max=3000.0)
    fig = Figure(figsize=(6.4, 5.0), layout="constrained")
    ax = fig.add_subplot()
    g = np.where(np.arange(36).reshape(6, 6) % 6 < 3, 1.0, 50.0)  # a regular and a chaotic half: one boundary
    map_axes(ax, {"growth_exponent": g, "fli": g, "lyap": g / 100, "status": np.zeros((6, 6), int)}, spec)
    assert ax.get_xlabel() == r"$\bar\lambda$" and ax.get_ylabel() == r"$\gamma$"
    assert len(ax.collections) >= 2  # the mesh and the contour
    bar_label = fig.axes[1].get_ylabel().replace("\u00a0", " ").replace("\n", " ")
    assert bar_label == "growth exponent (chaotic > 3)", bar_label  # one short line (it was four lines of prose)
    key = [t.get_text().replace("\u00a0", " ") for t in ax.get_legend().get_texts()]
    assert "growth exponent = 3 (chaotic/regular boundary)" in key and "missing" in key, key


def test_every_axis_label_of_the_figures_is_mathematical():
    """No figure module labels an axis with a parameter's code name (set_xlabel("lam"), "mu - 2 lam", "m").
    Read from the source: every literal passed to set_xlabel/set_ylabel.  Seen to fail on continuation.py
    before ("lam (mu = 2 lam)", "m", "mu - 2 lam")."""
    import ast
    import re
    from pathlib import Path

    import magrod.figures as figures

    code = re.compile(r"\b(lam|ptheta|pbar_theta|gamma|mu|delta)\b")
    bad = []
    for path in Path(figures.__file__).parent.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Call) and getattr(node.func, "attr", "") in ("set_xlabel", "set_ylabel"):
                for arg in node.args[:1]:
                    if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
                        text = re.sub(r"\$[^$]*\$", "", arg.value)  # mathtext is fine
                        if code.search(text) or text.strip() in ("m", "h"):
                            bad.append(f"{path.name}:{node.lineno} {arg.value!r}")
    assert not bad, bad


def test_figure_4_panels_share_their_ranges_and_dots_are_readable():
    """The four panels of Fig 4 are compared: one theta range and one pbar_theta range (the union), dots of at
    least 0.8 pt.  Seen to fail before (each panel autoscaled its own y-range; ',' markers of 1 px)."""
    from types import SimpleNamespace

    from magrod.core.params import RodParams
    from magrod.figures.poincare import panels_figure

    rng = np.random.default_rng(3)
    p = RodParams(m=1.7, mu=0.4, gamma=3, delta=3, lam=0.135)
    res = {}
    for i, k in enumerate(("4a", "4b", "4c", "4d")):
        pts = np.zeros((300, 4))
        pts[:, 0] = rng.uniform(0.2, 2.8, 300)
        pts[:, 2] = rng.uniform(-0.2 * (i + 1), 0.3 * (i + 1), 300)  # different ranges per panel
        res[k] = SimpleNamespace(points=pts, max_abs_dH=1e-14, params=p, h=0.9)
    fig = _agg(panels_figure(res, list(res), "4", 300))
    axes = fig.axes
    assert len(axes) == 4
    ylims = {tuple(np.round(a.get_ylim(), 12)) for a in axes}
    xlims = {tuple(np.round(a.get_xlim(), 12)) for a in axes}
    assert len(ylims) == 1 and len(xlims) == 1, (ylims, xlims)
    lo, hi = ylims.pop()
    assert lo <= -0.8 and hi >= 1.2  # the union of the four panels' data
    for a in axes:
        line = a.get_lines()[0]
        assert line.get_marker() == "." and line.get_markersize() >= 0.8


def test_every_contour_drawn_is_explained(tmp_path, monkeypatch):
    """Figure 3 (--quick) as built: every axes that draws contours has a legend with an entry per contour colour
    (the level sets and the homoclinic level).  Seen to fail before (fig3's portraits had no legend)."""
    from matplotlib.contour import ContourSet

    import magrod.figures.common as common
    from magrod.figures import build

    seen = []
    orig = common.clear_of_data

    def hooked(fig):
        seen.append(fig)
        return orig(fig)

    monkeypatch.setattr(common, "clear_of_data", hooked)
    build("3", tmp_path, quick=True)
    checked = 0
    for fig in seen:
        for ax in fig.axes:
            sets = [c for c in ax.collections if isinstance(c, ContourSet)]
            if not sets:
                continue
            colours = {tuple(np.round(np.atleast_2d(c.get_edgecolor())[0], 3)) for c in sets}
            leg = ax.get_legend()
            assert leg is not None, ax.get_title()
            assert len(leg.get_texts()) >= len(colours), (ax.get_title(), [t.get_text() for t in leg.get_texts()])
            checked += 1
    assert checked >= 3


@pytest.mark.parametrize("former", [False, True])
def test_a_control_point_does_not_stretch_the_log_axis(former):
    """The splitting figure's integrable controls (zero or at the rounding level) are drawn at a floor three decades
    under the measurements, marked "<=": the axis spans the measurements, not 1e-40.  The former drawing
    (max(|v|, 1e-40), former=True) is seen to fail the same check (the axis went down to 1e-40)."""
    from matplotlib.figure import Figure

    from magrod.figures.splitting import plot_control

    eps = np.array([0.05, 0.1, 0.2, 0.4])
    measured = 3e-3 * eps**4
    ctl = np.array([0.0, 1e-30, 0.0, 2e-17])
    ax = Figure().add_subplot()
    ax.loglog(eps, measured, "o-")
    if former:
        ax.loglog(eps, np.maximum(np.abs(ctl), 1e-40), "x")
    else:
        floor = plot_control(ax, eps, ctl, measured, "control")
        assert floor == pytest.approx(1e-3 * measured.min())
        assert any("\\leq" in t for t in [h.get_label() for h in ax.get_lines()])
    lo, hi = ax.get_ylim()
    decades = np.log10(hi) - np.log10(lo)
    assert (decades > 20) if former else (decades < 8), (lo, hi)


def test_model_section_axes_read_as_mathematics_and_its_title_has_no_diagnostics():
    """The landscape figure's section panels: axes $m_{2}$, $n_{2}$ (they read "m2", "n2"), and the title names the
    rod, its |dH| and |dC| being in the sidecar.  Seen to fail before (labels "m2", "n2"; title "... |dH| <= ...")."""
    from matplotlib.figure import Figure

    import magrod as mr
    from magrod.figures.models import math_name, plot_model_section

    secs = mr.poincare_sections("anisotropic", starts=2, iterates=3)
    ax = plot_model_section(secs, Figure().add_subplot(), x="m2", y="n2")
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("$m_{2}$", "$n_{2}$")
    assert "dH" not in ax.get_title() and "e-14" not in ax.get_title() and "Poincaré" in ax.get_title()
    assert math_name("eps") == r"$\varepsilon$" and math_name("ptheta") == r"$p_{\theta}$"


def test_fig4_panel_titles_carry_no_diagnostics():
    """Fig 4's panels are titled by the parameter that varies, in mathematics; max |Hbar - h| is in each panel's
    sidecar, not in its title, and the suptitle says Poincaré.  Seen to fail before ("[max|$\\bar H$-h| = 3.6e-14]"
    in every panel title, "Poincare")."""
    import magrod as mr
    from magrod.figures.poincare import panels_figure

    keys = ["4a", "4b", "4c", "4d"]
    results = {k: mr.poincare_section(k, iterates=20) for k in keys}
    fig = panels_figure(results, keys, "4", 20)
    titles = [ax.get_title() for ax in fig.axes]
    assert titles == [r"(a) $\bar\lambda = 0.135$", r"(b) $\bar\lambda = 0.1575$", r"(c) $\bar\lambda = 0.175$",
                      r"(d) $\bar\lambda = 0.186$"], titles
    sup = fig._suptitle.get_text()
    assert "Poincaré" in sup and "max" not in sup and "$h = 0.9$" in sup


def test_lyapunov_plot_title_says_its_verdict_plainly():
    """LyapunovResult.plot's title: the verdict, the growth exponent and the threshold, not the criterion's code
    ("(chaotic: chaotic iff growth_exponent = ...)").  Seen to fail before."""
    import magrod as mr
    from matplotlib.figure import Figure

    res = mr.lyapunov("4a", t_max=200)
    title = res.plot(ax=Figure().add_subplot()).get_title()
    verdict = "chaotic" if res.chaotic else "regular"
    assert f": {verdict} (growth exponent {res.growth_exponent:.3g}, threshold {res.threshold:g}" in title, title
    assert "iff" not in title and "growth_exponent" not in title
