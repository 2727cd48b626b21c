"""How much wider a horseshoe certificate's enclosure of DP over a set is than DP's true variation across it.

For sets N_i of a shipped horseshoe certificate: the stored enclosure [DP] over the set's first piece (the prover's;
the verifier recomputes one of the same size) against DP's variation across the set, estimated in float64 by
central differences of the float section map (horseshoe_design.FloatMap.jac, tol 1e-15, step 1e-7) at the set's centre
+- K l along its exit direction (l its half-length; K = 100 lifts the difference above the float noise, ~1e-8,
assuming D^2 P is constant over K l) and scaled back to +- l.  A measurement, not part of any proof.

    python research/dp_enclosure_width.py [--out research/dp_enclosure_width.json]

Stored run (dp_enclosure_width.json; 2026-12-04): the enclosure is 10^2 - 10^5 times DP's variation across the set.
Its radius grows step by step as the C^1 Lohner method adds each step's Jacobian variation over the set's hull as an
independent interval (tests: the logs of research/README.md, "DP's enclosure against DP's variation"), while the
true variation D^2 P (x - x_c) is one linear function of the offset, with cancellations along the flow.
"""
from __future__ import annotations

import argparse
import json
from fractions import Fraction
from pathlib import Path

import numpy as np

from magrod.proof import fields
from magrod.proof.provers.horseshoe_design import FloatMap
from magrod.proof.provers.section_horseshoe import set_data

ROOT = Path(__file__).resolve().parent.parent
CASES = {"horseshoe_fig4a": (2, 6, 10, 12, 13), "horseshoe_fig5b": (2, 6, 8, 10, 12)}
K = 100


def rows_for(name: str, sets) -> list:
    c = json.loads((ROOT / "magrod" / "proof" / "certificates" / f"{name}.json").read_text())
    p = fields.ExactParams(**{k: Fraction(v) for k, v in c["params"].items()})
    s = c["settings"]
    fm = FloatMap(p, Fraction(c["level"]), s.get("branch", "0"), int(s.get("root", -1)))
    flights = {int(f["set"]): f for f in c["flights"]}
    out = []
    for i in sets:
        cc, A = set_data(c["sets"][i])[:2]
        cc = np.array([float(v) for v in cc])
        A = np.array([[float(v) for v in r] for r in A])
        l = float(np.linalg.norm(A[:, 0]))
        var = np.abs(fm.jac(cc + K * A[:, 0]) - fm.jac(cc - K * A[:, 0])).max() / (2 * K)
        rad = max(float(Fraction(b["rad"])) for row in flights[i]["pieces"][0]["enclosures"]["DP"] for b in row)
        out.append({"certificate": name, "set": i, "l": l, "DP_variation_over_l": var, "DP_enclosure_radius": rad,
                    "ratio": rad / var, "pieces": len(flights[i]["pieces"])})
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None)
    a = ap.parse_args(argv)
    rows = [r for name, sets in CASES.items() for r in rows_for(name, sets)]
    for r in rows:
        print(f"{r['certificate']} N{r['set']}: l {r['l']:.2e}, DP varies by {r['DP_variation_over_l']:.2e} across "
              f"+-l, enclosure radius {r['DP_enclosure_radius']:.2e} ({r['ratio']:.0f}x)")
    if a.out:
        Path(a.out).write_text(json.dumps({"K": K, "rows": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main()
