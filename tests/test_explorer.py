"""The explorer without a browser: the streamed section equals poincare_section, cancelling, the click path (root
rule, no-root messages), inputs validated as the CLI validates them, delete/clear/undo, the export schema, the
energy-level boundary, and `magrod explore`'s refusals of bad input (exit 2, one line, nothing bound).
The page in a real browser: tests/test_explorer_browser.py."""
from __future__ import annotations

import json
import socket
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

from helpers import free_port
import magrod as mr
from magrod.explorer import model, worker

pytest.importorskip("panel")


@pytest.fixture(scope="module")
def app():
    a = mr.explore("4a", iterates=300)
    yield a
    a.close()


def test_stream_equals_poincare_section():
    """Same integrator, same propagate calls: the streamed points are poincare_section's to the last bit, and the
    chunks, concatenated, are the result's points."""
    P = mr.panel("4a")
    st = worker.solve_start(P.params, P.h, P.theta0, P.ptheta0, P.psi0)
    chunks = []
    res = worker.stream_section(st, 400, emit=chunks.append)
    ref = mr.poincare_section("4a", iterates=400)
    assert res.success and ref.success
    np.testing.assert_array_equal(res.points, ref.points)
    np.testing.assert_array_equal(res.times, ref.times)
    assert res.summary()["roots"] == ref.summary()["roots"] and res.p_psi0 == ref.p_psi0
    th = np.concatenate([c.theta for c in chunks])
    pt = np.concatenate([c.ptheta for c in chunks])
    np.testing.assert_allclose(th, ref.points[:, 0], rtol=0, atol=1e-14)
    np.testing.assert_allclose(pt, ref.points[:, 2], rtol=0, atol=1e-14)
    assert chunks[0].n_total == worker.FIRST_CHUNK and chunks[-1].n_total == 400


def test_cancel_stops_within_a_crossing():
    P = mr.panel("4a")
    st = worker.solve_start(P.params, P.h, P.theta0, P.ptheta0, P.psi0)
    ev = threading.Event()
    seen = []

    def emit(c):
        seen.append(c.n_total)
        if c.n_total >= 50:
            ev.set()

    t = time.perf_counter()
    res = worker.stream_section(st, 1_000_000, cancel=ev, emit=emit)
    assert time.perf_counter() - t < 30
    assert not res.success and res.message.startswith("cancelled")
    assert 50 <= res.n_points < 1_000_000 and res.n_points - max(seen) <= 1


def test_worker_cancel_all_and_shutdown():
    P = mr.panel("4a")
    st = worker.solve_start(P.params, P.h, P.theta0, P.ptheta0, P.psi0)
    w = worker.Worker(max_workers=2)
    started = threading.Event()
    jobs = [w.submit(worker.Job(i, st, 2_000_000, "positive"), on_chunk=lambda j, c: started.set()) for i in range(3)]
    assert started.wait(30)
    assert w.running == 3
    t = time.perf_counter()
    assert w.shutdown(timeout=1.0)
    assert time.perf_counter() - t < 1.0
    assert w.running == 0 and all(j.cancel.is_set() for j in jobs)
    assert not [t for t in threading.enumerate() if t.name.startswith("magrod-explore") and t.is_alive()]


def test_click_launches_with_the_paper_root(app):
    o = app.launch(0.1, 0.5)
    assert o is not None and app.wait(120)
    assert o.status == "done", o.message
    ref = mr.poincare_section("4a", iterates=300)
    np.testing.assert_array_equal(o.result.points, ref.points)
    assert o.start.root_index == 0 and len(o.start.roots) == 2  # the smaller of the two roots (fig:poincare1)
    assert "smallest" in o.message and f"{o.start.p_psi0:.10g}" in o.message
    ly = mr.lyapunov("4a")
    assert o.indicator.growth_exponent == pytest.approx(ly.growth_exponent, rel=1e-12)
    assert o.indicator.chaotic and f"growth {o.indicator.growth_exponent:.3g}" in o.label(app.threshold)
    assert list(o.source.data["x"]) == pytest.approx(list(ref.points[:, 0]), abs=1e-14)


