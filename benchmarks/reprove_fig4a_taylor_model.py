"""The Fig 4(a) horseshoe re-proved with the Taylor-model integrator (magrod/proof/taylor_model.py), verified side by
side with the shipped certificate in one process, one core (workers=1), in alternation, twice: CPU and wall per
verification, the steps each replays, and whether the theorems are the same.

The shipped certificate flies its centres by taylor.py at tol_thin 1e-32 and its sets at 1e-25.  The re-proved ones
(the prover section_horseshoe.prove with the design "fig4a" and only these settings changed):
  * "thin":     thin_integrator "taylor_model", tol_thin 1e-25 (centres); sets by taylor.py at 1e-25;
  * "thin+box": the sets by taylor_model too (integrator "taylor_model"), at tol 1e-22.

    python benchmarks/reprove_fig4a_taylor_model.py --prove thin --name benchmarks/horseshoe_fig4a_taylor_model.json
    python benchmarks/reprove_fig4a_taylor_model.py --prove thin+box --name benchmarks/horseshoe_fig4a_taylor_model_box.json
    python benchmarks/reprove_fig4a_taylor_model.py --out benchmarks/reprove_fig4a_taylor_model.json \
        benchmarks/horseshoe_fig4a_taylor_model.json benchmarks/horseshoe_fig4a_taylor_model_box.json
Prove: 115 s / 83 s of CPU (thin / thin+box; 950 s / 800 s wall at load ~15); verify ~30-60 s of CPU each."""
from __future__ import annotations

import argparse
import json
import os
import platform
import time
from fractions import Fraction
from importlib import resources

DESIGNS = {"thin": {"thin_integrator": "taylor_model", "tol_thin": 1e-25},
           "thin+box": {"thin_integrator": "taylor_model", "tol_thin": 1e-25, "integrator": "taylor_model",
                        "tol": 1e-22}}


def _verify(cert):
    from magrod.proof import verify

    t0, c0 = time.perf_counter(), time.process_time()
    res = verify.verify(cert, workers=1)
    return {"ok": res.ok, "reason": res.reason, "checks": len(res.checks), "wall_s": round(time.perf_counter() - t0, 2),
            "cpu_s": round(time.process_time() - c0, 2)}, res.theorem


def _steps(c, kind):
    return sum(len(ph) for f in c["flights"] for r in f["pieces"] for ph in r["steps"][kind])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("certs", nargs="*", help="re-proved certificates to verify beside the shipped one")
    ap.add_argument("--prove", choices=sorted(DESIGNS), default=None)
    ap.add_argument("--name", default=None, help="--prove: where the certificate goes")
    ap.add_argument("--out", default=None)
    ap.add_argument("--reps", type=int, default=2)
    ap.add_argument("--smoke", action="store_true", help="a tiny span: the shipped certificate verified once, nothing "
                    "proved or written (CI runs every benchmark so)")
    args = ap.parse_args()
    if args.smoke:
        args.prove, args.certs, args.out, args.reps = None, [], None, 1
    from magrod.proof import fields
    from magrod.proof.provers import horseshoe_design, section_horseshoe

    old = json.loads(resources.files("magrod.proof").joinpath("certificates", "horseshoe_fig4a.json").read_text())
    if args.prove:
        p = fields.ExactParams(**{k: Fraction(v) for k, v in old["params"].items()})
        st = horseshoe_design.HorseshoeSettings(**DESIGNS[args.prove])
        t0, c0 = time.perf_counter(), time.process_time()
        pr = section_horseshoe.prove(p, Fraction(old["level"]), Fraction(old["design"]["x0_theta"]), st)
        print({"ok": pr.ok, "reason": pr.reason, "wall_s": round(time.perf_counter() - t0, 1),
               "cpu_s": round(time.process_time() - c0, 1)}, flush=True)
        if pr.ok and args.name:
            with open(args.name, "w") as fh:
                json.dump(pr.certificate, fh, indent=1)
        return
    certs = {"shipped": old} | {os.path.basename(n): json.loads(open(n).read()) for n in args.certs}
    res = {"machine": platform.processor() or platform.machine(), "load_before": os.getloadavg()[0],
           "steps": {k: {"thin": _steps(c, "thin"), "box": _steps(c, "box")} for k, c in certs.items()},
           "settings": {k: {s: c["settings"].get(s, "taylor" if "integrator" in s else None)
                            for s in ("thin_integrator", "tol_thin", "integrator", "tol")} for k, c in certs.items()},
           "verify": [], "theorem": {}}
    for rep in range(args.reps):
        for k, c in certs.items():
            r, th = _verify(c)
            res["verify"].append({"cert": k, "rep": rep, **r})
            res["theorem"][k] = th
            print(res["verify"][-1], flush=True)
    if args.smoke and not all(r["ok"] for r in res["verify"]):
        raise SystemExit("reprove_fig4a_taylor_model --smoke: the shipped certificate was rejected")
    res["load_after"] = os.getloadavg()[0]
    cpu = {k: min(r["cpu_s"] for r in res["verify"] if r["cert"] == k) for k in certs}
    res["cpu_min_s"] = cpu
    res["cpu_ratio_shipped_over"] = {k: round(cpu["shipped"] / v, 2) for k, v in cpu.items()}
    res["same_theorem_as_shipped"] = {k: th == res["theorem"]["shipped"] for k, th in res["theorem"].items()}
    print({k: res[k] for k in ("steps", "cpu_min_s", "cpu_ratio_shipped_over", "same_theorem_as_shipped")})
    if args.out:
        with open(args.out, "w") as fh:
            json.dump(res, fh, indent=1)
            fh.write("\n")


if __name__ == "__main__":
    main()
