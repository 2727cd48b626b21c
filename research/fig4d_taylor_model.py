"""Fig 4(d) (lambdabar = 93/500) with the Taylor-model integrator: the closest design to a proof
(magrod/proof/designs/fig4d.json as it stood, "proving": false, N31 in 4 x 4 pieces) re-run by the prover with the Taylor-model integrator for the
centres only ("thin") or for the centres and the sets ("thin+box"), every other choice unchanged; records each
link's margins and where the prover stops.

    python research/fig4d_taylor_model.py thin+box --out research/fig4d_taylor_model.json
    python research/fig4d_taylor_model.py thin --out research/fig4d_taylor_model_thin.json
    python research/fig4d_taylor_model.py "thin, N31 in 8 x 8" --out research/fig4d_taylor_model_thin_8x8.json

~6.5 min of CPU per variant (one core).  Output: numerical bookkeeping of a prover run (the margins are those of
rigorous enclosures, but a run that stops proves nothing)."""
from __future__ import annotations

import argparse
import dataclasses
import json
import re
import time

# Every variant names its pieces: the design magrod/proof/designs/fig4d.json is now the proving one ("thin, N31 in
# 8 x 8"), while the first two runs had N31 in 4 x 4 as the design had then
PIECES_4x4 = {30: (4, 4), 31: (4, 4), 32: (2, 2), 33: (2, 2), 34: (2, 2)}
PIECES_8x8 = {30: (4, 4), 31: (8, 8), 32: (2, 2), 33: (2, 2), 34: (2, 2)}
VARIANTS = {"thin": {"thin_integrator": "taylor_model", "tol_thin": 1e-25, "pieces": PIECES_4x4},
            "thin, N31 in 8 x 8": {"thin_integrator": "taylor_model", "tol_thin": 1e-25, "pieces": PIECES_8x8},
            "thin+box": {"thin_integrator": "taylor_model", "tol_thin": 1e-25, "integrator": "taylor_model",
                         "tol": 1e-22, "pieces": PIECES_4x4}}
X0_THETA = 3.057288  # the saddle of statement 11 at Fig 4(d) (fixed_point_fig4d.json's --fixed-point seed)
LINK = re.compile(r"N(\d+) => N(\d+): \(a\) margin ([-0-9.e]+), \(b\) min \|y_u\| ([-0-9.e]+)")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("variant", choices=sorted(VARIANTS))
    ap.add_argument("--out", default=None)
    ap.add_argument("--cert", default=None, help="where the certificate goes if the prover issues one")
    args = ap.parse_args()
    from magrod.proof.provers import horseshoe_design, section_fixed_point, section_horseshoe

    st = dataclasses.replace(horseshoe_design.design("fig4d"), **VARIANTS[args.variant])
    p, h = section_fixed_point.validate("17/10", "2/5", "3", "3", "93/500", "9/10")
    links = []

    def say(s):
        print(s, flush=True)
        m = LINK.search(s)
        if m:
            links.append({"from": int(m[1]), "to": int(m[2]), "a_margin": float(m[3]), "b_min_abs_yu": float(m[4])})

    t0, c0 = time.perf_counter(), time.process_time()
    r = section_horseshoe.prove(p, h, X0_THETA, st, progress=say)
    out = {"variant": args.variant, "settings": st.as_json(), "ok": r.ok, "reason": r.reason, "links": links,
           "wall_s": round(time.perf_counter() - t0, 1), "cpu_s": round(time.process_time() - c0, 1)}
    print({k: out[k] for k in ("ok", "reason", "cpu_s")})
    if args.cert and r.ok:
        with open(args.cert, "w") as fh:
            json.dump(r.certificate, fh, indent=1)
            fh.write("\n")
    if args.out:
        with open(args.out, "w") as fh:
            json.dump(out, fh, indent=1)
            fh.write("\n")


if __name__ == "__main__":
    main()
