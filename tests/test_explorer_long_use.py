"""The explorer for long use, without a browser (issue 29): the plot holds no per-orbit legend (its frame cannot
shrink as orbits accumulate: tests/test_explorer_browser.py measures it), a typed start is the exact double of
its decimal, an extended orbit equals poincare_section for the longer run to the last bit, display-only
decimation keeps every point in the result, and the marker-size and projection controls act on every orbit."""
from __future__ import annotations

import numpy as np
import pytest

import magrod as mr

pytest.importorskip("panel")
from magrod.explorer import app as app_mod  # noqa: E402


@pytest.fixture(scope="module")
def page():
    a = mr.explore("4a", iterates=200)
    yield a
    a.close()


def test_typed_start_is_exact_and_extension_equals_the_longer_run(page):
    """Seen to fail with the `idx >= o.skip` filter of Explorer._stream removed (the rerun drew the first 200
    points a second time: 550 drawn), and before extend() existed."""
    page.start_inputs["theta0"].value = "0.1"
    page.start_inputs["ptheta0"].value = "0.5"
    o = page._launch_typed()
    assert o is not None and o.theta0 == 0.1 and o.ptheta0 == 0.5  # the doubles of the decimals, not a pixel
    assert page.wait(120) and o.status == "done", o.message
    ref = mr.poincare_section(mr.panel("4a").params, 0.9, 0.1, 0.5, 0.0, iterates=200)
    assert np.array_equal(o.result.points, ref.points)
    shown_before = len(o.source.data["x"])
    page.orbit_list.value = o.id
    page.extend_input.value = "150"
    page._extend_clicked()
    assert page.wait(120) and o.status == "done", o.message
    ref = mr.poincare_section(mr.panel("4a").params, 0.9, 0.1, 0.5, 0.0, iterates=350)
    assert o.n_points == 350 and np.array_equal(o.result.points, ref.points)
    x = np.asarray(o.source.data["x"])
    assert len(x) == 350 and shown_before == 200  # the first 200 were not drawn twice
    # the drawn points come from each chunk's chart conversion (evaluated chunk by chunk, so SIMD lanes may round
    # the last bit differently); the bit-exact claim is the result's, checked above with array_equal
    np.testing.assert_allclose(x, ref.points[:, 0], rtol=0, atol=1e-14)


def test_typed_start_bad_text_is_a_message(page):
    n = len(page.orbits)
    page.start_inputs["theta0"].value = "0.1.2"
    assert page._launch_typed() is None and len(page.orbits) == n
    assert "theta0" in page.status.object


def test_no_legend_item_per_orbit(page):
    """The plot's legend has one item per branch of the section (its marker and energy boundary) however many
    orbits there are; the orbits are listed in the scrolling list beside the plot.  Seen to fail before (one
    LegendItem per orbit slot)."""
    for th in (0.3, 0.6, 0.9, 1.2):
        page.launch(th, 0.0)
    assert page.wait(120)
    assert len(page.legend.items) == 2
    assert len(page.orbit_list.options) == len(page.orbits) >= 5


def test_display_decimation_keeps_every_point_in_the_result(monkeypatch):
    monkeypatch.setattr(app_mod, "DISPLAY_CAP", 100)
    a = mr.explore("4a", iterates=450)
    try:
        o = a.launch(0.1, 0.5)
        assert a.wait(120) and o.status == "done"
        assert o.stride == 5 and len(o.source.data["x"]) == 90  # every 5th of 450
        assert o.result.points.shape[0] == 450  # the result (and the export) keep all
        ref = mr.poincare_section("4a", iterates=450)
        np.testing.assert_allclose(np.asarray(o.source.data["x"]), ref.points[::5, 0], rtol=0, atol=1e-14)
    finally:
        a.close()


def test_marker_size_and_projection(page):
    page.set_marker_size(7)
    assert all(o.renderer.glyph.size == 7 for o in page.orbits)
    o = next(o for o in page.orbits if o.status == "done" and o.n_points)
    page.set_projection("θ – p̄ψ")
    assert page.fig.yaxis.axis_label == "p̄ψ" and not page.legend.visible
    ppsi = np.asarray(o.source.data["y"])
    # p_psi of the section points, from the result (its columns: theta, psi, ptheta, ppsi)
    np.testing.assert_allclose(ppsi, o.result.points[:, 3][::o.stride], rtol=0, atol=1e-14)
    page.set_projection("θ – p̄θ")
    assert page.legend.visible
    np.testing.assert_allclose(np.asarray(o.source.data["y"]), o.result.points[:, 2][::o.stride], rtol=0, atol=1e-14)


def test_no_renderer_is_added_during_a_click(monkeypatch):
    """Clicks beyond the renderers made with the page take renderers made between clicks (one batch), never a new
    one in the click: adding a renderer to a live page walks the whole document (~0.3-1 s on the event loop),
    which made every click after the 24th slower (the time per click crept up with the orbit count).  Seen to
    fail before the batch refill (slow_slots == 6 after 30 orbits with 24 slots; here 4 slots and 10 orbits)."""
    monkeypatch.setattr(app_mod, "N_SLOTS", 4)
    monkeypatch.setattr(app_mod, "SLOT_REFILL_AT", 2)
    from magrod.explorer import worker

    monkeypatch.setattr(worker, "growth_indicator", lambda *args: None)  # not what this test is about (~1 s each)
    a = mr.explore("4a", iterates=20)
    try:
        for k in range(10):
            o = a.launch(0.3 + 0.2 * k, 0.0)
            assert o is not None and a.wait(120) and o.status == "done", o and o.message
        assert a.slow_slots == 0 and len(a._free_slots) >= 1
        assert all(o.renderer.visible for o in a.orbits)
        assert len({id(o.source) for o in a.orbits}) == 10
    finally:
        a.close()
