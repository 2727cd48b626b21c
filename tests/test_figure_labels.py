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
