"""Why the horseshoe verifications cost what they cost (reproduce's +60 s): the accuracy-cost frontier of
the validated integrator's centre ("thin") flights, which are ~70 % of the steps of every shipped horseshoe.

The flight: one return of the section map from Fig 4(b)'s saddle x0 (fixed_point_fig4b.json; return time 5.13),
C^0, Newton series, 128 bits -- the flight HORSESHOE_CENTRE_TOL_FIG4B was tuned on (core/tolerances.py).  Measured:

  1. remainder inflation: per step, the Lagrange remainder x^[p+1](Y) h^(p+1) on the a priori enclosure Y, its
     radius against its midpoint (the true remainder's size) and against the last Taylor term (~tol);
  2. the radius of the box coefficients x^[k](Y) per unit width of Y, by k and by the width (the dependency growth
     of Arb series arithmetic on a box; Newton's and Picard's series);
  3. order x tolerance: steps, CPU and the enclosure of P(x0) (which failed to validate a step);
  4. a remainder-aware step control (reject a step whose remainder radius exceeds rem_tol): steps and enclosure;
  5. the same flight by magrod/proof/taylor_model.py (the step's remainder a Taylor model in time, validated by a
     Picard-Schauder test; no series on the a priori box): order x tolerance, and its remainder I against the last
     Taylor term by the tail order L - p ("extra": the point coefficients of f o P_c up to L, the Lagrange
     coefficient at L);
  6. the C^1 flight of a Fig 4(a) horseshoe set (horseshoe_fig4a.json, set 0, width ~1e-10) by both integrators,
     the centre C^0 (taylor at the certificate's tol_thin 1e-32, taylor_model at 1e-28) and the box C^1 at 1e-25:
     CPU, steps, and the widths of P(c) and DP;
  7. where a step's CPU goes (step_cost): the generated field's and Jacobian's share of the box flight (cProfile),
     their cost per call by series length against one series product, sine and square root, and what sharing
     sin and cos between the two would save (benchmarks/README.md: every method side by side).

Numerical measurements of a rigorous integrator's enclosure widths (each width is itself rigorous).  What they say:
the enclosure of a centre after one return is set by the remainder's radius on Y (inflated ~1e11 x at the median
step), not by the true truncation error; higher order inflates faster than it gains (order >= 24 fails to validate
steps), and shortening the inflated steps costs as many steps as a smaller tol.  Order 20 with tol 1e-28 .. 1e-32 is
on the frontier; a cheaper centre flight needs a remainder that is not a box evaluation (Taylor models; Cauchy bounds
from a first-order complex-time enclosure would need R < 1/|Df| ~ 0.044 at x0: far shorter steps), i.e. a new
integrator and every horseshoe re-proved.  Items 5 and 6 measure that integrator: its remainder is ~1x the last
Taylor term at the median step (extra 10 .. 12; ~2e4 x at extra 5, ~2e9 x at extra 0, which is the box evaluation
again, now of f o P_c over [0, h]), so the same enclosure of P(x0) (1e-20) takes 0.43x the steps (order 20 at
1e-25, 152 steps, against today's 1e-32, 353) at about the same cost per step: ~2.2-2.4x cheaper centre flights.
Its C^1 step costs ~1.1-1.3x today's and its DP is ~2x narrower at the same tolerance, so the sets' flights gain
only ~1.2x (tol 1e-22).  What a 3x verification would need beyond this is a cheaper step (the field's and its
Jacobian's series evaluations are ~50 % of it by cProfile), not a tighter remainder;
reprove_fig4a_taylor_model.py measures a whole certificate (1.6-2.1x).

    python benchmarks/centre_flight_frontier.py [--out benchmarks/centre_flight_frontier.json]   # ~2 min, 1 core
    python benchmarks/centre_flight_frontier.py --smoke      # a tiny span (CI)
"""
from __future__ import annotations

import argparse
import json
import platform
import time
from fractions import Fraction
from importlib import resources

import numpy as np


def _setup():
    from magrod.proof import fields
    from magrod.proof.provers.horseshoe_design import dyadic
    from magrod.proof.provers.section_horseshoe import t_approach

    c = json.loads(resources.files("magrod.proof").joinpath("certificates", "fixed_point_fig4b.json").read_text())
    p = fields.ExactParams(**{k: Fraction(v) for k, v in c["params"].items()})
    th = Fraction(c["newton"]["mid"])
    pc = dyadic(float(Fraction(c["point"]["level_newton"]["centre"]["mid"])), 60)
    t_a = t_approach(c["float"]["half_time"] * 2, Fraction(1, 256))
    return p, Fraction(c["level"]), th, pc, t_a


