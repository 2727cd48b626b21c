"""Chaos indicators: magrod vs peers, batch vs scalar, 1 vs 2 Dask workers, a 128 x 128 map.

    python benchmarks/chaos_vs_peers.py                  # everything except the 128 x 128 map
    python benchmarks/chaos_vs_peers.py --only map128    # the 128 x 128 map, t_max = 1000, 2 workers

Per-orbit cost of the maximal exponent: the Fig 4(a) orbit (body frame, 9-D, start of fig:poincare1) over
T = --span with renormalisation every 10 time units, against
  * JiTCODE's jitcode_lyap (C right-hand side, scipy's DOP853 driver), rtol 1e-10 / atol 1e-12 and 1e-12/1e-14,
  * scipy solve_ivp(DOP853) on the lambdified 18-D tangent system (SymPy from heyoka via hy.to_sympy),
each reporting L(T)/T and max |H - H0| (the accuracy actually achieved).  Needs `pip install ".[bench,derive]"`.
Numbers are printed; benchmarks/README.md records them.  No timing is asserted anywhere.
"""
from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

from magrod.chaos import indicators as chaos, maps
from magrod.core import systems
from _peers import compile_c  # noqa: E402  (benchmarks/: on sys.path as the script's directory)


def fig4a():
    x0, p, _, _ = maps.start_point(maps.panel_base("4a"))
    return x0, p


def magrod_batch(span, lanes=8, tol=None):
    x0, p = fig4a()
    ind = chaos.body_indicators(x0, p, t_max=10.0, tol=tol)  # build / load the integrator outside the timing
    X, P = np.repeat(x0[:, None], lanes, axis=1), np.repeat(p[:, None], lanes, axis=1)
    t0 = time.perf_counter()
    ind = chaos.body_indicators(X, P, t_max=span, tol=tol)
    wall = time.perf_counter() - t0
    return wall / lanes, float(ind.lyap[0]), float(np.max(ind.max_abs_dH))


def magrod_scalar(span, tol=None):
    """The same tangent system in a scalar (non-batch) heyoka integrator: the batch-vs-scalar baseline."""
    x0, p = fig4a()
    ta = systems.taylor(systems.tangent_system(systems.system("body"), len(systems.PARAMS)), np.ones(18), p, tol=tol)
    H = systems.body_functions()["H"]
    w = chaos.project_neutral(x0[:, None], chaos.generic_w0(9, 1), p[:, None])[:, 0]
    ta.time, ta.state[:9], ta.state[9:] = 0.0, x0, w / np.linalg.norm(w)
    L, dH, H0 = 0.0, 0.0, H(x0, p)[0]
    t0 = time.perf_counter()
    nsteps, dt = chaos._steps(span, chaos.DEFAULT_RENORM_DT)
    for k in range(1, nsteps + 1):
        ta.propagate_until(k * dt)
        x = np.array(ta.state[:9])
        w = chaos.project_neutral(x[:, None], np.array(ta.state[9:])[:, None], p[:, None])[:, 0]
        n = np.linalg.norm(w)
        L += np.log(n)
        ta.state[9:] = w / n
        dH = max(dH, abs(H(x, p)[0] - H0))
    return time.perf_counter() - t0, L / span, dH


def _sympy_system():
    import sympy as sp
    import heyoka as hy

    x = systems.variables("body")
    xs = sp.symbols(" ".join(systems.STATE["body"]))
    f = [hy.to_sympy(r) for _, r in systems.system("body")]
    _, p = fig4a()
    names = {str(v): s for v, s in zip(x, xs)}
    # hy.to_sympy names parameters par[i] (with assumptions): substitute the Fig 4(a) values by name
    f = [fi.subs({s: (float(p[int(s.name[4:-1])]) if s.name.startswith("par[") else names[s.name])
                  for s in fi.free_symbols}) for fi in f]
    return xs, f


def scipy_dop853(span, rtol=1e-10, atol=1e-12):
    import sympy as sp
    from scipy.integrate import solve_ivp

    xs, f = _sympy_system()
    ws = sp.symbols("w0:9")
    J = sp.Matrix(f).jacobian(xs)
    rhs = sp.lambdify([xs, ws], [*f, *(J * sp.Matrix(ws))], "numpy")
    fun = lambda t, y: np.array(rhs(y[:9], y[9:]), dtype=float)  # noqa: E731
    x0, p = fig4a()
    H = systems.body_functions()["H"]
    w = chaos.project_neutral(x0[:, None], chaos.generic_w0(9, 1), p[:, None])[:, 0]
    y, L, dH, H0 = np.concatenate([x0, w / np.linalg.norm(w)]), 0.0, 0.0, H(x0, p)[0]
    nsteps, dt = chaos._steps(span, chaos.DEFAULT_RENORM_DT)
    t0 = time.perf_counter()
    for k in range(nsteps):
        y = solve_ivp(fun, (k * dt, (k + 1) * dt), y, method="DOP853", rtol=rtol, atol=atol).y[:, -1]
        wk = chaos.project_neutral(y[:9, None], y[9:, None], p[:, None])[:, 0]
        n = np.linalg.norm(wk)
        L += np.log(n)
        y[9:] = wk / n
        dH = max(dH, abs(H(y[:9], p)[0] - H0))
    return time.perf_counter() - t0, L / span, dH


