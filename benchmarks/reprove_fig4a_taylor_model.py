"""Re-prove the Fig 4(a) horseshoe with the centres flown by the Taylor-model integrator (taylor_model.py), then
verify the shipped certificate (centres by taylor.py at tol_thin 1e-32) and the new one (taylor_model at 1e-25)
side by side in one process, one core, each twice in alternation: CPU and wall per verification.

    python benchmarks/reprove_fig4a_taylor_model.py [--out benchmarks/reprove_fig4a_taylor_model.json]
        [--cert NEW.json] [--tol-thin 1e-25]     # prove ~3-6 min, verify ~1 min each, by the load
--cert reuses a certificate proved before (no prove)."""
from __future__ import annotations

import argparse
import json
import platform
import time
from fractions import Fraction
from importlib import resources


def _verify(cert):
    from magrod.proof import verify

    t0, c0 = time.perf_counter(), time.process_time()
    res = verify.verify(cert, workers=1)
    return {"ok": res.ok, "message": res.message, "checks": len(res.checks), "wall_s": round(time.perf_counter() - t0, 2),
            "cpu_s": round(time.process_time() - c0, 2), "theorem": res.theorem}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None)
    ap.add_argument("--cert", default=None)
    ap.add_argument("--tol-thin", type=float, default=1e-25)
    ap.add_argument("--tol", type=float, default=1e-25, help="the sets' (box) flights' step tolerance")
    ap.add_argument("--box", choices=("taylor", "taylor_model"), default="taylor", help="the sets' integrator")
    ap.add_argument("--name", default="horseshoe_fig4a_taylor_model.json", help="where the new certificate goes")
    args = ap.parse_args()
    from magrod.proof import fields, horseshoe

    old = json.loads(resources.files("magrod.proof").joinpath("certificates", "horseshoe_fig4a.json").read_text())
    res = {"machine": platform.processor() or platform.machine()}
    if args.cert:
        new = json.loads(open(args.cert).read())
    else:
        p = fields.ExactParams(**{k: Fraction(v) for k, v in old["params"].items()})
        st = horseshoe.HorseshoeSettings(thin_integrator="taylor_model", tol_thin=args.tol_thin, tol=args.tol,
                                         integrator=args.box)
        t0, c0 = time.perf_counter(), time.process_time()
        pr = horseshoe.prove(p, Fraction(old["level"]), Fraction(old["design"]["x0_theta"]), st)
        res["prove"] = {"ok": pr.ok, "reason": pr.reason, "wall_s": round(time.perf_counter() - t0, 1),
                        "cpu_s": round(time.process_time() - c0, 1)}
        print(res["prove"], flush=True)
        if not pr.ok:
            raise SystemExit(1)
        new = pr.certificate
        with open(args.name, "w") as fh:
            json.dump(new, fh, indent=1)
    steps = {name: sum(len(ph) for f in c["flights"] for r in f["pieces"] for ph in r["steps"][kind])
             for name, c in (("old", old), ("new", new)) for kind in ("thin",)}
    res["thin_steps"] = steps
    res["box_steps"] = {name: sum(len(ph) for f in c["flights"] for r in f["pieces"] for ph in r["steps"]["box"])
                        for name, c in (("old", old), ("new", new))}
    runs = []
    for rep in range(2):
        for name, c in (("old", old), ("new", new)):
            r = _verify(c)
            runs.append({"cert": name, "rep": rep, **{k: v for k, v in r.items() if k != "theorem"}})
            print(runs[-1], flush=True)
            res.setdefault("theorem", {})[name] = r["theorem"]
    res["verify"] = runs
    cpu = {n: min(r["cpu_s"] for r in runs if r["cert"] == n) for n in ("old", "new")}
    res["cpu_ratio_old_over_new"] = round(cpu["old"] / cpu["new"], 2)
    res["same_theorem"] = res["theorem"]["old"] == res["theorem"]["new"]
    print({k: res[k] for k in ("thin_steps", "box_steps", "cpu_ratio_old_over_new", "same_theorem")})
    if args.out:
        with open(args.out, "w") as fh:
            json.dump(res, fh, indent=1)
            fh.write("\n")


if __name__ == "__main__":
    main()