def _fly(order, tol, hook=None, method="taylor", extra=None):
    """One C^0 return of x0; hook(sd, h, order) may raise EnclosureError (rejects the step).  (steps, cpu, P(x0)
    radii) or the failure.  The hook wraps the integrator's step_data for the flight's duration (restored after): the
    library has no per-step callback, and a benchmark must not add one to the verifier's trust base.  method:
    "taylor" (the a priori box's Lagrange remainder) or "taylor_model" (the Taylor-model remainder; extra: its
    tail order L - p, the module's default if None)."""
    from magrod.proof import ball, fields, section_return, taylor, taylor_model

    integ = {"taylor": taylor, "taylor_model": taylor_model}[method]
    p, h, th, pc, t_a = _setup()
    orig = integ.step_data

    def wrapped(fld, S, hh, order_, c1=True, cx=None, **kw):
        if extra is not None:
            kw["extra"] = extra
        sd = orig(fld, S, hh, order_, c1, cx, **kw)
        if hook is not None:
            hook(sd, hh, order_)
        return sd

    integ.step_data = wrapped
    t0 = time.process_time()
    head = {"method": method, "order": order, "tol": tol} | ({} if extra is None else {"extra": extra})
    try:
        with ball.workprec(128):
            fld = fields.chart_field(p)
            fld.series = "newton"
            fl = section_return.piece_return(fld.pars, h, fld, [th, Fraction(0)], [[0, 0], [0, 0]], pc,
                                             Fraction(1, 10**8), t_a, Fraction(1, 256), order=order, tol=tol,
                                             tol_thin=tol, box=False, thin_c1=False, integrator=integ)
        return {**head, "ok": True, "steps": sum(len(s) for s in fl["steps"]["thin"]),
                "cpu_s": round(time.process_time() - t0, 2), "Pc_rad": [float(v.rad()) for v in fl["Pc"]]}
    except (taylor.EnclosureError, taylor.GuardError, taylor.CrossingError) as err:
        return {**head, "ok": False, "reason": str(err)[:120], "cpu_s": round(time.process_time() - t0, 2)}
    finally:
        integ.step_data = orig


def tm_remainder(tol, extra=None):
    """The Taylor-model remainder I per step against the last Taylor term |x^[p]| h^p at the point (~tol): the
    inflation that the a priori box's Lagrange remainder shows at 1e9 .. 1e11 (inflation())."""
    rows = []

    def hook(sd, hh, order):
        rows.append((max(float(v.rad()) for v in sd.I),
                     max(abs(float(c[order].mid())) for c in sd.cx) * float(hh) ** order))

    run = _fly(20, tol, hook, "taylor_model", extra)
    a = np.array(rows)
    ratio = a[:, 0] / np.maximum(a[:, 1], 1e-300)
    return {**run, "I_rad_over_last_term": {"median": float(np.median(ratio)), "max": float(ratio.max())},
            "sum_I_rad": float(a[:, 0].sum()), "sum_last_term": float(a[:, 1].sum())}


def box_flights(method, set_index=0):
    """The C^1 flight of a Fig 4(a) horseshoe set (horseshoe_fig4a.json, set `set_index`, width ~1e-10) through one
    return at tol 1e-25, as the verifier flies it (the centre C^0 at tol_thin, the box C^1): CPU of each and the
    widths of P(c) and of DP."""
    from magrod.proof import ball, fields, section_return, taylor, taylor_model

    integ = {"taylor": taylor, "taylor_model": taylor_model}[method]
    c = json.loads(resources.files("magrod.proof").joinpath("certificates", "horseshoe_fig4a.json").read_text())
    p = fields.ExactParams(**{k: Fraction(v) for k, v in c["params"].items()})
    st = c["settings"]
    S = c["sets"][set_index]
    piece = c["flights"][set_index]["pieces"][0]
    cX = [Fraction(v) for v in S["c"]]
    AX = [[Fraction(v) for v in row] for row in S["A"]]
    out = {"method": method, "set": set_index}
    with ball.workprec(int(st["prec"]), int(st["series_cap"])):
        fld = fields.chart_field(p)
        fld.series = "newton"
        for kind, tt in (("thin", float(st["tol_thin"]) if method == "taylor" else 1e-28), ("box", float(st["tol"]))):
            t0 = time.process_time()
            f = section_return.piece_return(fld.pars, Fraction(c["level"]), fld, cX, AX, Fraction(piece["p_c"]),
                                            Fraction(st["p_rad"]), Fraction(piece["t_a"]), Fraction(st["lead"]),
                                            t1=Fraction(st["t1"]), order=int(st["order"]), tol=tt, tol_thin=tt,
                                            newton=int(st["newton"]), box=kind == "box", thin_c1=False,
                                            integrator=integ, thin=None if kind == "thin" else out["_thin"])
            if kind == "thin":
                out["_thin"] = f
            out[kind] = {"tol": tt, "cpu_s": round(time.process_time() - t0, 2),
                         "steps": sum(len(x) for x in f["steps"][kind])}
        out["thin"]["Pc_rad"] = [float(v.rad()) for v in f["Pc"]]
        out["box"]["DP_rad"] = [float(v.rad()) for row in f["DP"] for v in row]
        del out["_thin"]
    return out


