"""How wide a lambdabar interval the homoclinic proof of statement 5 carries (the boundary circle centred on the moving
saddle, lambdabar a state of the flights: magrod.proof.kernel.homoclinic.moving_arc; `magrod prove --lam-rad W`).

For each half-width W at the target (m, mu, gamma, delta, lambdabar) = (17/10, 1/25, 1, 1, 1/100): prove
(both targets psi = 0, pi), and record the outcome, the first check that fails, the phase arc the prover settled on,
the interval Newton radius in the phase and the dtheta_u/dpsi balls; then verify the certificate that proves.  The
numbers behind statement 5's interval sentence (docs/nonintegrability.md) and behind the shipped
magrod/proof/certificates/homoclinic_target_interval.json (W = 1e-9).

    python research/homoclinic_interval.py            # W = 1e-12 .. 1e-8 (~2 min on 2 cores)
    python research/homoclinic_interval.py --out research/homoclinic_interval.json
"""
from __future__ import annotations

import argparse
import json
import time
from concurrent.futures import ProcessPoolExecutor
from fractions import Fraction

WIDTHS = ("1/1000000000000", "1/10000000000", "1/1000000000", "1/500000000", "1/250000000", "1/100000000")


def one(w: str) -> dict:
    from magrod.proof import verify
    from magrod.proof.provers import transverse_homoclinic

    p = transverse_homoclinic.validate_params("1.7", "0.04", "1", "1", "0.01")
    st = transverse_homoclinic.interval_proof_settings(Fraction(w))
    t0 = time.perf_counter()
    res = transverse_homoclinic.prove(p, st)
    row = {"lam_rad": w, "ok": res.ok, "reason": res.reason[:240], "prove_s": round(time.perf_counter() - t0, 1),
           "saddle_radius": str(st.saddle_radius), "eig_rad": str(st.eig_rad)}
    if res.ok:
        row["crossings"] = [{"target": c["target"], "dphi": c["dphi"],
                             "newton_rad": float(Fraction(c["newton"]["rad"])),
                             "dtheta_dpsi": [float(Fraction(c["dtheta_dpsi"]["mid"])),
                                             float(Fraction(c["dtheta_dpsi"]["rad"]))],
                             "steps": [c["thin"]["n_steps"], c["arc"]["n_steps"]]} for c in res.certificate["crossings"]]
        t1 = time.perf_counter()
        v = verify.verify(json.loads(json.dumps(res.certificate)))
        row.update(verified=v.ok, verify_s=round(time.perf_counter() - t1, 1), n_checks=len(v.checks))
    return row


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None, help="write the rows as JSON here")
    ap.add_argument("--workers", type=int, default=2)
    a = ap.parse_args(argv)
    t0 = time.perf_counter()
    with ProcessPoolExecutor(a.workers) as ex:
        rows = list(ex.map(one, WIDTHS))
    for r in rows:
        extra = "; ".join(f"psi = {c['target']}: dphi {c['dphi']}, Newton radius {c['newton_rad']:.2e}, dtheta_u/dpsi "
                          f"{c['dtheta_dpsi'][0]:+.5f} +- {c['dtheta_dpsi'][1]:.5f}" for c in r.get("crossings", []))
        print(f"W = {float(Fraction(r['lam_rad'])):.1e}: {'proved' if r['ok'] else 'failed'} in {r['prove_s']} s"
              + (f", verified {r['verified']} in {r['verify_s']} s; {extra}" if r["ok"] else f": {r['reason']}"))
    if a.out:
        from magrod.core.io import versions

        with open(a.out, "w") as fh:
            json.dump({"rows": rows, "wall_s": round(time.perf_counter() - t0, 1), "versions": versions()}, fh,
                      indent=1)


if __name__ == "__main__":
    main()
