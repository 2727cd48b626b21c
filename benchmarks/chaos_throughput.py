"""Benchmark (not a test): chaos-map throughput -- where the time of a map goes, how it grows with the
grid, with T and with the number of Dask workers, and the 128 x 128 map at T = 1000 against a run of the previous
code (same classification of every point?).

    python benchmarks/chaos_throughput.py --only profile            # one 16 x 16 tile: root solve / integration / rest
    python benchmarks/chaos_throughput.py --only scaling            # grid 32^2, 64^2; T 250, 500, 1000; 1 vs 2 workers
    python benchmarks/chaos_throughput.py --only map128 --save after.npz
    /path/to/other/venv/bin/python benchmarks/chaos_throughput.py --only map128 --save before.npz   # previous code
    python benchmarks/chaos_throughput.py --compare before.npz after.npz

The map: lam x gamma = [0, 0.3] x [0, 3] at Figure 4's start rule (the README's 128 x 128 map), tile 16, a Dask
LocalCluster of processes with one thread each (cluster start-up included in the wall time).  Only APIs that the
previous code has too are used (maps.MapSpec, maps.compute_map), so the script runs under either.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

from magrod.chaos import maps


def uptime() -> str:
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    except OSError:
        return str(os.getloadavg())


def spec(n, t_max, tile=16):
    return maps.MapSpec(maps.parse_axis("x", f"lam:0:0.3:{n}"), maps.parse_axis("y", f"gamma:0:3:{n}"),
                        base=maps.panel_base("4a"), t_max=float(t_max), tile=tile)


def run_map(n, t_max, workers):
    from dask.distributed import Client, LocalCluster

    t0 = time.perf_counter()
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None) as lc, \
            Client(lc) as client:
        cm = maps.compute_map(spec(n, t_max), client=client)
    wall = time.perf_counter() - t0
    return wall, cm


def profile(t_max=1000.0):
    import cProfile
    import pstats

    s = spec(16, t_max)
    tile = maps.tiles(s)[0]
    maps.compute_tile(s, tile)  # build / load
    pr = cProfile.Profile()
    t0 = time.perf_counter()
    pr.enable()
    maps.compute_tile(s, tile)
    pr.disable()
    wall = time.perf_counter() - t0
    st = pstats.Stats(pr)
    tot = {k[2]: v[3] for k, v in st.stats.items()}  # function name -> cumulative time
    integ = sum(v[2] for k, v in st.stats.items() if k[2] == "<built-in method heyoka._core.propagate_until>"
                or "propagate_until" in k[2])
    roots = tot.get("solve_p_psi", 0.0)
    print(f"== one 16 x 16 tile, T = 1000 (profiled, wall {wall:.2f} s): propagate_until {integ:.2f} s "
          f"({100 * integ / wall:.0f}%), energy roots {roots:.2f} s ({100 * roots / wall:.0f}%), the rest "
          f"{wall - integ - roots:.2f} s ({100 * (wall - integ - roots) / wall:.0f}%) ==", flush=True)
    return dict(wall_s=wall, integration_s=integ, roots_s=roots)


def scaling(runs=((32, 500, 1), (32, 500, 2), (64, 500, 2), (32, 250, 2), (32, 1000, 2))):
    rows = []
    for n, t_max, w in runs:
        wall, cm = run_map(n, t_max, w)
        s = cm.summary()
        rows.append(dict(n=n, t_max=t_max, workers=w, wall_s=wall, points_per_s=n * n / wall,
                         computed=s["computed"], fraction_chaotic=s["fraction_chaotic"]))
        print(f"  {n} x {n}, T = {t_max}, {w} worker(s): {wall:.1f} s, {n * n / wall:.0f} points/s "
              f"({s['computed']} integrated), {uptime().split('load')[-1]}", flush=True)
    return rows


def map128(save):
    wall, cm = run_map(128, 1000.0, 2)
    s = cm.summary()
    print(f"== 128 x 128, T = 1000, 2 workers: {wall:.1f} s, {128 * 128 / wall:.0f} points/s, computed "
          f"{s['computed']}, missing {s['missing']}, fraction chaotic {s['fraction_chaotic']:.4f}, max |dH| "
          f"{s['max_abs_dH']:.1e} ==", flush=True)
    if save:
        np.savez(save, wall_s=wall, **cm.fields)
    return dict(wall_s=wall, points_per_s=128 * 128 / wall, **{k: s[k] for k in ("computed", "fraction_chaotic",
                                                                                  "max_abs_dH")})


def compare(a_path, b_path, threshold=3.0):
    a, b = np.load(a_path), np.load(b_path)
    out = {}
    for k in a.files:
        if k == "wall_s":
            continue
        out[k] = bool(np.array_equal(a[k], b[k], equal_nan=True))
    ok = (a["status"] == 0) & (b["status"] == 0)
    ca, cb = a["growth_exponent"] > threshold, b["growth_exponent"] > threshold
    diff = int(np.sum(ok & (ca != cb))) + int(np.sum(a["status"] != b["status"]))
    print(f"== {a_path} vs {b_path}: bit-identical fields {out}; points classified differently: {diff}; wall "
          f"{float(a['wall_s']):.1f} s vs {float(b['wall_s']):.1f} s ==")
    return dict(identical=out, classification_differences=diff)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", default="profile,scaling")
    ap.add_argument("--save", default=None)
    ap.add_argument("--compare", nargs=2, default=None)
    ap.add_argument("--json", default=None)
    ap.add_argument("--smoke", action="store_true", help="run once on a tiny span (benchmarks/smoke.py, CI): "
                    "one tile at T = 40, one 8 x 8 map on 2 workers; measures nothing, writes nothing")
    a = ap.parse_args(argv)
    if a.smoke:
        a.only, a.json, a.save, a.compare = "profile,scaling", None, None, None
    res = {"uptime_before": uptime()}
    print(res["uptime_before"], flush=True)
    if a.compare:
        res["compare"] = compare(*a.compare)
    else:
        for part in a.only.split(","):
            res[part] = {"profile": lambda: profile(40.0 if a.smoke else 1000.0),
                         "scaling": lambda: scaling(((8, 40, 2),)) if a.smoke else scaling(),
                         "map128": lambda: map128(a.save)}[part]()
    res["uptime_after"] = uptime()
    print(res["uptime_after"])
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(res, fh, indent=2, default=str)
    return 0


if __name__ == "__main__":
    sys.exit(main())
