"""Benchmark (not a test): work-precision of a chaos map's *classification*.

    python benchmarks/classification_precision.py --n 128 --out benchmarks/classification_precision.json
    python benchmarks/classification_precision.py --plot benchmarks/classification_precision.json

For T in {1000, 3000} and tol in {1e-8, 1e-10, 1e-12, eps}: the brute-force map lam x gamma = [0, 0.3] x [0, 3]
at Figure 4's start rule (the README's map), n x n points, on a LocalCluster of `--workers` processes.  Reported
per map: the wall time (the work) and the fraction of the points computed in both maps whose class (regular /
chaotic, growth exponent against 3) differs from the tol = eps map of the same T (the precision of the answer a
map is for), plus the points whose status differs (computed in one, missing in the other).  Each finished map is
saved to `--cache` (npz), so an interrupted study resumes.  The plot: misclassified fraction against wall time.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import time

import numpy as np

from magrod.chaos import indicators, maps

TOLS = (1e-8, 1e-10, 1e-12, 0.0)  # 0 = machine epsilon, the reference
T_MAX = (1000.0, 3000.0)


def uptime() -> str:
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    except OSError:
        return str(os.getloadavg())


def spec(n, t_max, tol, refine=0):
    return maps.MapSpec(maps.parse_axis("x", f"lam:0:0.3:{n}"), maps.parse_axis("y", f"gamma:0:3:{n}"),
                        base=maps.panel_base("4a"), t_max=float(t_max), tol=float(tol), refine=int(refine))


def run(s, workers):
    from dask.distributed import Client, LocalCluster

    t0 = time.perf_counter()
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None) as lc, \
            Client(lc) as client:
        cm = maps.compute_map(s, client=client)
    return time.perf_counter() - t0, cm.fields


def study(a):
    os.makedirs(a.cache, exist_ok=True)
    out = {"grid": a.n, "workers": a.workers, "refine": a.refine, "uptime_before": uptime(), "maps": {}}
    fields = {}
    for T in (T_MAX if a.t_max is None else (a.t_max,)):
        for tol in (0.0,) + (TOLS[:-1] if a.tols is None else tuple(float(t) for t in a.tols.split(","))):  # ref first
            key = f"T{T:g}_tol{tol:g}"
            path = os.path.join(a.cache, f"{key}_{a.n}{f'_L{a.refine}' if a.refine else ''}.npz")
            if os.path.exists(path):
                d = np.load(path)
                fields[key], wall = {k: d[k] for k in d.files if k != "wall_s"}, float(d["wall_s"])
            else:
                wall, fields[key] = run(spec(a.n, T, tol, a.refine), a.workers)
                np.savez(path, wall_s=wall, **fields[key])
            ref = fields[f"T{T:g}_tol0"]
            both = (ref["status"] == indicators.OK) & (fields[key]["status"] == indicators.OK)
            if a.refine:  # a refined map: compare the points both maps computed (inferred ones separately)
                comp = (ref["inferred"] == 0) & (fields[key]["inferred"] == 0)
                cr_all = ref["growth_exponent"][both] > indicators.GROWTH_THRESHOLD
                cf_all = fields[key]["growth_exponent"][both] > indicators.GROWTH_THRESHOLD
                inf_extra = {"computed_in_both_maps": int(comp.sum()),
                             "points_computed": int((fields[key]["inferred"] == 0).sum()),
                             "misclassified_incl_inferred": int((cr_all != cf_all).sum()),
                             "physical_incl_inferred": int(both.sum()),
                             "status_differs_incl_inferred": int((ref["status"] != fields[key]["status"]).sum())}
                both = both & comp
                status_mask = comp
            else:
                inf_extra, status_mask = {}, np.ones(ref["status"].shape, bool)
            cr = ref["growth_exponent"][both] > indicators.GROWTH_THRESHOLD
            cf = fields[key]["growth_exponent"][both] > indicators.GROWTH_THRESHOLD
            out["maps"][key] = {"t_max": T, "tol": tol or "eps", "wall_s": wall, "computed_both": int(both.sum()),
                                "misclassified": int((cr != cf).sum()),
                                "fraction_misclassified": float((cr != cf).mean()) if both.any() else None,
                                "status_differs": int(((ref["status"] != fields[key]["status"]) & status_mask).sum()),
                                "fraction_chaotic": float(cf.mean()) if both.any() else None, **inf_extra}
            print(key, json.dumps(out["maps"][key]), flush=True)
    out["uptime_after"] = uptime()
    return out


def compare(ref: dict, f: dict) -> dict:
    """How map f differs from the reference map ref (same grid and T): among the points computed (not inferred)
    in f whose status is ok in both, the misclassified ones (growth exponent against the threshold), and the
    points computed in f whose status differs from ref's (lost or gained); the same over every point, inferred ones
    included.  A refined map's computed points cluster at the class boundaries, so the first fraction is a
    conservative (boundary-weighted) sample of the misclassification a brute-force map at that setting would show."""
    comp = (f["inferred"] == 0) if "inferred" in f else np.ones(f["status"].shape, bool)
    comp = comp & ((ref["inferred"] == 0) if "inferred" in ref else True)
    okb = (ref["status"] == indicators.OK) & (f["status"] == indicators.OK)
    with np.errstate(invalid="ignore"):
        cr = ref["growth_exponent"] > indicators.GROWTH_THRESHOLD
        cf = f["growth_exponent"] > indicators.GROWTH_THRESHOLD
    mis = okb & (cr != cf)
    st = ref["status"] != f["status"]
    n_c = int((okb & comp).sum())
    return {"computed_both": n_c, "misclassified": int((mis & comp).sum()),
            "fraction_misclassified": float((mis & comp).sum() / n_c) if n_c else None,
            "status_differs": int((st & comp).sum()), "points_compared": int(comp.sum()),
            "all_points_ok_both": int(okb.sum()), "misclassified_all_points": int(mis.sum()),
            "status_differs_all_points": int(st.sum()),
            "fraction_chaotic": float(cf[f["status"] == indicators.OK].mean())}


def report(dirs, n) -> dict:
    """The study from the maps cached in `dirs` (npz files of study() runs, brute force or refined): per T the
    reference is the brute-force tol = eps map if there is one, else the refined one; every other map is compared
    with it (compare())."""
    import glob
    import re

    found = {}
    for d in dirs:
        for path in glob.glob(os.path.join(d, f"T*_tol*_{n}*.npz")):
            m = re.match(rf"T([\d.e+]+)_tol([\d.e+-]+)_{n}(?:_L(\d+))?\.npz$", os.path.basename(path))
            if m:
                found[(float(m.group(1)), float(m.group(2)), int(m.group(3) or 0))] = path
    out = {"grid": n, "maps": {}}
    for T in sorted({k[0] for k in found}):
        refs = [k for k in found if k[0] == T and k[1] == 0.0]
        if not refs:
            continue
        rk = min(refs, key=lambda k: k[2])  # brute force (L = 0) first
        ref = dict(np.load(found[rk]))
        for k in sorted(found):
            if k[0] != T or k == rk:
                continue
            f = dict(np.load(found[k]))
            out["maps"][f"T{T:g}_tol{k[1]:g}_L{k[2]}"] = {
                "t_max": T, "tol": k[1] or "eps", "refine": k[2], "reference": f"tol eps, L = {rk[2]}",
                "wall_s": float(f["wall_s"]), "reference_wall_s": float(ref["wall_s"]), **compare(ref, f)}
    return out


def cost(n_orbits=64, repeats=3) -> dict:
    """Seconds per orbit of the indicator run at each (T, tol), in this process: the same n_orbits starts of the
    map (its first tiles' physical points), the tols alternated and the minimum of `repeats` taken, so that a
    loaded machine (whose cluster wall times above are noisy) still gives the work ratio."""
    from magrod.chaos.indicators import body_indicators

    s = spec(64, 1000.0, 0.0)
    starts = [maps.start_point(s.point(ix, iy)) for iy in range(s.y.n) for ix in range(s.x.n)]
    starts = [st for st in starts if st[2] == indicators.OK][:n_orbits]
    x0 = np.array([st[0] for st in starts]).T
    p = np.array([st[1] for st in starts]).T
    out = {}
    for T in T_MAX:
        for tol in TOLS:
            body_indicators(x0[:, :8], p[:, :8], t_max=10.0, tol=tol or None)  # compile / load once
        best = {tol: np.inf for tol in TOLS}
        for _ in range(repeats):
            for tol in TOLS:
                t0 = time.perf_counter()
                body_indicators(x0, p, t_max=T, tol=tol or None)
                best[tol] = min(best[tol], (time.perf_counter() - t0) / x0.shape[1])
        out[f"T{T:g}"] = {("eps" if not tol else f"{tol:g}"): v for tol, v in best.items()}
        print(f"T{T:g}", out[f"T{T:g}"], flush=True)
    return out


def plot(path_json, path_png):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    d = json.load(open(path_json))
    cost_path = os.path.join(os.path.dirname(path_json), "classification_cost.json")
    c = json.load(open(cost_path))["seconds_per_orbit"] if os.path.exists(cost_path) else None
    fig, ax = plt.subplots(figsize=(5.5, 4.0), layout="constrained")
    for T, mk in zip(T_MAX, "os"):
        rows = [r for r in d["maps"].values() if r["t_max"] == T and r["tol"] != "eps"]
        ref = next(r for r in d["maps"].values() if r["t_max"] == T and r["tol"] == "eps")
        if c is not None:  # the in-process cost (alternated, min of repeats): robust on a loaded machine
            x = [c[f"T{T:g}"][f"{r['tol']:g}"] / c[f"T{T:g}"]["eps"] for r in rows]
        else:
            x = [r["wall_s"] / ref["wall_s"] for r in rows]
        # what differs from the eps map: a class, or a point lost (status), as a fraction of the eps map's points;
        # none differing is drawn as a down-triangle at the resolution 1/(points)
        n_ref = ref["computed_both"]
        frac = [(r["misclassified"] + r["status_differs"]) / n_ref for r in rows]
        floor = 1.0 / n_ref
        ax.loglog(x, [max(f, floor) for f in frac], mk + "-", label=f"T = {T:g}", mfc="none")
        for xi, f, r in zip(x, frac, rows):
            if f == 0:
                ax.plot([xi], [floor], "v", color=ax.lines[-1].get_color())
            ax.annotate(f"{r['tol']:g}: {r['misclassified']} misclassified, {r['status_differs']} lost", (xi, max(f, floor)),
                        fontsize=6, textcoords="offset points", xytext=(4, 4 if T == 1000 else -10))
    ax.set_xlabel("cost per orbit / cost at tol = eps (same T)" if c is not None else
                  "wall time / wall time at tol = eps (same T)")
    ax.set_ylabel("fraction differing from tol = eps (class or lost)")
    ax.set_title(f"{d['grid']}^2 map lam x gamma, Fig 4 start rule; v: nothing differs (below 1/points)", fontsize=8)
    ax.legend(fontsize=8)
    fig.savefig(path_png, dpi=120)


def plot_report(path_json, path_png):
    """The report's study: fraction of the compared points that differ from the tol = eps reference (a class, or
    the status), against tol, one line per T; a map where nothing differs is drawn at 1/points (down-triangle)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    d = json.load(open(path_json))
    fig, ax = plt.subplots(figsize=(5.5, 4.0), layout="constrained")
    groups = sorted({(r["t_max"], r["refine"]) for r in d["maps"].values()})
    for gi, ((T, L), mk) in enumerate(zip(groups, "os^dv<>")):
        rows = sorted((r for r in d["maps"].values() if r["t_max"] == T and r["refine"] == L and r["tol"] != "eps"),
                      key=lambda r: r["tol"])
        if not rows:
            continue
        x = [r["tol"] for r in rows]
        frac = [(r["misclassified"] + r["status_differs"]) / max(1, r["points_compared"]) for r in rows]
        floor = [1.0 / max(1, r["points_compared"]) for r in rows]
        ln, = ax.loglog(x, [max(f, fl) for f, fl in zip(frac, floor)], mk + "-", mfc="none",
                        label=f"T = {T:g}, {'brute force' if not L else f'refined L = {L}'} (reference "
                              f"{rows[0]['reference'].replace('L = 0', 'brute force')})")
        for xi, f, fl, r in zip(x, frac, floor, rows):
            if f == 0:
                ax.plot([xi], [fl], "v", color=ln.get_color())
            ax.annotate(f"{r['misclassified']} class, {r['status_differs']} status / {r['points_compared']}",
                        (xi, max(f, fl)), fontsize=6, textcoords="offset points", xytext=(4, 4 - 9 * gi),
                        color=ln.get_color())
    ax.set_xlabel("Taylor tolerance tol")
    ax.set_ylabel("fraction differing from tol = eps (class or status)")
    ax.set_title(f"{d['grid']}^2 map lam x gamma, Fig 4 start rule; computed points compared; v: none differs",
                 fontsize=8)
    ax.legend(fontsize=6)
    fig.savefig(path_png, dpi=120)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=128)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--cache", default="/tmp/magrod-classification-precision")
    ap.add_argument("--out", default=None)
    ap.add_argument("--refine", type=int, default=0, help="refined maps of this many levels (0: brute force)")
    ap.add_argument("--t-max", type=float, default=None, help="only this T (default: 1000 and 3000)")
    ap.add_argument("--tols", default=None, help="comma-separated tolerances after the eps reference, in this order")
    ap.add_argument("--plot", default=None, help="draw the JSON of a finished study next to it (.png)")
    ap.add_argument("--report", default=None, help="comma-separated cache directories: the study from their maps")
    ap.add_argument("--cost", default=None, help="only the in-process cost per orbit at each (T, tol), into this JSON")
    ap.add_argument("--smoke", action="store_true", help="run once on a tiny span (benchmarks/smoke.py, CI): a 4 x 4 "
                    "map at T = 20 and two tolerances, cached in a temporary directory; measures nothing")
    a = ap.parse_args()
    if a.smoke:
        import tempfile

        a.n, a.t_max, a.tols, a.out, a.cache = 4, 20.0, "1e-8", None, tempfile.mkdtemp(prefix="magrod-smoke-")
    if a.cost:
        out = {"uptime_before": uptime(), "seconds_per_orbit": cost(), "uptime_after": uptime()}
        with open(a.cost, "w") as fh:
            fh.write(json.dumps(out, indent=2) + "\n")
        return
    if a.plot:
        plot(a.plot, a.plot.replace(".json", ".png"))
        return
    if a.report:
        out = report(a.report.split(","), a.n)
        text = json.dumps(out, indent=2)
        print(text)
        if a.out:
            with open(a.out, "w") as fh:
                fh.write(text + "\n")
            plot_report(a.out, a.out.replace(".json", ".png"))
        return
    out = study(a)
    text = json.dumps(out, indent=2)
    print(text)
    if a.out:
        with open(a.out, "w") as fh:
            fh.write(text + "\n")


if __name__ == "__main__":
    main()