@pytest.mark.parametrize("theta, ptheta, needle", [(1.5, 1.4, "no real root"), (0.12, 0.5, "no real root"),
                                                   (-0.2, 0.1, "theta0")])
def test_click_without_energy_root_is_a_message(app, theta, ptheta, needle):
    n = len(app.orbits)
    assert app.launch(theta, ptheta) is None
    assert len(app.orbits) == n and app.running == 0
    assert "No orbit" in app.status.object and needle in app.status.object


def test_negative_radicand_everywhere_is_a_message():
    a = mr.explore("4a")
    try:
        assert a.set_input("lam", "0") == ""
        # mu < 0 with lam = 0: sqrt(mu - 2 lam pbar_psi) is imaginary for every pbar_psi: refused at the widget
        assert "imaginary" in a.set_input("mu", "-0.1")
        assert a.params.mu == 0.4  # not applied
        # the same condition reached by a click (parameters set behind the widgets' back): a message, no worker
        a.params = a.params.replace(mu=-0.1)
        assert a.launch(0.5, 0.1) is None and a.running == 0
        assert "radicand" in a.status.object and "negative" in a.status.object
    finally:
        a.close()


@pytest.mark.parametrize("name, value, needle", [("delta", "-1", "delta: must be >= 0"),
                                                 ("m", "0", "m: must be > 0"),
                                                 ("gamma", "abc", "gamma: must be a number"),
                                                 ("iterates", "2.5", "iterates: must be an integer"),
                                                 ("iterates", "3000000", "iterates: must be <= 2000000"),
                                                 ("h", "1e7", "h: must satisfy |h| <= 1e+06"),
                                                 ("h", "-5", "h: no point of the section")])
def test_invalid_input_message_next_to_widget(name, value, needle):
    """The messages of `magrod poincare` for the same values (one parser), shown next to the widget."""
    a = mr.explore("4a")
    try:
        msg = a.set_input(name, value)
        assert needle in msg, msg
        assert a.params == mr.panel("4a").params and a.h == 0.9
        if name != "h" or value != "-5":  # the CLI refuses the same value naming the same option
            r = subprocess.run([sys.executable, "-m", "magrod.cli", "poincare", "--panel", "4a", f"--{name}", value,
                                "--iterates", "5" if name != "iterates" else value],
                               capture_output=True, text=True, timeout=120)
            assert r.returncode == 2 and needle.split(":")[0] in r.stderr
    finally:
        a.close()


def test_parameter_change_relaunches(app):
    a = mr.explore("4a", iterates=100)
    try:
        o = a.launch(0.1, 0.5)
        assert a.wait(120)
        assert a.set_input("lam", "0.186") == ""
        assert a.params.lam == 0.186 and o.status == "running"
        assert a.wait(120)
        ref = mr.poincare_section("4d", iterates=100)
        np.testing.assert_array_equal(o.result.points, ref.points)
    finally:
        a.close()


def test_delete_clear_undo():
    a = mr.explore("4a", iterates=50)
    try:
        o1, o2 = a.launch(0.1, 0.5), a.launch(1.0, 0.3)
        assert a.wait(120)
        assert [o.id for o in a.orbits] == [1, 2]
        a.delete(1)
        assert [o.id for o in a.orbits] == [2] and not o1.renderer.visible
        a.clear()
        assert a.orbits == []
        a.undo()
        assert [o.id for o in a.orbits] == [2]
        a.undo()
        assert [o.id for o in a.orbits] == [1, 2] and o1.renderer.visible
        a.undo()  # undo the launch of #2
        assert [o.id for o in a.orbits] == [1]
        assert o2.status in ("done", "cancelled")
    finally:
        a.close()


