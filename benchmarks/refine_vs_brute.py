"""Benchmark (not a test): adaptive (refined) chaos maps against the brute-force map, in one run.

    python benchmarks/refine_vs_brute.py --n 256 --t-max 1000 --levels 3 4 --out benchmarks/refine_vs_brute.json
    python benchmarks/refine_vs_brute.py --n 1024 --levels 4 --no-brute --out benchmarks/refine_1024.json

The map: lam x gamma = [0, 0.3] x [0, 3] at Figure 4's start rule (the README's map, as in chaos_throughput.py),
tile 16, a Dask LocalCluster of `--workers` single-threaded processes started for each map (start-up included in
every wall time, so the ratios are fair).  Reported per refined map: the wall time and its ratio to the brute-force
map's, the points integrated, the effective throughput (requested grid points per second) and its ratio to the
brute-force map's, and the agreement of the classification (regular / chaotic / each missing reason,
magrod.chaos.refine.point_class) with the brute-force map on the physical points (status not
unphysical_parameters), split into computed and inferred points.  Also a check that the computed points carry the
brute-force numbers bit for bit.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import time

import numpy as np

from magrod.chaos import indicators, maps
from magrod.chaos.refine import point_class


def uptime() -> str:
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    except OSError:
        return str(os.getloadavg())


def spec(n, t_max, refine=0, tile=16):
    return maps.MapSpec(maps.parse_axis("x", f"lam:0:0.3:{n}"), maps.parse_axis("y", f"gamma:0:3:{n}"),
                        base=maps.panel_base("4a"), t_max=float(t_max), tile=tile, refine=refine)


def run(s, workers):
    from dask.distributed import Client, LocalCluster

    t0 = time.perf_counter()
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None) as lc, \
            Client(lc) as client:
        cm = maps.compute_map(s, client=client)
    return time.perf_counter() - t0, cm


def compare(brute, refined) -> dict:
    cb = point_class(brute.fields["status"], brute.fields["growth_exponent"])
    cr = point_class(refined.fields["status"], refined.fields["growth_exponent"])
    phys = np.asarray(brute.fields["status"]) != indicators.UNPHYSICAL
    inf = np.asarray(refined.fields["inferred"]) != 0
    same = cb == cr
    comp = ~inf
    bits = all(np.array_equal(np.asarray(brute.fields[k])[comp], np.asarray(refined.fields[k])[comp], equal_nan=True)
               for k in maps.MAP_FIELDS + ("status",))
    return {"physical_points": int(phys.sum()), "agreement_physical": float(same[phys].mean()),
            "disagree_computed": int((~same & phys & comp).sum()), "disagree_inferred": int((~same & phys & inf).sum()),
            "computed_points_bit_identical": bool(bits),
            "fraction_chaotic": {"brute": brute.fraction_chaotic, "refined": refined.fraction_chaotic}}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=256)
    ap.add_argument("--t-max", type=float, default=1000.0)
    ap.add_argument("--levels", type=int, nargs="+", default=[3, 4])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--no-brute", action="store_true", help="refined maps only (the 1024^2 run)")
    ap.add_argument("--out", default=None)
    ap.add_argument("--smoke", action="store_true", help="run once on a tiny span (benchmarks/smoke.py, CI): a "
                    "32 x 32 grid at T = 40, one refined level; measures nothing, writes nothing")
    a = ap.parse_args()
    if a.smoke:
        a.n, a.t_max, a.levels, a.out = 32, 40.0, [1], None
    out = {"grid": a.n, "t_max": a.t_max, "workers": a.workers, "uptime_before": uptime(), "refined": {}}
    from heyoka import recommended_simd_size

    out["simd_width"] = int(recommended_simd_size())
    out["batch_size"] = spec(a.n, a.t_max).batch_size
    for L in a.levels:
        wall, cm = run(spec(a.n, a.t_max, refine=L), a.workers)
        s = cm.summary()
        out["refined"][L] = {"wall_s": wall, "grid_points_per_s": a.n * a.n / wall, **s["refine"],
                             "fraction_chaotic": s["fraction_chaotic"], "missing": s["missing"], "_map": cm}
        print(f"refined L={L}: {wall:.1f} s, {s['refine']['points_computed']} of {a.n * a.n} points computed",
              flush=True)
    if not a.no_brute:
        wall, brute = run(spec(a.n, a.t_max), a.workers)
        out["brute"] = {"wall_s": wall, "grid_points_per_s": a.n * a.n / wall,
                        "fraction_chaotic": brute.fraction_chaotic, "missing": brute.summary()["missing"]}
        print(f"brute force: {wall:.1f} s", flush=True)
        for r in out["refined"].values():
            r.update(compare(brute, r["_map"]), wall_ratio=r["wall_s"] / wall,
                     throughput_ratio=r["grid_points_per_s"] / out["brute"]["grid_points_per_s"])
    for r in out["refined"].values():
        r.pop("_map")
    out["uptime_after"] = uptime()
    text = json.dumps(out, indent=2, default=float)
    print(text)
    if a.out:
        with open(a.out, "w") as fh:
            fh.write(text + "\n")


if __name__ == "__main__":
    main()
