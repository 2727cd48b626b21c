"""Benchmark (not a test): the batch targets (panels, ensemble, diagram) as ratios that hold on any machine:
batched lanes against the scalar path and against JiTCODE, each in one run.

    python benchmarks/batch_ratios.py --json benchmarks/batch_ratios_w4.json
    MAGROD_BATCH_WIDTH=8 python benchmarks/batch_ratios.py --json benchmarks/batch_ratios_w8.json

Jobs (those of benchmarks/batch_sections.py, and the one engine's):
  scaling   the 8 panels against 1 panel with two workers, in processes (the default) and in threads: the cost of 8
            panels in units of one, and the same points either way
  engine    the paper's rod through the one engine from body states (the path of every model) against its chart
            path, the same 8 orbits: the CPU ratio and the agreement of the first crossings
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
from magrod.chaos.section import poincare_section, poincare_sections
from magrod.paper import run_panels
from magrod.core import systems
from magrod.paper.printed import PANELS, panel
from _peers import compile_c  # noqa: E402  (benchmarks/: on sys.path as the script's directory)
import _smoke  # noqa: E402

KEYS = list(PANELS)
RTOLS = (1e-12, 1e-14)


def uptime() -> str:
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    except OSError:
        return f"load {os.getloadavg()}"


def cpu() -> float:
    """CPU seconds of this process and of its finished child processes (magrod.chaos.batch: two or more workers run
    in spawned processes, one pool per call, joined before the call returns; time.process_time does not see them)."""
    import resource

    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + kids.ru_utime + kids.ru_stime


def timed(f):
    w0, c0 = time.perf_counter(), cpu()
    out = f()
    return time.perf_counter() - w0, cpu() - c0, out


def _lanes(processes: bool):
    """A context in which the batch runs its workers in processes (the default) or in threads (the older way)."""
    import contextlib

    from magrod.chaos import batch

    @contextlib.contextmanager
    def ctx():
        orig = batch.run

        def run(orbits, **kw):
            return orig(orbits, processes=processes, **kw)

        batch.run = run
        try:
            yield
        finally:
            batch.run = orig
    return ctx()


def job_scaling(iterates):
    """8 panels against 1 panel, two workers, in processes and in threads: the cost of 8 panels in units of one."""
    out = {}
    for name, procs in (("processes", True), ("threads", False)):
        with _lanes(procs):
            poincare_sections(KEYS, iterates=10, workers=2)
            w8, c8, r8 = timed(lambda: poincare_sections(KEYS, iterates=iterates, workers=2))
            w1, c1, _ = timed(lambda: poincare_sections(KEYS[:1], iterates=iterates, workers=2))
        out[name] = {"wall_8": w8, "wall_1": w1, "ratio_8_over_1": w8 / w1, "cpu_8": c8, "cpu_1": c1,
                     "points_equal": None, "last": [r.points[-1].tolist() for r in r8]}
        print(f"== scaling ({name}): 8 panels {w8:.2f} s, 1 panel {w1:.2f} s wall: {w8 / w1:.2f}x one panel "
              f"| {uptime()[-30:]}", flush=True)
    out["points_equal"] = out["processes"]["last"] == out["threads"]["last"]
    print(f"   processes and threads give the same points: {out['points_equal']}", flush=True)
    return out


def job_engine(iterates):
    """The paper's rod through the one engine from body states (section.StateStart: the path of every model) against
    its chart path (the paper's panels), the same 8 orbits in the same lanes."""
    from magrod.chaos.section import SectionOptions, StateStart, _run_lanes
    from magrod.core.system import as_system

    chart = poincare_sections(KEYS, iterates=iterates, workers=2)
    starts = []
    for k, r in zip(KEYS, chart):
        s = as_system(k)[0]
        x0 = r.body_points[0]
        starts.append(StateStart(s, x0, systems.model_body(s).level(x0, s.array())))
    opts = SectionOptions(iterates=iterates)
    _run_lanes(starts[:2], SectionOptions(iterates=10), 2, None)
    wc, cc, _ = timed(lambda: poincare_sections(KEYS, iterates=iterates, workers=2))
    we, ce, re_ = timed(lambda: _run_lanes(starts, opts, 2, None))
    same = max(float(np.max(np.abs(a.body_points[1:11] - b.points[0:10]))) for a, b in zip(chart, re_))
    print(f"== engine: chart path {wc:.2f} s wall / {cc:.2f} s CPU; one engine from body states {we:.2f} s wall / "
          f"{ce:.2f} s CPU: CPU ratio chart/engine {cc / ce:.2f}x; first crossings agree to {same:.1e} "
          f"| {uptime()[-30:]}", flush=True)
    return {"chart_wall_s": wc, "chart_cpu_s": cc, "engine_wall_s": we, "engine_cpu_s": ce,
            "cpu_ratio_chart_over_engine": cc / ce, "first_crossings_agree_to": same}


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
    orbit_diagram("4a", "lam", vals[:4], iterates=10)
    wb, cb, od = timed(lambda: orbit_diagram("4a", "lam", vals, iterates=it, workers=2))
    rb = [o for o in od.orbits if o is not None]
    P = panel("4a")
    sub = vals[::10]
    ws, cs, rs = timed(lambda: [poincare_section(P.params.replace(lam=float(v)), P.h, P.theta0, P.ptheta0, P.psi0,
                                                 iterates=it) for v in sub])
    return dict(batched=(wb, cb, rb), scalar=(ws, cs, rs), scale=len(vals) / len(sub), sample=rb[::10])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", default="panels,ensemble,diagram,scaling,engine")
    ap.add_argument("--iterates", type=int, default=10_000, help="iterates per orbit of the scaling and engine jobs")
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
        if name in ("scaling", "engine"):
            out["jobs"][name] = (job_scaling if name == "scaling" else job_engine)(a.iterates)
            continue
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