def inflation(tol):
    from magrod.proof import ball

    rows = []

    def hook(sd, hh, order):
        hp = float(ball.pow_int(hh, order + 1))
        rows.append((max(abs(float(v.mid())) for v in sd.cY) * hp, max(float(v.rad()) for v in sd.cY) * hp,
                     max(abs(float(c[order].mid())) for c in sd.cx) * float(hh) ** order,
                     max(float(v.rad()) for v in sd.Y)))

    run = _fly(20, tol, hook)
    a = np.array(rows)
    ratio = a[:, 1] / np.maximum(a[:, 0], 1e-300)
    return {**run, "remainder_rad_over_mid": {"median": float(np.median(ratio)), "max": float(ratio.max())},
            "sum_remainder_rad": float(a[:, 1].sum()), "sum_remainder_mid": float(a[:, 0].sum()),
            "sum_last_term": float(a[:, 2].sum()), "Y_rad_median": float(np.median(a[:, 3]))}


def coefficient_growth():
    from flint import arb

    from magrod.proof import ball, fields, taylor

    p = _setup()[0]
    out = []
    with ball.workprec(128):
        fld = fields.chart_field(p)
        x = [arb(0.751), arb(0.3), arb(0.2), arb(1.13)]  # a point of the flight's middle (theta = 0.75)
        for series in ("newton", "picard"):
            fld.series = series
            cp, _ = taylor.solution_series(fld, x, 21)
            row = {"series": series, "k": [1, 5, 10, 15, 21],
                   "point_abs": [max(abs(float(c[k].mid())) for c in cp) for k in (1, 5, 10, 15, 21)], "by_width": {}}
            for w in (1e-2, 1e-3, 1e-4, 1e-6):
                Y = [v + ball.interval(-1, 1) * arb(w) for v in x]
                cY, _ = taylor.solution_series(fld, Y, 21)
                row["by_width"][f"{w:g}"] = [max(float(c[k].rad()) for c in cY) / w for k in (1, 5, 10, 15, 21)]
            out.append(row)
    return out


def remainder_control(tol, rem_tol):
    from magrod.proof import ball, taylor

    n = {"rejected": 0}

    def hook(sd, hh, order):
        r = max(float(v.rad()) for v in sd.cY) * float(ball.pow_int(hh, order + 1))
        if r > rem_tol and float(hh) > 1e-4:
            n["rejected"] += 1
            raise taylor.EnclosureError("remainder radius above rem_tol")

    return {**_fly(20, tol, hook), "rem_tol": rem_tol, **n}


def _costs_at(fld, cs, n: int, repeat: int, shared) -> dict:
    """step_cost's timings (microseconds per call) on the series of length n with coefficients cs."""
    import timeit

    from flint import arb_series

    def pair(kind):
        xs = [kind(c, prec=n) for c in cs]
        fld.rhs(xs, fld.pars)
        fld.jacobian(xs, fld.pars)

    a, b = arb_series(cs[0], prec=n), arb_series(cs[1], prec=n)
    fns = {"rhs_us": lambda: fld.rhs([arb_series(c, prec=n) for c in cs], fld.pars),
           "jac_us": lambda: fld.jacobian([arb_series(c, prec=n) for c in cs], fld.pars),
           "pair_plain_us": lambda: pair(arb_series), "pair_shared_trig_us": lambda: pair(shared),
           "product_us": lambda: a * b, "sin_us": lambda: a.sin(), "sqrt_us": lambda: b.sqrt()}
    t = {name: timeit.timeit(fn, number=repeat) / repeat * 1e6 for name, fn in fns.items()}
    return {"length": n, **{k: round(v, 2) for k, v in t.items()},
            "shared_trig_saves": round(1 - t["pair_shared_trig_us"] / t["pair_plain_us"], 3)}