def test_export_has_the_poincare_schema(tmp_path, app):
    if not app.orbits:
        app.launch(0.1, 0.5)
    assert app.wait(120)
    paths = app.export(tmp_path / "exp")
    got = __import__("magrod.explorer.export", fromlist=["load_export"]).load_export(tmp_path / "exp")
    arrays, side = got["orbit01"]
    r = subprocess.run([sys.executable, "-m", "magrod.cli", "poincare", "--panel", "4a", "--iterates", "300", "--out",
                        str(tmp_path / "cli"), "--quiet"], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    cli_side = json.loads((tmp_path / "cli" / "fig4a.json").read_text())
    with np.load(tmp_path / "cli" / "fig4a.npz") as z:
        assert set(z.files) == set(arrays)
        np.testing.assert_array_equal(z["points"], arrays["points"])
    assert set(cli_side) <= set(side) and set(side) - set(cli_side) == {"explorer"}
    assert side["explorer"]["threshold"] == 3.0 and side["explorer"]["chaotic"] is True
    assert (tmp_path / "exp" / "section.png").stat().st_size > 10_000
    assert json.loads((tmp_path / "exp" / "explore.json").read_text())["exported"][0]["n_points"] == 300
    assert len(paths["files"]) == 5


def test_energy_boundary_agrees_with_the_root_solver():
    """Inside the curve solve_p_psi finds a root, outside it finds none (1% off the curve either way)."""
    P = mr.panel("4a")
    b = model.energy_boundary(P.params, P.h, n=61)
    from magrod.chaos.section import solve_p_psi

    for th, pm in list(zip(b["theta"], b["pmax"]))[::6]:
        assert len(solve_p_psi(P.params, P.h, th, 0.99 * pm)) >= 1
        with pytest.raises(mr.ParameterError):
            solve_p_psi(P.params, P.h, th, 1.01 * pm + 1e-9)


def test_colours_use_the_chaos_map_scale():
    from magrod.figures.chaos import growth_norm

    norm = growth_norm(model.GROWTH_VMAX, 3.0)
    assert float(norm(3.0)) == pytest.approx(0.5)
    assert model.colorbar_ticks(3.0)[0.5] == "3 (threshold)"
    assert model.growth_colour(0.5, 3.0) != model.growth_colour(20.0, 3.0)


# ----------------------------------------------------------------------------------------------------------------
# `magrod explore` on bad input: exit 2, one stderr line naming the option, nothing left listening
# ----------------------------------------------------------------------------------------------------------------
def _explore(*args):
    return subprocess.run([sys.executable, "-m", "magrod.cli", "explore", "--no-browser", *args], capture_output=True,
                          text=True, timeout=120)


_free_port = free_port

def _listening(port) -> bool:
    with socket.socket() as s:
        return s.connect_ex(("127.0.0.1", port)) == 0


@pytest.mark.parametrize("args, option", [(["--port", "0"], "port"), (["--port", "70000"], "port"),
                                          (["--port", "x"], "port"), (["--panel", "9z"], "panel"),
                                          (["--host", "0.0.0.0"], "host"), (["--host", "192.0.2.1"], "host"),
                                          (["--iterates", "0"], "iterates")])
def test_bad_input_exits_2(args, option):
    r = _explore(*args)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"magrod explore: error: {option}:"), r.stderr
    assert r.stdout == ""
    if "--port" in args and args[1].isdigit() and 1 <= int(args[1]) <= 65535:
        assert not _listening(int(args[1]))


def test_port_in_use_exits_2():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen(1)
        port = s.getsockname()[1]
        r = _explore("--port", str(port))
    assert r.returncode == 2
    assert r.stderr.strip().splitlines() == [f"magrod explore: error: port: 127.0.0.1:{port} is already in use; "
                                             "choose another --port"]


def test_bad_input_json():
    r = _explore("--port", "70000", "--json")
    assert r.returncode == 2
    d = json.loads(r.stdout)
    assert d["ok"] is False and d["parameter"] == "port" and d["exit_code"] == 2


def test_remote_host_needs_allow_remote():
    from magrod.explorer.server import check_address

    port = _free_port()
    assert check_address("localhost", port) == ("localhost", port)
    with pytest.raises(mr.ParameterError) as e:
        check_address("0.0.0.0", port)
    assert e.value.name == "host" and "--allow-remote" in e.value.message
    assert check_address("0.0.0.0", port, allow_remote=True)[1] == port  # bound and released, never contacted


