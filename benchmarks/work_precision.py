"""Benchmark (not a test): work-precision diagrams of magrod against its peers, in one run on one machine.

    python benchmarks/work_precision.py                         # everything (scipy's sweep takes ~10 min)
    python benchmarks/work_precision.py --only sections --repeat 3 --json wp.json --png wp.png
    python benchmarks/work_precision.py --only lyapunov

Sections: the Fig 4(a) orbit (start of fig:poincare1, h = 0.9, the smaller root pbar_psi0) over T = 10 665
(1000 section iterates), for a sweep of tolerances of every code:
  magrod scalar     poincare_section (body frame, heyoka Taylor, tol swept), section by stopping terminal events
  magrod batch      the same orbit in one lane of a full SIMD batch (three other orbits of the same level in the
                    other lanes); cost = batch wall time / batch width (throughput per orbit)
  JiTCODE DOP853    JiTCODE's C right-hand side of the 4-D reduced system (derive/, SymPy), scipy's Fortran
                    dop853, rtol swept (atol = rtol / 100); no events: sampled at the reference crossing times and
                    on a unit grid
  scipy DOP853      solve_ivp(method="DOP853") on the lambdified 4-D system, event sin(psi) = 0 (direction +),
                    rtol swept (atol = rtol / 100)
Errors: max |Hbar - h| (at the section points; JiTCODE: on the unit grid and at the reference crossing times) and
the distance to a long-double reference (magrod body frame in np.longdouble, tol = its epsilon) over the first 50
crossings: max over crossings of the chart distance (theta, psi mod 2 pi, pbar_theta, pbar_psi) between the
code's section points and the reference's (JiTCODE: its state at the reference crossing times).  Cost: wall time,
best of --repeat runs (scipy: one run per rtol, its runs take up to minutes), compile times excluded.

Lyapunov: the maximal exponent of the Fig 4(a) orbit over T = 1000 (renormalisation every 10): magrod's tangent
system in SIMD batches (body_indicators; cost per orbit = batch wall / width) and scalar, and JiTCODE's
jitcode_lyap + dop853, tolerances swept; accuracy = max |H - H0| along the orbit (JiTCODE draws its own random
tangent vector, so finite-time exponents differ by the start vector, not by accuracy: the exponents are listed).

Writes a PNG of the diagrams and a JSON of every point; prints the table of benchmarks/README.md.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from magrod.chaos import indicators as chaos  # noqa: E402
from magrod.chaos import batch as B  # noqa: E402
from magrod.chaos.portrait import grid_starts  # noqa: E402
from magrod.chaos.section import poincare_section  # noqa: E402
from magrod.core import systems  # noqa: E402
from magrod.core.printed import panel_kwargs  # noqa: E402
from _peers import compile_c  # noqa: E402  (benchmarks/: on sys.path as the script's directory)
import _smoke  # noqa: E402
from magrod.core.limits import LIMITS  # noqa: E402

N_CROSS = 50
MAGROD_TOLS = [2.0**-52, 1e-15, 1e-14, 1e-13, 1e-12, 1e-11, 1e-10, 1e-9, 1e-8, 1e-7, 1e-6]
JITCODE_RTOLS = [1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13, 1e-14]
SCIPY_RTOLS = [1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12]
LYAP_TOLS = [2.0**-52, 1e-14, 1e-13, 1e-12, 1e-11, 1e-10, 1e-9, 1e-8, 1e-7]
LYAP_RTOLS = [1e-6, 1e-8, 1e-10, 1e-12, 1e-13]


def uptime() -> str:
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    except OSError:
        return str(os.getloadavg())


def chart_dist(a, b) -> float:
    """max over rows of the chart distance, psi compared modulo 2 pi."""
    d = np.abs(np.asarray(a, float) - np.asarray(b, float))
    d[:, 1] = np.abs(np.angle(np.exp(1j * (np.asarray(a)[:, 1] - np.asarray(b)[:, 1]))))
    return float(np.max(d))


def best_of(f, repeat):
    walls, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = f()
        walls.append(time.perf_counter() - t0)
    return min(walls), out


# ----------------------------------------------------------------------------------------------------------
# sections
# ----------------------------------------------------------------------------------------------------------
def reference(T):
    kw = panel_kwargs("4a")
    t0 = time.perf_counter()
    ref = poincare_section(**kw, iterates=N_CROSS, precision="long double")
    print(f"  long-double reference: {ref.n_points} crossings in {time.perf_counter() - t0:.1f} s, max |dH| "
          f"{ref.max_abs_dH:.1e}", flush=True)
    return ref


def magrod_scalar(T, ref, repeat):
    kw = panel_kwargs("4a")
    rows = []
    for tol in MAGROD_TOLS:
        poincare_section(**kw, iterates=3, tol=tol, verify=False)  # build / load the integrator
        wall, r = best_of(lambda tol=tol: poincare_section(**kw, iterates=LIMITS["iterates"], t_max=T, tol=tol,
                                                           verify=False),
                          repeat)
        n = min(N_CROSS, r.n_points)
        rows.append(dict(tol=tol, wall_s=wall, max_abs_dH=r.max_abs_dH, n_points=r.n_points,
                         dist_ref=chart_dist(r.points[:n], ref.points[:n]) if n == N_CROSS else float("nan")))
        print(f"  magrod scalar tol {tol:.1e}: {wall:.3f} s, max|dH| {r.max_abs_dH:.1e}, dist {rows[-1]['dist_ref']:.1e},"
              f" {r.n_points} crossings", flush=True)
    return rows


def _batch_starts():
    """The Fig 4(a) orbit in lane 0 and three other starts of its level in the other lanes (SectionStart)."""
    from magrod.chaos.section import section_start

    kw = panel_kwargs("4a")
    b = systems.recommended_batch_size()
    others = grid_starts("4a", theta0=(0.3, 2.0, 4), ptheta0=(-0.5, 0.5, 3))[: b - 1]
    starts = [(kw["theta0"], kw["ptheta0"])] + [tuple(s) for s in others]
    return [section_start(kw["params"], kw["h"], th, pt, 0.0) for th, pt in starts]


def magrod_batch(T, ref, repeat):
    from magrod.chaos.section import SectionOptions, _Orbit
    from magrod.core.limits import LIMITS

    starts = _batch_starts()
    b = len(starts)
    rows = []
    for tol in MAGROD_TOLS:
        opts = SectionOptions(iterates=LIMITS["iterates"], t_max=T, tol=tol)

        def go(opts=opts):
            orbits = [_Orbit(s, opts) for s in starts]  # the lanes' orbits (section._Orbit: crossings, assembly)
            B.run(orbits, direction=opts.direction, tol=opts.taylor_tol, workers=1)
            return orbits[0].result

        go()  # build / load
        wall, r = best_of(go, repeat)
        n = min(N_CROSS, r.n_points)
        rows.append(dict(tol=tol, wall_s=wall / b, batch_wall_s=wall, max_abs_dH=r.max_abs_dH, n_points=r.n_points,
                         dist_ref=chart_dist(r.points[:n], ref.points[:n]) if n == N_CROSS else float("nan")))
        print(f"  magrod batch tol {tol:.1e}: {wall / b:.3f} s per orbit ({wall:.3f} s for {b}), max|dH| "
              f"{r.max_abs_dH:.1e}, dist {rows[-1]['dist_ref']:.1e}", flush=True)
    return rows


def jitcode_sweep(T, ref, repeat, rhs, state):
    try:
        import symengine
        from jitcode import jitcode, y
    except ImportError as exc:
        print(f"  JiTCODE unavailable: {exc}")
        return []
    kw = panel_kwargs("4a")
    y0 = np.array([kw["theta0"], kw["psi0"], kw["ptheta0"], ref.p_psi0])
    sub = {s: y(i) for i, s in enumerate(state)}
    f = [symengine.sympify(e.subs(sub)) for e in rhs]
    ode = jitcode(f, verbose=False)
    tc = time.perf_counter()
    compile_c(ode)
    compile_s = time.perf_counter() - tc
    H = systems.reduced_functions()["H"]
    pars = kw["params"].array()
    tref = ref.times[:N_CROSS]
    grid = np.unique(np.concatenate([tref, np.arange(1.0, T, 1.0)]))
    iref = np.searchsorted(grid, tref)
    rows = []
    for rtol in JITCODE_RTOLS:
        def go(rtol=rtol):
            ode.set_integrator("dop853", rtol=rtol, atol=rtol / 100, nsteps=10**9)
            ode.set_initial_value(y0, 0.0)
            Y = np.empty((grid.size, 4))
            for i, t in enumerate(grid):
                Y[i] = ode.integrate(t)
            return Y

        wall, Y = best_of(go, repeat)
        dH = float(np.nanmax(np.abs(H(np.ascontiguousarray(Y.T), pars)[0] - kw["h"])))
        rows.append(dict(rtol=rtol, wall_s=wall, max_abs_dH=dH, dist_ref=chart_dist(Y[iref], ref.points[:N_CROSS]),
                         compile_s=compile_s, samples=int(grid.size)))
        print(f"  JiTCODE rtol {rtol:.0e}: {wall:.3f} s, max|dH| {dH:.1e}, dist {rows[-1]['dist_ref']:.1e}", flush=True)
    return rows


def scipy_sweep(T, ref, rhs, state, rtols):
    import sympy as sp
    from scipy.integrate import solve_ivp

    kw = panel_kwargs("4a")
    f = sp.lambdify(state, rhs, modules="math")
    fun = lambda t, y: f(*y)  # noqa: E731
    ev = lambda t, y: math.sin(y[1])  # noqa: E731
    ev.direction = 1.0
    H = systems.reduced_functions()["H"]
    pars = kw["params"].array()
    y0 = [kw["theta0"], kw["psi0"], kw["ptheta0"], ref.p_psi0]
    rows = []
    for rtol in rtols:
        t0 = time.perf_counter()
        sol = solve_ivp(fun, (0.0, T), y0, method="DOP853", rtol=rtol, atol=rtol / 100, events=ev)
        wall = time.perf_counter() - t0
        Y = sol.y_events[0]
        dH = float(np.max(np.abs(H(np.ascontiguousarray(Y.T), pars)[0] - kw["h"]))) if Y.size else float("nan")
        n = min(N_CROSS, Y.shape[0])
        rows.append(dict(rtol=rtol, wall_s=wall, max_abs_dH=dH, n_points=int(Y.shape[0]), status=sol.status,
                         dist_ref=chart_dist(Y[:n], ref.points[:n]) if n == N_CROSS else float("nan")))
        print(f"  scipy DOP853 rtol {rtol:.0e}: {wall:.2f} s, max|dH| {dH:.1e}, dist {rows[-1]['dist_ref']:.1e}, "
              f"{Y.shape[0]} crossings", flush=True)
    return rows


def sections(repeat, scipy_rtols):
    from poincare_vs_peers import sympy_rhs

    kw = panel_kwargs("4a")
    probe = poincare_section(**kw, iterates=_smoke.n(1000, 2 * N_CROSS))
    T = probe.final_time + 1e-6
    print(f"== sections: Fig 4(a), T = {T:.1f} (1000 iterates), {N_CROSS} crossings against long double ==",
          flush=True)
    ref = reference(T)
    rhs, state = sympy_rhs()
    return dict(T=T, magrod_scalar=magrod_scalar(T, ref, repeat), magrod_batch=magrod_batch(T, ref, repeat),
                jitcode=jitcode_sweep(T, ref, repeat, rhs, state), scipy=scipy_sweep(T, ref, rhs, state, scipy_rtols))


# ----------------------------------------------------------------------------------------------------------
# Lyapunov exponent
# ----------------------------------------------------------------------------------------------------------
def lyapunov(repeat, span=1000.0):
    from chaos_vs_peers import fig4a, jitcode_lyap, magrod_scalar as lyap_scalar

    print(f"== maximal Lyapunov exponent, Fig 4(a), T = {span:g} ==", flush=True)
    x0, p = fig4a()
    b = systems.recommended_batch_size()
    X, P = np.repeat(x0[:, None], b, axis=1), np.repeat(p[:, None], b, axis=1)
    rows = {"magrod_batch": [], "magrod_scalar": [], "jitcode": []}
    for tol in LYAP_TOLS:
        chaos.body_indicators(x0, p, t_max=10.0, tol=tol)
        wall, ind = best_of(lambda tol=tol: chaos.body_indicators(X, P, t_max=span, tol=tol), repeat)
        rows["magrod_batch"].append(dict(tol=tol, wall_s=wall / b, lyap=float(ind.lyap[0]),
                                         max_abs_dH=float(np.max(ind.max_abs_dH))))
        print(f"  magrod batch tol {tol:.1e}: {wall / b:.4f} s/orbit, lyap {ind.lyap[0]:.5f}, max|dH| "
              f"{np.max(ind.max_abs_dH):.1e}", flush=True)
    for tol in (None, 1e-12, 1e-10, 1e-8):
        w, lam, dH = min((lyap_scalar(span, tol=tol) for _ in range(repeat)), key=lambda r: r[0])
        rows["magrod_scalar"].append(dict(tol=tol or 2.0**-52, wall_s=w, lyap=lam, max_abs_dH=dH))
        print(f"  magrod scalar tol {tol or 2.0**-52:.1e}: {w:.4f} s, lyap {lam:.5f}, max|dH| {dH:.1e}", flush=True)
    for rtol in LYAP_RTOLS:
        try:
            w, lam, dH, c = min((jitcode_lyap(span, rtol, rtol / 100) for _ in range(repeat)), key=lambda r: r[0])
        except Exception as exc:  # pragma: no cover - optional peer
            print(f"  JiTCODE unavailable: {type(exc).__name__}: {exc}")
            break
        rows["jitcode"].append(dict(rtol=rtol, wall_s=w, lyap=lam, max_abs_dH=dH, compile_s=c))
        print(f"  jitcode_lyap rtol {rtol:.0e}: {w:.4f} s, lyap {lam:.5f}, max|dH| {dH:.1e}", flush=True)
    return rows


# ----------------------------------------------------------------------------------------------------------
def draw(res, path):
    import matplotlib

    matplotlib.use("Agg")  # a script, not the library: choosing the backend here is fine
    import matplotlib.pyplot as plt

    panels = [k for k in ("sections", "lyapunov") if k in res]
    ncol = 2 * ("sections" in res) + ("lyapunov" in res)
    fig, axes = plt.subplots(1, ncol, figsize=(5.2 * ncol, 4.4), dpi=130, layout="constrained")
    axes = np.atleast_1d(axes)
    style = {"magrod_scalar": ("magrod scalar (tol sweep)", "o-", "tab:blue"),
             "magrod_batch": ("magrod batch, per orbit", "s-", "tab:green"),
             "jitcode": ("JiTCODE + dop853 (rtol sweep)", "^-", "tab:orange"),
             "scipy": ("scipy solve_ivp DOP853 (rtol sweep)", "v-", "tab:red")}
    k = 0
    if "sections" in res:
        s = res["sections"]
        for err, title in (("max_abs_dH", "max |Hbar - h|"), ("dist_ref", f"distance to long double, first {N_CROSS} "
                                                                            f"crossings")):
            ax = axes[k]
            k += 1
            for code in ("magrod_scalar", "magrod_batch", "jitcode", "scipy"):
                rows = [r for r in s.get(code, []) if np.isfinite(r[err])]
                if rows:
                    lab, mk, c = style[code]
                    ax.loglog([r[err] for r in rows], [r["wall_s"] for r in rows], mk, color=c, label=lab, ms=4)
            ax.set_xlabel(title)
            ax.set_ylabel("wall time [s]")
            ax.set_title(f"Fig 4(a) section, T = {s['T']:.0f}", fontsize=9)
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=7)
    if "lyapunov" in res:
        ax = axes[k]
        for code in ("magrod_batch", "magrod_scalar", "jitcode"):
            rows = res["lyapunov"].get(code, [])
            if rows:
                lab, mk, c = style[code]
                ax.loglog([r["max_abs_dH"] for r in rows], [r["wall_s"] for r in rows], mk, color=c,
                          label=lab.replace("JiTCODE + dop853", "jitcode_lyap + dop853"), ms=4)
        ax.set_xlabel("max |H - H0| along the orbit")
        ax.set_ylabel("wall time per orbit [s]")
        ax.set_title("maximal Lyapunov exponent, Fig 4(a), T = 1000", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"work-precision, one run, {os.cpu_count()} cores, heyoka batch width "
                 f"{systems.recommended_batch_size()}; {res['uptime_before'].split('load')[-1].strip()}", fontsize=8)
    fig.savefig(path)
    del panels


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", default="sections,lyapunov")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--scipy-rtols", default=",".join(f"{r:g}" for r in SCIPY_RTOLS))
    ap.add_argument("--json", default="work_precision.json")
    ap.add_argument("--png", default="work_precision.png")
    ap.add_argument("--smoke", action="store_true", help=_smoke.HELP)
    a = ap.parse_args(argv)
    if _smoke.enable(a.smoke):  # one tolerance of each sweep, a few crossings, written into a temporary directory
        import tempfile

        global N_CROSS, MAGROD_TOLS, JITCODE_RTOLS, LYAP_TOLS, LYAP_RTOLS
        N_CROSS, MAGROD_TOLS, JITCODE_RTOLS, LYAP_TOLS, LYAP_RTOLS = 3, MAGROD_TOLS[:1], [1e-10], [2.0**-52], [1e-10]
        a.repeat, a.scipy_rtols = 1, "1e-8"
        tmp = tempfile.mkdtemp(prefix="magrod-smoke-")
        a.json, a.png = os.path.join(tmp, "wp.json"), os.path.join(tmp, "wp.png")
    res = {"uptime_before": uptime()}
    print(res["uptime_before"], flush=True)
    for part in a.only.split(","):
        if part == "sections":
            res["sections"] = sections(a.repeat, [float(x) for x in a.scipy_rtols.split(",") if x])
        elif part == "lyapunov":
            res["lyapunov"] = lyapunov(a.repeat, _smoke.n(1000.0, 20.0))
    res["uptime_after"] = uptime()
    print(res["uptime_after"])
    with open(a.json, "w") as fh:
        json.dump(res, fh, indent=2, default=str)
    draw(res, a.png)
    print(f"wrote {a.json}, {a.png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
