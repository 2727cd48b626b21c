"""Benchmark (not a test): batched Poincare sections, section portraits and orbit diagrams.

    python benchmarks/batch_sections.py                 # every target, best of 3
    python benchmarks/batch_sections.py --only panels   # panels | ensemble | diagram | agreement
    python benchmarks/batch_sections.py --repeat 1 --json out.json

Targets (wall time on this machine, warm JIT cache, heyoka's batch width hy.recommended_simd_size()):
  panels     the 8 panels of Figs 4-5, 10 000 iterates each, 2 threads: batched lanes vs the scalar run_panels
             (what `magrod reproduce` runs), with max |Hbar - h| over all lanes
  ensemble   64 orbits x 1000 iterates on the Fig 4(a) level (starts of grid_starts on an 8 x 8 grid... the first 64
             accessible points of a 10 x 10 grid), 2 threads
  diagram    an orbit diagram of 200 lambdabar values x 500 iterates (lambdabar 0.131 .. 0.2, Fig 4's start)
  agreement  batch vs scalar over the first 100 crossings of every panel, against float64 vs long double
Each timing is the best of --repeat runs; `uptime` is printed before and after (the machine is shared).
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

from magrod.chaos.portrait import grid_starts, orbit_diagram
from magrod.chaos.section import poincare_section
from magrod.core import systems
from magrod.paper import PANELS, run_panels
import _smoke  # noqa: E402  (benchmarks/: on sys.path as the script's directory)

KEYS = list(PANELS)


def uptime() -> str:
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    except OSError:
        return f"load {os.getloadavg()}"


def best(f, repeat):
    walls, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = f()
        walls.append(time.perf_counter() - t0)
    return min(walls), walls, out


def panels(repeat):
    poincare_section(KEYS, iterates=10, workers=2)
    run_panels(KEYS, iterates=10, workers=2)
    it = _smoke.n(10_000, 10)
    wb, allb, rb = best(lambda: poincare_section(KEYS, iterates=it, workers=2), repeat)
    ws, alls, rs = best(lambda: run_panels(KEYS, iterates=it, workers=2), repeat)
    dh_b = max(r.max_abs_dH for r in rb)
    dh_s = max(r.max_abs_dH for r in rs.values())
    print(f"== 8 panels x 10 000 iterates, 2 threads: batched {wb:.2f} s (runs {', '.join(f'{w:.2f}' for w in allb)}), "
          f"scalar run_panels {ws:.2f} s ({', '.join(f'{w:.2f}' for w in alls)}): {ws / wb:.2f}x; max |dH| batched "
          f"{dh_b:.2e}, scalar {dh_s:.2e}; all ok {all(r.success for r in rb)} ==", flush=True)
    return dict(batch_s=wb, batch_runs=allb, scalar_s=ws, scalar_runs=alls, speedup=ws / wb, max_dH_batch=dh_b,
                max_dH_scalar=dh_s)


def ensemble(repeat, n=64, iterates=1000):
    starts = grid_starts("4a", theta0=(0.1, 3.0, 10), ptheta0=(-1.0, 1.0, 10))[:n]
    poincare_section("4a", starts=starts[:4], iterates=10, workers=2)
    w, walls, res = best(lambda: poincare_section("4a", starts=starts, iterates=iterates, workers=2), repeat)
    w1, walls1, _ = best(lambda: poincare_section("4a", starts=starts, iterates=iterates, workers=1), repeat)
    ws, wss, _ = best(lambda: [poincare_section("4a", theta0=a, ptheta0=b, iterates=iterates) for a, b in starts[:16]],
                      1)
    ws *= len(starts) / 16
    dh = max(r.max_abs_dH for r in res)
    print(f"== {len(starts)} orbits x {iterates} iterates on the Fig 4(a) level: 2 threads {w:.2f} s "
          f"({', '.join(f'{x:.2f}' for x in walls)}), 1 thread {w1:.2f} s; scalar one by one (16 timed, scaled) "
          f"{ws:.2f} s; max |dH| {dh:.2e} ==", flush=True)
    return dict(n=len(starts), iterates=iterates, wall_s=w, runs=walls, wall_1thread_s=w1, scalar_serial_s=ws,
                max_dH=dh)


def diagram(repeat, n=200, iterates=500):
    vals = np.linspace(0.131, 0.2, n)
    orbit_diagram("4a", "lam", vals[:4], iterates=10)
    w, walls, od = best(lambda: orbit_diagram("4a", "lam", vals, iterates=iterates, workers=2), repeat)
    print(f"== orbit diagram {n} values x {iterates} iterates: {w:.2f} s ({', '.join(f'{x:.2f}' for x in walls)}), "
          f"max |dH| {od.worst_dH:.2e}, ok {od.success} ==", flush=True)
    return dict(n=n, iterates=iterates, wall_s=w, runs=walls, max_dH=od.worst_dH)


def agreement(n=100):
    B = poincare_section(KEYS, iterates=n)
    rows = {}
    for k, b in zip(KEYS, B):
        s = poincare_section(k, iterates=n)
        ld = poincare_section(k, iterates=n, precision="long double")
        d_bs = np.max(np.abs(b.body_points - s.body_points), axis=1)
        d_sl = np.max(np.abs(s.body_points - ld.body_points), axis=1)

        def first(d):
            return int(np.argmax(d > 1e-12)) if (d > 1e-12).any() else None

        rows[k] = dict(batch_scalar_max=float(d_bs.max()), batch_scalar_first_gt_1e12=first(d_bs),
                       scalar_longdouble_max=float(d_sl.max()), scalar_longdouble_first_gt_1e12=first(d_sl))
        print(f"  {k}: batch-scalar max {d_bs.max():.1e} (first > 1e-12 at crossing {first(d_bs)}), "
              f"float64-long double max {d_sl.max():.1e} (first > 1e-12 at {first(d_sl)})", flush=True)
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", default="panels,ensemble,diagram,agreement")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--json", default=None)
    ap.add_argument("--smoke", action="store_true", help=_smoke.HELP)
    a = ap.parse_args(argv)
    if _smoke.enable(a.smoke):
        a.repeat, a.json = 1, None
    out = {"uptime_before": uptime(), "simd": systems.recommended_batch_size(), "cores": os.cpu_count()}
    print(f"{out['uptime_before']}\nheyoka batch width {out['simd']}, {out['cores']} cores", flush=True)
    for part in a.only.split(","):
        out[part] = {"panels": lambda: panels(a.repeat),
                     "ensemble": lambda: ensemble(a.repeat, *_smoke.n((64, 1000), (16, 10))),
                     "diagram": lambda: diagram(a.repeat, *_smoke.n((200, 500), (4, 10))),
                     "agreement": lambda: agreement(_smoke.n(100, 10))}[part]()
    out["uptime_after"] = uptime()
    print(out["uptime_after"])
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(out, fh, indent=2, default=str)
    return 0


if __name__ == "__main__":
    sys.exit(main())