def test_the_rod_of_a_launched_orbit_waits_until_no_orbit_computes(app):
    """A finished orbit, selected because it was launched, shows no rod while another orbit still computes (the
    tube is the page's costliest picture; one per finished orbit delayed the later clicks of a burst); once nothing
    computes the rod of the selection is drawn.  Seen to fail with the rod drawn at every finished orbit."""
    import time

    app.iterates = 20_000  # ~4 s: still computing when the second orbit is done
    long = app.launch(0.3, 0.2)
    app.iterates = 200
    short = app.launch(0.1, 0.5)
    deadline = time.perf_counter() + 120
    while short.status == "running" and time.perf_counter() < deadline:
        app.poll()
        time.sleep(0.01)
    assert short.status == "done" and long.status == "running", (short.status, long.status)
    app.poll()
    # no rod of `short` computed or shown (the pane may keep an earlier rod: its title names that orbit, and
    # hiding the pane relayouted the page, repainting every point)
    assert app.selected() is short and short.rod_figure is None
    assert "rod: drawn when no orbit is computing" in app.details.object
    assert app.wait(120) and long.status == "done"
    deadline = time.perf_counter() + 120
    while short.rod_figure is None and time.perf_counter() < deadline:  # the rod computes on a tail thread
        app.poll()
        time.sleep(0.02)
    assert app.selected() is short and app.rod_pane.visible and app.rod_pane.object is short.rod_figure
    assert f"rod #{short.id} " in short.rod_figure.layout.title.text


def test_a_new_orbit_does_not_queue_behind_an_earlier_indicator():
    """The sections and the indicators run on separate pools: with one thread each, a second orbit's first points
    arrive while the first orbit's chaos indicator (T = 20000, seconds) is still computing.  Seen to fail with one
    pool for both (the second section waited for the first indicator)."""
    P = mr.panel("4a")
    st = worker.solve_start(P.params, P.h, P.theta0, P.ptheta0, P.psi0)
    w = worker.Worker(max_workers=1)
    try:
        first_done = threading.Event()
        a = w.submit(worker.Job(1, st, 50, "positive"), on_chunk=lambda j, c: None,
                     on_done=lambda j, r, i: first_done.set(), indicator_t_max=20_000.0)
        assert a.future.result(60).n_points == 50  # a's section is done; its indicator runs on the tail pool
        got = threading.Event()
        w.submit(worker.Job(2, st, 50, "positive"), on_chunk=lambda j, c: got.set())
        assert got.wait(60)
        assert not first_done.is_set(), "the second orbit's first points waited for the first orbit's indicator"
    finally:
        w.shutdown(timeout=2.0)


def test_every_wrong_field_is_shown_and_no_typed_value_is_silently_stale():
    """Two wrong fields: both messages show (before, only the first field's); a valid field typed meanwhile says it
    is not applied and which value is in use (before: its box showed the new value, the plot the old one, no word).
    Seen to fail before input_errors existed."""
    a = mr.explore("4a")
    try:
        delta_in_use = a.params.delta
        assert "m: must be a number" in a.set_input("m", "abc")
        assert "gamma: must be a number" in a.set_input("gamma", "xyz")
        assert "m: must be a number" in a.errors["m"].object  # the first one is still there
        note = a.set_input("delta", "0.5")
        assert "not applied until m, gamma are fixed" in note and f"in use: {delta_in_use:g}" in note
        assert a.params.delta == delta_in_use
        a.set_input("m", "1.7")
        a.set_input("gamma", "0.15")  # everything valid: applied, every note gone
        assert a.params.delta == 0.5 and all(e.object == "" for e in a.errors.values())
    finally:
        a.close()


def test_orbit_list_row_is_short():
    """The list shows the start to 4 digits (the details keep the exact doubles), so the verdict fits its width.
    Seen to fail before (a click's start printed to 17 digits)."""
    from magrod.explorer.app import Orbit

    o = Orbit(3, 2.4987654321098765, -0.0030123456789012345, status="done", n_points=1000)
    assert o.label(3.0) == "#3: θ₀=2.499, p̄θ₀=-0.003012, 1000 pts"