def step_cost(lengths=(2, 6, 14, 21, 31), repeat=200, profile=True):
    """Where a step's CPU goes.  (a) cProfile of the Fig 4(a) set's C^1 box flight (box_flights, taylor_model): the
    share of the generated field's and Jacobian's evaluations (chart_rhs, chart_jacobian, on Arb series); (b) their
    cost per call by series length, against one series product, sin, sqrt at the longest length (the step evaluates
    the Jacobian on series of length L + 1 = 31 twice, the field on series up to 31 four times); (c) what sharing
    sin and cos would save: the field and its Jacobian evaluated on the same series, plain against a series type
    whose sin() and cos() come from one sin_cos() (bit for bit the same balls from length 3 on; measured here,
    not in the trust base)."""
    import cProfile
    import pstats

    from flint import arb, arb_series

    from magrod.proof import ball, fields

    class SharedTrig(arb_series):
        def _sc(self):
            if "sin_cos_" not in self.__dict__:
                self.__dict__["sin_cos_"] = arb_series.sin_cos(self)
            return self.__dict__["sin_cos_"]

        def sin(self):
            return self._sc()[0]

        def cos(self):
            return self._sc()[1]

    out = {}
    if profile:
        pr = cProfile.Profile()
        t0 = time.process_time()
        pr.enable()
        box_flights("taylor_model")
        pr.disable()
        total = time.process_time() - t0
        st = pstats.Stats(pr).stats
        gen = {fn[2]: v[3] for fn, v in st.items() if fn[0].endswith("validated.py")}  # cumulative time by function
        out["profile_box_flight"] = {"cpu_s": round(total, 2), "share": {k: round(v / total, 3) for k, v in gen.items()
                                                                          if k in ("chart_rhs", "chart_jacobian")}}
    p = _setup()[0]
    rng = np.random.default_rng(0)
    rows = []
    with ball.workprec(128, 64):
        fld = fields.chart_field(p)
        base = [0.75, 0.3, 0.2, 1.13]
        for n in lengths:
            cs = [[arb(base[i], 1e-20)] + [arb(float(rng.standard_normal()), 1e-20) for _ in range(n - 1)]
                  for i in range(4)]
            rows.append(_costs_at(fld, cs, n, repeat, SharedTrig))
    out["by_length"] = rows
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None)
    ap.add_argument("--smoke", action="store_true", help="a tiny span: one Taylor-model flight and the step's cost "
                    "at two series lengths, no profile (CI runs every benchmark so)")
    args = ap.parse_args()
    t0 = time.perf_counter()
    if args.smoke:
        res = {"taylor_model": [_fly(20, 1e-22, method="taylor_model")],
               "step_cost": step_cost(lengths=(2, 31), repeat=5, profile=False)}
        for r in res["taylor_model"] + res["step_cost"]["by_length"]:
            print(r)
        if not res["taylor_model"][0]["ok"]:
            raise SystemExit("centre_flight_frontier --smoke: the Taylor-model flight failed")
        return
    res = {"machine": platform.processor() or platform.machine(),
           "flight": "one return of Fig 4(b)'s x0 (fixed_point_fig4b.json), C^0, Newton series, 128 bits",
           "inflation": [inflation(1e-25), inflation(1e-32)],
           "coefficient_growth": coefficient_growth(),
           "order_tol": [_fly(o, t) for o in (20, 22, 24, 26, 32) for t in (1e-25, 1e-28, 1e-32)],
           "remainder_control": [remainder_control(1e-25, r) for r in (1e-24, 1e-30)],
           "taylor_model": {
               "order_tol": [_fly(o, t, method="taylor_model") for o in (20, 24) for t in (1e-22, 1e-25, 1e-28, 1e-32)],
               "extra": [tm_remainder(1e-25, e) for e in (0, 2, 5, 8, 10, 12)],
               "remainder": [tm_remainder(1e-28)]},
           "box_flights_fig4a": [box_flights(m) for m in ("taylor", "taylor_model")],
           "step_cost": step_cost()}
    res["wall_s"] = round(time.perf_counter() - t0, 1)
    text = json.dumps(res, indent=1)
    if args.out:
        with open(args.out, "w") as fh:
            fh.write(text + "\n")
    for r in res["order_tol"]:
        print(r)
    for r in res["inflation"] + res["remainder_control"]:
        print({k: v for k, v in r.items()})
    for r in res["taylor_model"]["order_tol"] + res["taylor_model"]["extra"] + res["taylor_model"]["remainder"]:
        print(r)
    for r in res["box_flights_fig4a"]:
        print(r)
    print(res["step_cost"].get("profile_box_flight"))
    for r in res["step_cost"]["by_length"]:
        print(r)


if __name__ == "__main__":
    main()
