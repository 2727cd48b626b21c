"""Benchmark (not a test): issue 18's panel, ensemble and diagram targets as ratios that hold on any machine
(issue 28, item 5): batched lanes against the scalar path and against JiTCODE, each in one run.

    python benchmarks/batch_ratios.py --json benchmarks/batch_ratios_w4.json
    MAGROD_BATCH_WIDTH=8 python benchmarks/batch_ratios.py --json benchmarks/batch_ratios_w8.json

Jobs (issue 18's, benchmarks/batch_sections.py):
  panels    the 8 panels of Figs 4-5 x 10 000 iterates: batched (poincare_sections, 2 threads) vs the scalar
            run_panels (2 threads)
  ensemble  64 orbits x 1000 iterates on the Fig 4(a) level: batched (2 threads) vs scalar one by one (the first
            --scalar-sample orbits timed, scaled to 64)
  diagram   200 lambdabar values x 500 iterates (0.131 .. 0.2, Fig 4's start): orbit_diagram (2 threads) vs scalar
            poincare_section per value (every 10th value timed, scaled)
Every job is timed by wall clock AND by the process CPU time (time.process_time: all threads).  On a shared
machine the wall times of a one-thread and a two-thread job are not comparable (the load takes cores), so the
ratio that holds on any machine is the CPU-time ratio: the work each path needs for the same answer.  The wall
ratio is printed too, with `uptime`.

Against JiTCODE (Fortran dop853 with a C right-hand side of the 4-D Euler-chart system, one thread, its compile
excluded; no events, sampled on a unit time grid as in poincare_vs_peers.py): a sample of each job's orbits
(their chart starts and parameters, from the batched run) is integrated for --jit-span time units each; the ratio
is JiTCODE's CPU seconds per unit of orbit time over the batched lanes' (CPU of the whole job / the summed final
times of its orbits), at rtol 1e-12 and 1e-14 (atol 1e-14); max |Hbar - h| on the grid is its accuracy, against
the lanes' max |Hbar - h| at the section points.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
import warnings

import numpy as np

from magrod.chaos.portrait import grid_starts, orbit_diagram
from magrod.chaos.section import poincare_section, poincare_sections, run_panels
from magrod.core import systems
from magrod.core.printed import PANELS, panel
from _peers import compile_c  # noqa: E402  (benchmarks/: on sys.path as the script's directory)
import _smoke  # noqa: E402

KEYS = list(PANELS)
RTOLS = (1e-12, 1e-14)


def uptime() -> str:
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    except OSError:
        return f"load {os.getloadavg()}"


def timed(f):
    w0, c0 = time.perf_counter(), time.process_time()
    out = f()
    return time.perf_counter() - w0, time.process_time() - c0, out


class Jit:
    """The 4-D chart system in JiTCODE with the rod's parameters as control parameters (compiled once)."""

    def __init__(self):
        import symengine
        from jitcode import jitcode, y

        from magrod.derive.build import reduced_module

        _, d = reduced_module()
        syms = {s.name: s for s in set().union(*[e.free_symbols for e in d["rhs"]])}
        state = [syms["theta"], syms["psi"], syms["pbar_theta"], syms["pbar_psi"]]
        self.pnames = ["m", "mu", "gamma", "delta", "lambdabar"]
        cp = [symengine.Symbol(n) for n in self.pnames]
        sub = {s: y(i) for i, s in enumerate(state)}
        sub.update({syms[n]: c for n, c in zip(self.pnames, cp)})
        f = [symengine.sympify(e.subs(sub)) for e in d["rhs"]]
        self.ode = jitcode(f, control_pars=cp, verbose=False)
        t0 = time.perf_counter()
        compile_c(self.ode)
        self.compile_s = time.perf_counter() - t0
        self.H = systems.reduced_functions()["H"]

    def run(self, results, span, rtol):
        """CPU seconds per unit time and max |Hbar - h| over `results` (PoincareResult) integrated for `span`."""
        c0 = time.process_time()
        worst = 0.0
        total = 0.0
        for r in results:
            p = r.params
            self.ode.set_integrator("dop853", rtol=rtol, atol=1e-14, nsteps=10**9)
            self.ode.set_parameters(p.m, p.mu, p.gamma, p.delta, p.lam)
            self.ode.set_initial_value(np.array([r.theta0, r.psi0, r.ptheta0, r.p_psi0]), 0.0)
            grid = np.arange(1.0, span + 0.5, 1.0)
            Y = np.empty((4, grid.size))
            for i, t in enumerate(grid):
                Y[:, i] = self.ode.integrate(t)
            total += grid[-1]
            with np.errstate(invalid="ignore"):
                dH = np.abs(self.H(np.ascontiguousarray(Y), p.array())[0] - r.h)
            worst = max(worst, float(np.nanmax(dH)) if np.isfinite(dH).any() else np.inf)
        return (time.process_time() - c0) / total, worst


