"""Figures compared with reviewed reference renders (tests/baseline/*.png), as matplotlib's own tests do
(matplotlib.testing.compare.compare_images, RMS tolerance): a change in what a figure shows (a title carrying
diagnostics again, a four-line colour-bar label, a lost legend) fails here, not only a changed string.  Cheap
figures only: a chaos map drawn from fixed fields (no integration) and a Poincaré panel of 300 iterates.

The references were rendered by this file (MAGROD_WRITE_BASELINE=1 writes them) and reviewed by eye; the RMS
tolerance absorbs anti-aliasing differences between FreeType builds, not a changed text or mark.  Seen to fail
with the figures as they were before (colour-bar label of four lines: RMS 62; panel title with
max|Hbar - h| and no mathtext: RMS 32)."""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np

BASELINE = Path(__file__).resolve().parent / "baseline"
TOL = 6.0  # RMS on 0..255 grey levels (matplotlib's own tests use 0-10 where fonts may differ)


def _check(fig, name, tmp_path):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.testing.compare import compare_images

    FigureCanvasAgg(fig)
    got = tmp_path / f"{name}.png"
    fig.savefig(got, dpi=80)
    ref = BASELINE / f"{name}.png"
    if os.environ.get("MAGROD_WRITE_BASELINE"):
        ref.write_bytes(got.read_bytes())
    out = os.environ.get("MAGROD_ARTIFACTS")
    if out:  # the render beside its reference, for a reviewer
        Path(out).mkdir(parents=True, exist_ok=True)
        (Path(out) / f"{name}.png").write_bytes(got.read_bytes())
    err = compare_images(str(ref), str(got), tol=TOL)
    assert err is None, err


def test_chaos_map_from_fixed_fields(tmp_path):
    from matplotlib.figure import Figure

    from magrod.chaos import maps
    from magrod.figures.chaos import map_axes

    spec = maps.MapSpec(maps.parse_axis("x", "lam:0.12:0.2:8"), maps.parse_axis("y", "gamma:2:4:8"),
                        base=maps.panel_base("4a"), panel="4a", t_max=3000.0)
    i, j = np.meshgrid(np.arange(8), np.arange(8))
    g = np.where(i + j < 8, 0.5 + 0.2 * i, 10.0 ** (0.3 * (i + j)))  # a regular corner, a chaotic rest
    status = np.zeros((8, 8), int)
    status[0, 7] = 1  # one missing point (grey)
    fig = Figure(figsize=(5.0, 4.0), layout="constrained")
    map_axes(fig.add_subplot(), {"growth_exponent": g, "fli": g, "lyap": g / 100, "status": status}, spec)
    _check(fig, "chaos_map", tmp_path)


def test_poincare_panel(tmp_path):
    import magrod as mr
    from matplotlib.figure import Figure

    res = mr.poincare_section("4a", iterates=300)
    fig = Figure(figsize=(5.0, 4.2), layout="constrained")
    res.plot(ax=fig.add_subplot())
    _check(fig, "poincare_4a", tmp_path)


def test_explorer_picture_shows_both_branches(tmp_path):
    """The explorer's exported section picture (section.png) on Fig 5(a) with the orbit from (2.499, -0.003) that
    crosses both branches: each branch's boundary and no-root shading (psi = 0 solid and grey, psi = pi dashed and
    hatched) and its own marker.  Seen to fail with the picture as it was (one boundary, at psi = 0: RMS 51)."""
    from matplotlib.testing.compare import compare_images

    import magrod as mr
    from magrod.explorer.export import section_picture

    app = mr.explore("5a", iterates=300)
    try:
        o = app.launch(2.499, -0.003)
        assert o is not None and app.wait(120) and o.status == "done", o and o.message
        got = section_picture(app, tmp_path / "explore_5a.png")
    finally:
        app.close()
    ref = BASELINE / "explore_5a.png"
    if os.environ.get("MAGROD_WRITE_BASELINE"):
        ref.write_bytes(Path(got).read_bytes())
    err = compare_images(str(ref), str(got), tol=TOL)
    assert err is None, err