def jitcode_lyap(span, rtol=1e-10, atol=1e-12):
    import symengine
    from jitcode import jitcode_lyap as JL, y as jy

    xs, f = _sympy_system()
    sub = {s: jy(i) for i, s in enumerate(xs)}
    fj = [symengine.sympify(fi).subs({symengine.Symbol(str(k)): v for k, v in sub.items()}) for fi in f]
    x0, p = fig4a()
    H = systems.body_functions()["H"]
    ode = JL(fj, n_lyap=1, verbose=False)
    t0 = time.perf_counter()
    compile_c(ode, omp=False)
    compile_s = time.perf_counter() - t0
    ode.set_integrator("dop853", rtol=rtol, atol=atol)
    ode.set_initial_value(x0, 0.0)
    nsteps, dt = chaos._steps(span, chaos.DEFAULT_RENORM_DT)
    lyaps, dH, H0 = [], 0.0, H(x0, p)[0]
    t0 = time.perf_counter()
    for k in range(1, nsteps + 1):
        state, lyap, _ = ode.integrate(k * dt)
        lyaps.append(lyap[0])
        dH = max(dH, abs(H(state[:9], p)[0] - H0))
    return time.perf_counter() - t0, float(np.mean(lyaps)), dH, compile_s


def peers(span):
    print(f"== per-orbit maximal exponent, Fig 4(a) orbit, T = {span:g}, renormalisation every 10 ==")
    rows = []
    for tol, name in ((None, "magrod batch (8 lanes), tol = eps"), (1e-10, "magrod batch (8 lanes), tol = 1e-10")):
        w, lam, dH = magrod_batch(span, tol=tol)
        rows.append((name, w, lam, dH))
    w, lam, dH = magrod_scalar(span)
    rows.append(("magrod scalar, tol = eps", w, lam, dH))
    for rtol, atol in ((1e-10, 1e-12), (1e-12, 1e-14)):
        try:
            w, lam, dH, c = jitcode_lyap(span, rtol, atol)
            rows.append((f"JiTCODE jitcode_lyap dop853 rtol {rtol:g} (compile {c:.1f} s excluded)", w, lam, dH))
        except Exception as exc:  # pragma: no cover - optional peer
            print(f"JiTCODE unavailable: {type(exc).__name__}: {exc}")
    w, lam, dH = scipy_dop853(span)
    rows.append(("scipy solve_ivp DOP853 rtol 1e-10, lambdified", w, lam, dH))
    base = rows[0][1]
    print(f"{'code':62s} {'s/orbit':>9s} {'L(T)/T':>9s} {'max|dH|':>9s} {'vs magrod':>9s}")
    for name, w, lam, dH in rows:
        print(f"{name:62s} {w:9.4f} {lam:9.5f} {dH:9.1e} {w / base:8.1f}x")


def batch_vs_scalar(span):
    b, _, _ = magrod_batch(span)
    s, _, _ = magrod_scalar(span)
    print(f"== batch vs scalar (T = {span:g}): {s / span * 1e6:.1f} us vs {b / span * 1e6:.1f} us per orbit per "
          f"unit time: batch throughput {s / b:.2f}x ==")


def workers(n=32, t_max=1000.0):
    from magrod.store import tiles as chaos_store

    spec = maps.MapSpec(maps.parse_axis("x", f"lam:0.12:0.2:{n}"), maps.parse_axis("y", f"gamma:2:4:{n}"),
                         base=maps.panel_base("4a"), t_max=t_max, tile=8)
    walls = {}
    for w in (1, 2):
        d = tempfile.mkdtemp()
        try:
            pth = chaos_store.paths(d, "b")
            chaos_store.create_or_open(spec, pth["store"], pth["tiles"])
            t0 = time.perf_counter()
            r = chaos_store.run_tiles(spec, pth["store"], pth["tiles"], workers=w)
            walls[w] = (time.perf_counter() - t0, r["task_wall_s"])
        finally:
            shutil.rmtree(d)
    print(f"== {n} x {n} map, T = {t_max:g}, tile 8: 1 worker {walls[1][0]:.1f} s (tasks {walls[1][1]:.1f} s), "
          f"2 workers {walls[2][0]:.1f} s (tasks {walls[2][1]:.1f} s): speed-up {walls[1][0] / walls[2][0]:.2f}x "
          f"(incl. cluster start-up) ==")


def map128():
    out = tempfile.mkdtemp()
    try:
        t0 = time.perf_counter()
        r = subprocess.run([sys.executable, "-m", "magrod.cli", "chaosmap", "--x", "lam:0:0.3:128", "--y",
                            "gamma:0:3:128", "--t-max", "1000", "--workers", "2", "--out", out, "--json"],
                           capture_output=True, text=True, cwd=tempfile.gettempdir())
        wall = time.perf_counter() - t0
        import json

        d = json.loads(r.stdout)
        print(f"== 128 x 128 map lam:0:0.3 x gamma:0:3, T = 1000, 2 workers: command wall {wall:.1f} s, map "
              f"{d['wall_s']:.1f} s, {d['orbits_per_s']:.0f} orbits/s, computed {d['computed']}, missing "
              f"{d['missing']}, fraction chaotic {d['fraction_chaotic']:.3f}, max |dH| {d['max_abs_dH']:.1e} ==")
    finally:
        shutil.rmtree(out)


if __name__ == "__main__":
    import _smoke

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", default="peers,batch,workers", help="peers, batch, workers, map128")
    ap.add_argument("--span", type=float, default=500.0)
    ap.add_argument("--smoke", action="store_true", help=_smoke.HELP)
    a = ap.parse_args()
    if _smoke.enable(a.smoke):
        a.span = 20.0
    print(f"heyoka SIMD width {systems.recommended_batch_size()}, {os.cpu_count()} cores")
    for part in a.only.split(","):
        {"peers": lambda: peers(a.span), "batch": lambda: batch_vs_scalar(_smoke.n(2000.0, 20.0)),
         "workers": lambda: workers(*_smoke.n((32, 1000.0), (8, 40.0))),
         "map128": map128}[part]()
