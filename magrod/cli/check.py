"""`magrod check`: the integrability report (magrod.integrability.report), from generated/report.json, re-derived
(--rederive) or for a modified model (--subs); with --integrals, the exact search for polynomial first integrals
(magrod.integrability.first_integrals).  Imports neither heyoka nor matplotlib."""
from __future__ import annotations


def add_arguments(p):
    p.add_argument("--rederive", action="store_true",
                   help="re-run the SymPy derivation instead of reading generated/report.json (slower)")
    p.add_argument("--all", action="store_true", help="include every derived result, not only the integrability ones")
    p.add_argument("--subs", metavar="NAME=VALUE,...",
                   help="compute the involution table of H, I1, I2 and the Casimirs live for a modified model, e.g. "
                        "'B2=B1,c_J=c_H,lambda=0' (symbols: B1 B2 C c_H c_J c_K lambda; c = 1/stiffness, so "
                        "c_H=0,c_J=0,c_K=0 is the inextensible, unshearable rod); needs sympy.  With --integrals: "
                        "the model searched (default B2=B1,c_J=c_H, the paper's rod)")
    p.add_argument("--integrals", action="store_true",
                   help="exact search for polynomial first integrals of degree <= --degree in the 9 body variables "
                        "(kernel of F -> {F, H} mod a prime against the algebra of the known integrals), with the "
                        "controls lambda = 0, inextensible, anisotropic, extensible")
    p.add_argument("--degree", type=str, default=None, help="maximum degree D of the search, 1 <= D <= 12 (default 4; "
                                                             "D = 6 takes minutes)")
    p.add_argument("--seed", type=str, default=None, help="seed of the random rational parameter values (default 20)")
    p.add_argument("--model", default=None, metavar="NAME|FILE.py",
                   help="a rod model of the family (`magrod models`) or a model file ./my_rod.py (code you run on "
                        "purpose: executed, checked, compiled into the cache): its derivation report; with "
                        "--integrals the exact search on it (default: the paper's rod, as without --model)")
    p.add_argument("--model-params", default=None, metavar="NAME=VALUE,...",
                   help="with --model --integrals: exact parameter values (integer, decimal or p/q); the others are "
                        "seeded random rationals")
    p.add_argument("--fast", action="store_true",
                   help="with --model FILE.py: skip the slow exact analyses (Kovalevskaya exponents, Painleve test, "
                        "Morales-Ramis; seconds to minutes of SymPy); registered models read them stored")
    p.add_argument("--morales-ramis", action="store_true",
                   help="with --model FILE.py: also run Morales-Ramis along the pendulum solutions (Kovacic's "
                        "algorithm; tens of seconds per pendulum); registered models read it stored")
    p.add_argument("--level", default=None, metavar="CASIMIR=VALUE,...",
                   help="with --model --integrals: search on a special Casimir level, e.g. C2=0 (m.n = 0)")


def run(args) -> dict:
    from ..core.errors import ParameterError
    from . import options

    if args.model is not None:
        return _run_model(args)
    for opt in ("model_params", "level"):
        if getattr(args, opt, None) is not None:
            raise ParameterError(opt.replace("_", "-"), "applies only with --model")
    for opt in ("fast", "morales_ramis"):
        if getattr(args, opt, False):
            raise ParameterError(opt.replace("_", "-"), "applies only with --model")

    if args.integrals:
        if args.rederive or args.all:
            raise ParameterError("integrals", "searches first integrals: do not combine it with --rederive or --all")
        from ..integrability import DEFAULT_SEED, MAX_DEGREE

        degree = options.integer("degree", "4" if args.degree is None else args.degree, 1, MAX_DEGREE)
        seed = options.integer("seed", DEFAULT_SEED if args.seed is None else args.seed, 0, 2**62)
        if args.subs is not None and not args.subs.strip():
            raise ParameterError("subs", "is empty")
        from ..integrability import first_integral_search

        return first_integral_search(degree, args.subs, seed=seed).to_dict()
    if args.degree is not None or args.seed is not None:
        raise ParameterError("degree" if args.degree is not None else "seed", "applies only with --integrals")

    from ..integrability import custom_involution, report_summary as summary

    if args.subs is not None:
        if args.rederive or args.all:
            raise ParameterError("subs", "computes one custom table: do not combine it with --rederive or --all")
        return custom_involution(args.subs)
    return summary(args.rederive, args.all)


def _run_model(args) -> dict:
    """`check --model NAME|FILE [--integrals --degree D --model-params ... --level ...]`."""
    from ..core.errors import ParameterError
    from ..core.models import resolve
    from . import options
    from .models import parse_assignments

    for opt in ("subs", "rederive", "all"):
        if getattr(args, opt):
            raise ParameterError(opt, "applies to the paper's rod, not with --model")
    mc = resolve(args.model)
    if not args.integrals:
        for opt in ("model_params", "level", "degree", "seed"):
            if getattr(args, opt) is not None:
                raise ParameterError(opt.replace("_", "-"), "applies only with --integrals")
        from ..integrability import model_report

        rep = model_report(mc, decided=not args.fast, morales_ramis=args.morales_ramis)
        return {"ok": rep.success, "model": mc.name, "source": rep.source, "results": rep.rows,
                "statuses": rep.statuses, "disagreements_with_paper": []}
    from ..integrability import DEFAULT_SEED, MAX_DEGREE
    from ..integrability import search_model as model_search

    degree = options.integer("degree", "4" if args.degree is None else args.degree, 1, MAX_DEGREE)
    seed = options.integer("seed", DEFAULT_SEED if args.seed is None else args.seed, 0, 2**62)
    values = parse_assignments("model-params", args.model_params, mc.names.PARAMS)
    level = parse_assignments("level", args.level, mc.names.CASIMIRS)
    r = model_search(mc, degree, values=values, level=level, seed=seed)
    d = r.to_dict()
    d["ok"] = True
    d["search"] = True
    return d


def format_text(out: dict) -> str:
    if out.get("search"):
        lines = [f"[{'certified' if out['certified'] else 'NOT certified'}] model {out['model']}: polynomial first "
                 f"integrals of degree <= {out['degree']}" + (f" on the level {out['level']}" if out["level"] else ""),
                 f"    parameters: {out['values']}",
                 f"    known: {', '.join(out['known'])}; candidates lost: {', '.join(out['candidates_lost']) or '-'}",
                 f"    dim ker L, degree <= 0..{out['degree']}: {out['kernel_dims']}",
                 f"    dim known algebra:           {out['algebra_dims']}"]
        for f, ok in zip(out["new_integrals"], out["new_verified"]):
            lines.append(f"    NEW integral ({'{F, H} = 0 re-checked exactly' if ok else 'RE-CHECK FAILED'}): {f}")
        lines += [f"    {out['message']}  ({out['wall_time_s']:.2f} s)", "", out["statement"]]
        return "\n".join(lines)
    if "controls" in out:
        from ..integrability import format_integrals as fmt_integrals

        return fmt_integrals(out)
    from ..integrability import format_report as fmt

    return fmt(out)
