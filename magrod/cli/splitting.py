"""`magrod splitting --m 1.7 --gamma 1 --delta 1 --a 2 --b 1 --eps 0.1,0.03,0.01 --precision quad`: splitting of
the separatrix of the straight rod along mu = a eps^2, lambdabar = b eps^2 (eq:condition_unperturbed_1),
measured at the first turning point of the unstable manifold (magrod/splitting.py, docs/nonintegrability.md).
a = 2b: the saddle is the straight rod (an equilibrium); D = psi_u and d = rho sin psi_u.  a > 2b: the saddle is
the tilted straight rod (a saddle-focus of the reduced chart); D(psi) = theta_u(psi) - theta_u(-psi) ~ 2 s1 sin psi.
The result is computed in --precision (a magrod Precision: double, "long double", quad, mp) and checked in the next
lower precision.

Any other model with a saddle and a small parameter (--model NAME|FILE.py [--model-params ...]: the anisotropic rod,
B2 = B1 (1 + eps), and the curved rod, k1 = eps): the splitting of its straight rod's homoclinic manifold measured
against its Mel'nikov function, per --eps (`mr.splitting`).  A model without a small parameter is named with what it
lacks (exit 2)."""
from __future__ import annotations

from .options import add_model, integer, is_paper_model, number, out_dir

DEFAULTS = {"m": "1.7", "gamma": "1", "delta": "1", "a": "2", "b": "1", "eps": "0.3,0.1,0.03,0.01,0.003,0.001",
            "precision": "quad", "phases": "64"}  # the paper's rod's scan (eq:condition_unperturbed_1)

# the check precision of each working precision: the next lower one
CHECK = {"mp": "quad", "quad": "long double", "long double": "double", "double": None}


def add_arguments(p):
    d = DEFAULTS
    p.add_argument("--m", default=None, help=f"m = m3/sqrt(B C2), 0 < m < m_c = 2 sqrt(1 + gamma) (default {d['m']})")
    p.add_argument("--gamma", default=None, help=f"extensibility gamma >= 0 (default {d['gamma']})")
    p.add_argument("--delta", default=None, help=f"shear compliance delta >= 0 (default {d['delta']})")
    p.add_argument("--a", default=None, help=f"mu = a eps^2 (a >= 2b) (default {d['a']})")
    p.add_argument("--b", default=None, help=f"lambdabar = b eps^2 (b >= 0) (default {d['b']})")
    p.add_argument("--eps", default=None, help=f"comma-separated eps > 0 (default {d['eps']}; another model: the "
                                               "library's scan)")
    p.add_argument("--precision", default=None, choices=tuple(CHECK),
                   help=f"working precision of the reference values (checked in the next lower one) (default "
                        f"{d['precision']})")
    p.add_argument("--phases", default=None, help=f"launch phases on the unstable eigenplane (a > 2b only) (default "
                                                  f"{d['phases']})")
    p.add_argument("--out", default=None, help="write splitting.json/.npz/.png into this directory")
    add_model(p, help="the rod model: a registered name (`magrod models`) or a model file, with a saddle and a small "
                      "parameter (default: the paper's rod)")


def _eps_list(s):
    """The comma-separated --eps as numbers (their range, distinctness and resolvability: the library's
    magrod.separatrix.splitting.check_eps)."""
    return [number("eps", x) for x in str(s).split(",") if x.strip()]


def run(args) -> dict:
    from .. import System, splitting
    from ..separatrix import scan_summary
    from ..core.progress import bar

    if not is_paper_model(args.model):
        return _model_run(args)
    if args.model_params:
        from ..core.errors import ParameterError

        raise ParameterError("model_params", "needs --model (the paper's rod takes --m --gamma --delta --a --b)")
    for k, v in DEFAULTS.items():
        if getattr(args, k) is None:
            setattr(args, k, v)
    vals = {k: number(k, getattr(args, k)) for k in ("m", "gamma", "delta", "a", "b")}
    eps = _eps_list(args.eps)
    n = integer("phases", args.phases, minimum=8, maximum=4096)
    dest = out_dir("out", args.out) if args.out is not None else None
    precs = tuple(p for p in (CHECK[args.precision], args.precision) if p)
    with bar(len(eps), "splitting", not args.quiet, unit="eps") as update:
        spl = splitting(System(m=vals["m"], gamma=vals["gamma"], delta=vals["delta"]), a=vals["a"], b=vals["b"],
                        eps=eps, precisions=precs, n_phases=n, progress=update)
    res = spl.scan
    if spl.kind == "equilibrium":
        out = {"ok": True, "case": "equilibrium (a = 2b)", **scan_summary(res)}
    else:
        out = {"ok": True, "case": "tilted saddle-focus (a > 2b)", **res.to_dict(), "precisions": list(precs)}
    if spl.leading is not None:
        out["leading"] = spl.leading
    if dest is not None:
        from ..figures.splitting import write

        out["paths"] = write(res, dest)
    return out


