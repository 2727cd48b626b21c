"""Time the computer-assisted proof at the target (m, gamma, delta, mu, lam) = (1.7, 1, 1, 0.04, 0.01) and its
verification (target: <= 10 min on 2 cores), report the integrator's enclosure widths against time on the test
problems, and compare with codac's CtcLohner (if `pip install codac` is available) on the harmonic oscillator.

    python benchmarks/prove_target.py                 # everything (~3 min)
    python benchmarks/prove_target.py --only proof    # the target proof + verification
    python benchmarks/prove_target.py --only widths   # integrator widths (and codac, if installed)
"""
from __future__ import annotations

import argparse
import json
import math
import time
from fractions import Fraction


def proof(args):
    from magrod.proof import verify
    from magrod.proof.provers import transverse_homoclinic

    p = transverse_homoclinic.validate_params("1.7", "0.04", "1", "1", "0.01")
    t0 = time.perf_counter()
    stages = []
    res = transverse_homoclinic.prove(p, progress=lambda m: stages.append((m, time.perf_counter() - t0)))
    t_prove = time.perf_counter() - t0
    print(f"prove: ok={res.ok} ({res.reason}) in {t_prove:.1f} s; stages: "
          + ", ".join(f"{m} at {t:.1f} s" for m, t in stages))
    if not res.ok:
        return
    for c in res.certificate["crossings"]:
        print(f"  psi = {c['target']:>2}: dtheta_u/dpsi in [{float(Fraction(c['dtheta_dpsi']['mid'])):+.6e} "
              f"+- {float(Fraction(c['dtheta_dpsi']['rad'])):.2e}], phi* in [{float(Fraction(c['newton']['mid'])):.9f} "
              f"+- {float(Fraction(c['newton']['rad'])):.1e}], flight steps {c['thin']['n_steps']} (thin) "
              f"{c['arc']['n_steps']} (arc), max width {c['thin']['max_width']:.2e} / {c['arc']['max_width']:.2e}")
    cert = json.loads(json.dumps(res.certificate))
    t1 = time.perf_counter()
    v = verify.verify(cert)
    print(f"verify: ok={v.ok} ({v.reason}) in {time.perf_counter() - t1:.1f} s, {len(v.checks)} checks")
    print(f"total {time.perf_counter() - t0:.1f} s (limit 600 s)")


def widths(a):
    from magrod.proof import ball, fields, taylor

    with ball.workprec(128):
        fld = taylor.linear_field([[0, 1], [-1, 0]])
        S = taylor.initial_set([ball.q(1), ball.q(0)], radii=[Fraction(1, 10**12)] * 2)
        t0 = time.perf_counter()
        print("harmonic oscillator, box 2e-12 (magrod.proof.taylor, order 20):\n  t       width      wall")
        for T in (1, 10) if a.smoke else (1, 10, 100, 1000):
            S = taylor.propagate(fld, S, T, order=20)
            print(f"  {T:<7} {max(S.widths()):.3e}  {time.perf_counter() - t0:.1f} s")
        p = fields.ExactParams.from_values(m="1.7", mu="0.04", gamma=1, delta=1, lam="0.01")
        for name, fl, x0 in (("chart", fields.chart_field(p), [0.1433, 0.0004, -0.0002, 0.99]),):
            S = taylor.initial_set([ball.dyadic(v) for v in x0], radii=[Fraction(1, 10**15)] * 4)
            t0 = time.perf_counter()
            print(f"{name} field at the target, box 2e-15 around {x0}:\n  t       width      wall")
            for T in (2,) if a.smoke else (2, 4, 6, 8):
                S = taylor.propagate(fl, S, T, order=20)
                print(f"  {T:<7} {max(S.widths()):.3e}  {time.perf_counter() - t0:.1f} s")
    if a.smoke:
        return
    try:
        import codac
    except ImportError:
        print("codac not installed: `pip install codac` to compare its CtcLohner")
        return
    x = codac.VectorVar(2)
    f = codac.AnalyticFunction([x], codac.vec(x[1], -x[0]))
    for dt in (0.01, 0.001):
        td = codac.create_tdomain([0, 20], dt, False)
        tube = codac.SlicedTube(td, codac.IntervalVector(2))
        tube.set(codac.IntervalVector([[1 - 1e-12, 1 + 1e-12], [-1e-12, 1e-12]]), 0.0)
        t0 = time.perf_counter()
        tube = codac.CtcLohner(f).contract(tube, codac.TimePropag.FWD)
        wall = time.perf_counter() - t0
        print(f"codac {getattr(codac, '__version__', '?')} CtcLohner (defaults), slices dt = {dt}: {wall:.1f} s; "
              + ", ".join(f"t = {t}: width {tube(float(t))[0].diam():.2e} (contains cos t: "
                          f"{tube(float(t))[0].contains(math.cos(t))})" for t in (1, 10, 20)))


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--only", choices=("proof", "widths"), default=None)
    ap.add_argument("--smoke", action="store_true", help="run once on a tiny span (benchmarks/smoke.py, CI): the "
                    "integrator widths to t = 10 and 2 only (the proof itself takes minutes)")
    a = ap.parse_args()
    if a.smoke:
        a.only = "widths"
    if a.only in (None, "widths"):
        widths(a)
    if a.only in (None, "proof"):
        proof(a)
