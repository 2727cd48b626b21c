"""Benchmark (not a test): what the early exit of a chaos map saves, in one run.

    python benchmarks/early_exit.py --json benchmarks/early_exit.json

The brute-force map lam x gamma = [0, 0.3] x [0, 3] at Figure 4's start rule (the README's map), --n x --n points,
in this process (no cluster), at each T in --t-max: early_exit off and on, alternated, --repeat times; the
process CPU time of each (the load-free measure of work on a shared machine; the minimum is kept) and the wall
time, the classes compared point by point, the orbits that exited and the share of T integrated."""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import time

import numpy as np

from magrod.chaos import indicators, maps


def uptime() -> str:
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    except OSError:
        return str(os.getloadavg())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=32)
    ap.add_argument("--t-max", default="1000,3000")
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--json", default=None)
    ap.add_argument("--smoke", action="store_true", help="run once on a tiny span (benchmarks/smoke.py, CI): a "
                    "4 x 4 map at T = 40, once; measures nothing, writes nothing")
    a = ap.parse_args()
    if a.smoke:
        a.n, a.t_max, a.repeat, a.json = 4, "40", 1, None
    out = {"grid": a.n, "uptime_before": uptime(), "runs": {}}
    for T in (float(t) for t in a.t_max.split(",")):
        best, res = {}, {}
        for _ in range(a.repeat):
            for ee in (False, True):
                s = maps.MapSpec(maps.parse_axis("x", f"lam:0:0.3:{a.n}"), maps.parse_axis("y", f"gamma:0:3:{a.n}"),
                                 base=maps.panel_base("4a"), t_max=T, early_exit=ee)
                w0, c0 = time.perf_counter(), time.process_time()
                cm = maps.compute_map(s)
                w, c = time.perf_counter() - w0, time.process_time() - c0
                b = best.setdefault(ee, {"cpu_s": np.inf, "wall_s": np.inf})
                b["cpu_s"], b["wall_s"] = min(b["cpu_s"], c), min(b["wall_s"], w)
                res[ee] = cm
        f0, f1 = res[False].fields, res[True].fields
        ok = f0["status"] == indicators.OK
        c0 = f0["growth_exponent"][ok] > indicators.GROWTH_THRESHOLD
        c1 = f1["growth_exponent"][ok] > indicators.GROWTH_THRESHOLD
        row = {"off": best[False], "on": best[True], "cpu_ratio_on_over_off": best[True]["cpu_s"] / best[False]["cpu_s"],
               "status_differs": int((f0["status"] != f1["status"]).sum()), "class_differs": int((c0 != c1).sum()),
               "computed": int(ok.sum()), "chaotic": int(c0.sum()), **res[True].summary()["early_exit"],
               "uptime": uptime()}
        out["runs"][f"T{T:g}"] = row
        print(f"T = {T:g}: CPU off {row['off']['cpu_s']:.1f} s, on {row['on']['cpu_s']:.1f} s "
              f"(ratio {row['cpu_ratio_on_over_off']:.3f}); {row['orbits_exited']} of {row['computed']} orbits exited "
              f"({row['chaotic']} chaotic), time fraction {row['time_fraction']:.3f}; classes differing "
              f"{row['class_differs']}, status differing {row['status_differs']} | {row['uptime'][-30:]}", flush=True)
    out["uptime_after"] = uptime()
    if a.json:
        with open(a.json, "w") as fh:
            fh.write(json.dumps(out, indent=2) + "\n")


if __name__ == "__main__":
    main()
