"""Costs of the exact integrability analyses (derive/painleve.py, derive/kovacic.py, derive/morales_ramis.py).

    python benchmarks/decided_costs.py [--out benchmarks/decided_costs.json]

Times, in one process on this machine (wall and CPU seconds; the machine's load average is recorded, since a
shared 2-core machine inflates wall times):
  * exponents: the Kovalevskaya exponents of every balance of a 6-D model (the anisotropic rod at 1:2:3 and the
    Kovalevskaya rod 1:2:2 with the ARS conditions) -- target <= 10 s;
  * ratio_conditions: the NVEs along both pendulums of the symmetric rod with r symbolic and their Riemann data on
    the separatrix (the conditions on r that Kimura's theorem turns into the exceptional set);
  * kovalevskaya_1889: the anisotropic rod with (B1, B2, C) symbols: the axis balances' exponents and the exact
    solution of their integrality conditions for k, k' <= 6, with the full analysis at each rational case;
  * morales_ramis: one Kovacic run on a Heun-type NVE (r = 1/4, energy 0: the step that removes r = 1/4);
  * theorem: the whole symmetric-rod theorem, every step;
  * registry: what `python -m derive` spends on generated/decided/registry.json;
  * magnetic (only with --magnetic, minutes): the 9-D magnetic rod's planar solution normal to the field, its NVE
    cut down to 2 x 2 (Casimir e3.n, integral m3, quotient by X_m3) at the level h = -1/4, C1 = 1/16, where the
    singular points are 0, -1 and the roots of z^2 - z + 2 and 6 z^2 + 1; Kovacic's verdict there (a control: the
    rod is integrable, G0 must be abelian) and its cost with quadratic-irrational poles.
No number here is asserted by a test."""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))


def timed(fn):
    w0, c0 = time.perf_counter(), time.process_time()
    out = fn()
    return out, round(time.perf_counter() - w0, 2), round(time.process_time() - c0, 2)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=ROOT / "benchmarks" / "decided_costs.json")
    ap.add_argument("--skip-registry", action="store_true", help="skip the (slow) registry timing")
    ap.add_argument("--magnetic", action="store_true", help="also run Kovacic on the magnetic rod's planar NVE (minutes)")
    ap.add_argument("--smoke", action="store_true", help="a tiny span: the exponents of one 6-D model and one Kovacic "
                    "run, nothing written (CI runs every benchmark so)")
    a = ap.parse_args(argv)
    import sympy as sp

    from derive import decided, models, painleve
    from derive import morales_ramis as MR

    res = {"load_average_start": os.getloadavg()[0]}
    m = models.get("anisotropic")
    cases = (("exponents_1:2:3", {"B1": 1, "B2": 2, "C": 3}), ("exponents_1:2:2", {"B1": 1, "B2": 2, "C": 2}))
    for tag, vals in cases[:1] if a.smoke else cases:
        def run(vals=vals):
            X, f, _ = painleve.model_field(m, vals)
            return painleve.analyse_field(f, X)
        out, w, c = timed(run)
        res[tag] = {"wall_s": w, "cpu_s": c, "balances": sum(len(ch["balances"]) for ch in out["choices"])}

    model, vals = MR._symmetric_rod()

    def kovacic_heun():
        """One Kovacic run on a Heun-type NVE (r = 1/4, energy 0: the step that removes r = 1/4)."""
        nves = MR.pendulum_nves(model, vals)
        sub = {MR.h: 0, MR.r: sp.Rational(1, 4)}
        out, w, c = timed(lambda: MR.galois_of(sp.cancel(nves[1][1].subs(sub)), sp.cancel(nves[1][2].subs(sub))))
        res["morales_ramis_kovacic_heun"] = {"wall_s": w, "cpu_s": c, "group": out.group}

    if a.smoke:  # the Kovacic run, then stop
        kovacic_heun()
        print(json.dumps(res, indent=1))
        return 0

    def conditions():
        nves = MR.pendulum_nves(model, vals)
        return [MR.riemann_data(sp.cancel(p.subs(MR.h, 1)), sp.cancel(q.subs(MR.h, 1))) for _, p, q, _ in nves]
    out, w, c = timed(conditions)
    res["ratio_conditions"] = {"wall_s": w, "cpu_s": c,
                               "exponent_differences": [[str(v) for v in d.values()] for d in out]}
    from derive import kovalevskaya1889

    out, w, c = timed(kovalevskaya1889.conditions)
    res["kovalevskaya_1889"] = {"wall_s": w, "cpu_s": c, "cases": [f"{r['name']} ({r['ratios']}): {r['verdict']}"
                                                                  for r in out["cases"]]}
    kovacic_heun()
    out, w, c = timed(MR.symmetric_rod_theorem)
    res["theorem"] = {"wall_s": w, "cpu_s": c, "status": out["status"]}
    if not a.skip_registry:
        _, w, c = timed(decided.registry_results)
        res["registry"] = {"wall_s": w, "cpu_s": c}
    if a.magnetic:
        mg = models.get("magnetic")
        _, _, mv = painleve.model_field(mg)
        c1 = sp.Symbol("c1")
        pm, qm, _ = MR.nve(mg, mv, MR.invariant_planes(mg, mv)[0], MR.h, c1)
        lev = {MR.h: sp.Rational(-1, 4), c1: sp.Rational(1, 16)}
        out, w, c = timed(lambda: MR.galois_of(sp.cancel(pm.subs(lev)), sp.cancel(qm.subs(lev))))
        res["magnetic_planar_kovacic"] = {"wall_s": w, "cpu_s": c, "group": out.group,
                                          "abelian": out.abelian_identity_component,
                                          "singular_points": str(sp.factor(sp.denom(sp.together(pm.subs(lev)))))}
    res["load_average_end"] = os.getloadavg()[0]
    a.out.write_text(json.dumps(res, indent=1) + "\n")
    print(json.dumps(res, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
