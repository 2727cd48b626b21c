"""A shipped horseshoe certificate re-proved with the Taylor-model integrator (magrod/proof/taylor_model.py) for its
centres and its sets, every other choice of its design unchanged; the re-proved certificate is then verified beside
the shipped one, in one process, alternating (CPU and wall per verification, the steps each replays, the theorem).

    python research/reprove_taylor_model.py fig4b --out /tmp/horseshoe_fig4b_tm.json          # prove
    python research/reprove_taylor_model.py fig4b --compare /tmp/horseshoe_fig4b_tm.json --reps 1

The design is the certificate's named design (magrod.proof.provers.horseshoe_design.DESIGNS: fig4a, fig4b, fig4c) or, for the
Fig 5 panels, the design "fig4a" with the certificate's own recorded settings (branch, root, m_back, n_exc, margins,
passes) and s* from its design record.  Integrators: centres "taylor_model" at tol_thin (default 1e-25), sets
"taylor_model" at tol (default 1e-22) -- benchmarks/reprove_fig4a_taylor_model.py measured these on Fig 4(a).
Output is a certificate (a proof only once the verifier accepts it), numerical timings otherwise."""
from __future__ import annotations

import argparse
import dataclasses
import json
import os
import time
from fractions import Fraction
from importlib import resources


def _shipped(name: str) -> dict:
    return json.loads(resources.files("magrod.proof").joinpath("certificates", f"horseshoe_{name}.json").read_text())


def settings_for(name: str, cert: dict, tol_thin: float, tol: float):
    """HorseshoeSettings of the shipped certificate `name`, the integrators replaced."""
    from magrod.proof.provers import horseshoe_design

    if name in horseshoe_design.DESIGNS:
        st = horseshoe_design.DESIGNS[name]()
    else:
        s = cert["settings"]
        kw = {k: s[k] for k in ("m_back", "n_exc", "qu", "qs", "l0_frac", "l1_frac", "w_cap", "branch", "root",
                                "stop_frac", "period", "q_cycle") if k in s}
        kw["passes"] = tuple(s.get("passes", ("tol", "tol", "thin")))
        kw["s_star"] = float(cert["design"]["s_star"])
        for k in ("p_rad", "t1", "lead"):
            kw[k] = Fraction(s[k])
        st = horseshoe_design.HorseshoeSettings(**kw)
    return dataclasses.replace(st, thin_integrator="taylor_model", integrator="taylor_model", tol_thin=tol_thin,
                               tol=tol)


def _steps(c, kind):
    return sum(len(ph) for f in c["flights"] for r in f["pieces"] for ph in r["steps"][kind])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("name", help="fig4a, fig4b, fig4c, fig5a, fig5b, fig5c or fig5d")
    ap.add_argument("--out", help="prove and write the re-proved certificate here")
    ap.add_argument("--compare", help="verify this re-proved certificate beside the shipped one")
    ap.add_argument("--tol-thin", type=float, default=1e-25)
    ap.add_argument("--tol", type=float, default=1e-22)
    ap.add_argument("--reps", type=int, default=1)
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--json", help="--compare: write the measurement here")
    args = ap.parse_args()
    from magrod.proof import fields, verify
    from magrod.proof.provers import section_horseshoe

    old = _shipped(args.name)
    if args.out:
        p = fields.ExactParams(**{k: Fraction(v) for k, v in old["params"].items()})
        st = settings_for(args.name, old, args.tol_thin, args.tol)
        t0, c0 = time.perf_counter(), time.process_time()
        pr = section_horseshoe.prove(p, Fraction(old["level"]), Fraction(old["design"]["x0_theta"]), st,
                             progress=lambda s: print(f"[{time.perf_counter() - t0:7.1f} s] {s}", flush=True))
        print({"ok": pr.ok, "reason": pr.reason, "wall_s": round(time.perf_counter() - t0, 1),
               "cpu_s": round(time.process_time() - c0, 1)}, flush=True)
        if pr.ok:
            cert = pr.certificate
            cert["provenance"] = {
                "command": f"python research/reprove_taylor_model.py {args.name} --out OUT --tol-thin {args.tol_thin:g} "
                           f"--tol {args.tol:g}",
                "design_script": old.get("provenance", {}).get("design_script"),
                "recorded": "at proof time"}
            with open(args.out, "w") as fh:
                json.dump(cert, fh, indent=1)
                fh.write("\n")
        return
    new = json.loads(open(args.compare).read())
    certs = {"shipped": old, "taylor_model": new}
    res = {"name": args.name, "load_before": os.getloadavg()[0], "workers": args.workers,
           "steps": {k: {"thin": _steps(c, "thin"), "box": _steps(c, "box")} for k, c in certs.items()},
           "verify": [], "theorem": {}}
    for rep in range(args.reps):
        for k, c in certs.items():
            t0, c0 = time.perf_counter(), time.process_time()
            r = verify.verify(c, workers=args.workers)
            res["verify"].append({"cert": k, "rep": rep, "ok": r.ok, "reason": r.reason, "checks": len(r.checks),
                                  "wall_s": round(time.perf_counter() - t0, 2),
                                  "cpu_s": round(time.process_time() - c0, 2)})
            res["theorem"][k] = r.theorem
            print(res["verify"][-1], flush=True)
    res["load_after"] = os.getloadavg()[0]
    res["same_theorem"] = res["theorem"]["shipped"] == res["theorem"]["taylor_model"]
    print({k: res[k] for k in ("steps", "same_theorem", "load_before", "load_after")})
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(res, fh, indent=1)
            fh.write("\n")


if __name__ == "__main__":
    main()