def _model_run(args) -> dict:
    """Another model: mr.splitting(system, eps=...) (its Mel'nikov measurement), with its accuracy; --out DIR:
    splitting.json + splitting.npz (Result.save)."""
    import magrod as mr

    from .modelrun import refuse
    from .options import system_from

    system, _ = system_from(args)
    refuse(args, ("m", "gamma", "delta", "a", "b", "precision", "phases"), system.model,
           "belongs to the paper's rod's scaling mu = a eps^2, lambdabar = b eps^2")
    eps = None if args.eps is None else _eps_list(args.eps)
    dest = out_dir("out", args.out) if args.out is not None else None
    spl = mr.splitting(system) if eps is None else mr.splitting(system, eps=eps)
    acc = spl.accuracy
    # the small parameter replaces one of the model's parameters (B2 = B1 (1 + eps), k1 = eps): `perturbation`
    out = {"ok": bool(spl.success and acc.get("passed", True)), "case": "Mel'nikov measurement", "model": system.model,
           "params": system.params, "perturbation": getattr(spl.scan, "perturbation", None), **spl.to_dict(),
           "accuracy": acc}
    if not out["ok"]:
        out["error"] = spl.message
    elif dest is not None:
        from ..core.io import ensure_writable_dir

        out["paths"] = spl.save(ensure_writable_dir(dest, "out") / "splitting")
    return out


def _fit_line(name, f):
    if not f:
        return f"  {name}: no fit"
    return (f"  {name} ~ C eps^p:  p = {f['p']:.4f} (drop smallest eps: {f['p_drop_smallest']:.4f}, drop largest: "
            f"{f['p_drop_largest']:.4f}), max |log residual| {f['max_abs_residual']:.2e};  "
            f"C0 = lim {name}/eps^{f['p_int']} = {f['C0']:+.8g}")


def format_text(r: dict) -> str:
    if r.get("model"):
        from .modelrun import checks, header

        lead = r.get("leading") or {}
        lines = [f"splitting of the separatrix of {header(r)} under {r['perturbation']} (Mel'nikov measurement)",
                 f"  {'eps':>9s} {'c / eps':>22s}"]
        lines += [f"  {e:9.3g} {m:+22.14e}" for e, m in zip(r["eps"], r["measure"])]
        if lead:
            lines.append(f"  Mel'nikov coefficient per unit eps {lead['melnikov_unit']:+.12g}, measured "
                         f"{lead['measured_unit']:+.12g} ({lead['digits']:.3g} digits)")
        lines.append(f"  checks: {checks(r['accuracy'])}")
        lines += [f"  wrote {p}" for p in r.get("paths", [])]
        return "\n".join(lines)
    lines = [f"{r['case']}: m = {r['m']:g}, gamma = {r['gamma']:g}, delta = {r['delta']:g}, a = {r['a']:g}, "
             f"b = {r['b']:g}; precisions {', '.join(r['precisions'])}"]
    if "rows" in r:
        lines.append(f"  {'eps':>9s} {'psi_u':>22s} {'d = rho sin psi_u':>22s} {'theta_u':>10s} {'|dH|':>8s}")
        for row in r["rows"]:
            lines.append(f"  {row['eps']:9.3g} {row['psi']:+22.14e} {row['d']:+22.14e} {row['theta']:10.6f} "
                         f"{abs(row['H_drift']):8.1e}")
        for k, v in r["agreement_psi"].items():
            lines.append(f"  max relative difference {k} vs {r['precisions'][-1]}: psi_u {v:.1e}, d "
                         f"{r['agreement_d'][k]:.1e}")
        lines += [_fit_line("psi_u", r["fit_psi"]), _fit_line("d", r["fit_d"])]
        lines += ["  " + n for n in r["notes"]]
    else:
        lines.append(f"  {'eps':>9s} {'s1 (D ~ 2 s1 sin psi)':>24s} {'s2':>12s} {'fit residual':>12s}")
        for c in r["curves"]:
            lines.append(f"  {c['eps']:9.3g} {c['sin_coeffs'][0]:+24.12e} {c['sin_coeffs'][1]:+12.4e} "
                         f"{c['fit_residual']:12.1e}")
        lines.append(f"  max |s1 difference| between precisions: {r['agreement_s1']:.1e}")
        lines.append(_fit_line("s1", r["fit_s1"]))
    for p in r.get("paths", []):
        lines.append(f"  wrote {p}")
    return "\n".join(lines)