def job_panels():
    poincare_sections(KEYS, iterates=10, workers=2)
    run_panels(KEYS, iterates=10, workers=2)
    it = _smoke.n(10_000, 10)
    wb, cb, rb = timed(lambda: poincare_sections(KEYS, iterates=it, workers=2))
    ws, cs, rs = timed(lambda: run_panels(KEYS, iterates=it, workers=2))
    return dict(batched=(wb, cb, rb), scalar=(ws, cs, list(rs.values())), scale=1.0, sample=rb)


def job_ensemble(scalar_sample):
    starts = grid_starts("4a", theta0=(0.1, 3.0, 10), ptheta0=(-1.0, 1.0, 10))[:_smoke.n(64, 4)]
    it = _smoke.n(1000, 10)
    poincare_sections("4a", starts=starts[:8], iterates=10, workers=2)
    wb, cb, rb = timed(lambda: poincare_sections("4a", starts=starts, iterates=it, workers=2))
    sub = starts[:scalar_sample]
    ws, cs, rs = timed(lambda: [poincare_section("4a", theta0=a, ptheta0=b, iterates=it) for a, b in sub])
    return dict(batched=(wb, cb, rb), scalar=(ws, cs, rs), scale=len(starts) / len(sub), sample=rb[:16])


def job_diagram():
    vals = np.linspace(0.131, 0.2, _smoke.n(200, 20))
    it = _smoke.n(500, 10)
    orbit_diagram("lam", vals[:4], iterates=10)
    wb, cb, od = timed(lambda: orbit_diagram("lam", vals, iterates=it, workers=2))
    rb = [o for o in od.orbits if o is not None]
    P = panel("4a")
    sub = vals[::10]
    ws, cs, rs = timed(lambda: [poincare_section(P.params.replace(lam=float(v)), P.h, P.theta0, P.ptheta0, P.psi0,
                                                 iterates=it) for v in sub])
    return dict(batched=(wb, cb, rb), scalar=(ws, cs, rs), scale=len(vals) / len(sub), sample=rb[::10])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", default="panels,ensemble,diagram")
    ap.add_argument("--scalar-sample", type=int, default=16)
    ap.add_argument("--jit-span", type=float, default=1000.0)
    ap.add_argument("--no-jitcode", action="store_true")
    ap.add_argument("--json", default=None)
    ap.add_argument("--smoke", action="store_true", help=_smoke.HELP)
    a = ap.parse_args(argv)
    if _smoke.enable(a.smoke):
        a.scalar_sample, a.jit_span, a.json = 2, 10.0, None
    warnings.simplefilter("ignore", DeprecationWarning)
    out = {"uptime_before": uptime(), "width": systems.batch_width(), "cores": os.cpu_count(), "jobs": {}}
    print(out["uptime_before"], f"| batch width {out['width']}", flush=True)
    jit = None
    if not a.no_jitcode:
        try:
            jit = Jit()
            out["jitcode_compile_s"] = jit.compile_s
        except ImportError as exc:
            out["jitcode"] = f"unavailable: {exc}"
    for name in a.only.split(","):
        r = {"panels": job_panels, "ensemble": lambda: job_ensemble(a.scalar_sample), "diagram": job_diagram}[name]()
        wb, cb, rb = r["batched"]
        ws, cs, rs = r["scalar"]
        ws, cs = ws * r["scale"], cs * r["scale"]
        orbit_time = float(sum(x.final_time for x in rb))
        row = {"batched_wall_s": wb, "batched_cpu_s": cb, "scalar_wall_s": ws, "scalar_cpu_s": cs,
               "scalar_scaled_by": r["scale"], "cpu_ratio_scalar_over_batched": cs / cb,
               "wall_ratio_scalar_over_batched": ws / wb, "orbits": len(rb), "orbit_time": orbit_time,
               "batched_cpu_per_unit_time": cb / orbit_time,
               "batched_max_dH": float(max(x.max_abs_dH for x in rb)),
               "scalar_max_dH": float(max(x.max_abs_dH for x in rs)), "all_ok": all(x.success for x in rb),
               "uptime": uptime()}
        if jit is not None:
            for rtol in RTOLS:
                per, dH = jit.run(r["sample"], a.jit_span, rtol)
                row[f"jitcode_rtol{rtol:g}"] = {"cpu_per_unit_time": per, "max_dH": dH, "orbits": len(r["sample"]),
                                                "span": a.jit_span,
                                                "cpu_ratio_jitcode_over_batched": per / row["batched_cpu_per_unit_time"]}
        out["jobs"][name] = row
        jt = "; ".join(f"JiTCODE rtol {k[12:]}: {v['cpu_ratio_jitcode_over_batched']:.1f}x (max|dH| {v['max_dH']:.1e})"
                       for k, v in row.items() if k.startswith("jitcode_"))
        print(f"== {name}: batched {wb:.2f} s wall / {cb:.2f} s CPU; scalar {ws:.2f} s wall / {cs:.2f} s CPU "
              f"(x{r['scale']:g}): CPU ratio {cs / cb:.2f}x, wall ratio {ws / wb:.2f}x; lanes max|dH| "
              f"{row['batched_max_dH']:.1e}; {jt} | {row['uptime'][-30:]}", flush=True)
    out["uptime_after"] = uptime()
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(out, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
