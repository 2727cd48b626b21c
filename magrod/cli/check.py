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
    p.add_argument("--seed", type=str, default=None,
                   help="seed of the random rational parameter values (default 20; with --model, the model's own "
                        "parameter values unless a seed is given)")
    p.add_argument("--model", default=None, metavar="NAME|FILE.py",
                   help="a rod model of the family (`magrod models`) or a model file ./my_rod.py (code you run on "
                        "purpose: executed, checked, compiled into the cache): its derivation report and the exact "
                        "search for polynomial first integrals (to --degree) at the model's own parameter "
                        "values; with --integrals the search alone (default: the paper's rod, as without "
                        "--model)")
    p.add_argument("--model-params", default=None, metavar="NAME=VALUE,...",
                   help="with --model: exact parameter values of the search (integer, decimal, 1e-8 or p/q); the "
                        "others at the model's defaults (or seeded random rationals with --seed)")
    p.add_argument("--fast", action="store_true",
                   help="with --model FILE.py: skip the slow exact analyses (Kovalevskaya exponents, Painleve test, "
                        "Morales-Ramis; seconds to minutes of SymPy); registered models read them stored")
    p.add_argument("--morales-ramis", action="store_true",
                   help="with --model FILE.py: also run Morales-Ramis along the pendulum solutions (Kovacic's "
                        "algorithm; tens of seconds per pendulum); registered models read it stored")
    p.add_argument("--level", default=None, metavar="CASIMIR=VALUE,...",
                   help="with --model: search on a special Casimir level, e.g. C2=0 (m.n = 0)")
    p.add_argument("--no-cache", action="store_true",
                   help="with --model FILE: compile the model file afresh into a temporary directory, the cache "
                        "untouched (also: environment variable MAGROD_NO_MODEL_CACHE=1)")


def run(args) -> dict:
    from ..core.errors import ParameterError
    from . import options

    if args.model is not None:
        return _run_model(args)
    for opt in ("model_params", "level"):
        if getattr(args, opt, None) is not None:
            raise ParameterError(opt.replace("_", "-"), "applies only with --model")
    if getattr(args, "no_cache", False):
        raise ParameterError("no-cache", "applies only with --model FILE")
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
    """`check --model NAME|FILE [--integrals] [--degree D] [--seed S] [--model-params ...] [--level ...]`: the
    model's derivation report and the exact search (--integrals: the search alone)."""
    from ..core.errors import ParameterError
    from ..core.models import resolve
    from ..integrability import MAX_DEGREE
    from ..integrability import search_model as model_search
    from . import options
    from .models import parse_assignments

    for opt in ("subs", "rederive", "all"):
        if getattr(args, opt):
            raise ParameterError(opt, "applies to the paper's rod, not with --model")
    mc = resolve(args.model, cache=False if getattr(args, "no_cache", False) else None)
    degree = options.integer("degree", "4" if args.degree is None else args.degree, 1, MAX_DEGREE)
    seed = None if args.seed is None else options.integer("seed", args.seed, 0, 2**62)
    values = parse_assignments("model-params", args.model_params, mc.names.PARAMS)
    level = parse_assignments("level", args.level, mc.names.CASIMIRS)
    r = model_search(mc, degree, values=values, level=level, seed=seed)
    d = r.to_dict()
    d["kind"] = "search"
    if args.integrals:
        d["ok"] = True
        return d
    from ..integrability import model_report

    rep = model_report(mc, decided=not args.fast, morales_ramis=args.morales_ramis)
    return {"ok": rep.success, "kind": "model", "model": mc.name, "title": mc.names.TITLE,
            "source": mc.names.SOURCE, "report": rep.source, "results": rep.rows, "statuses": rep.statuses,
            "search": d}


def _search_text(out: dict) -> list:
    head = ("certified" if out["certified"] and not out["new_integrals"] else
            f"found {len(out['new_integrals'])} integral(s); certified complete with them" if out["certified"] else
            "not certified: the kernel exceeds the known algebra")
    lines = [f"[{head}] model {out['model']}: polynomial first integrals of degree <= {out['degree']}"
             + (f" on the level {out['level']}" if out["level"] else ""),
             f"    parameters: {out['values']}",
             f"    known: {', '.join(out['known'])}; candidates lost: {', '.join(out['candidates_lost']) or '-'}",
             f"    dim ker L, degree <= 0..{out['degree']}: {out['kernel_dims']}",
             f"    dim algebra (known and found):  {out['algebra_dims']}"]
    for f, ok in zip(out["new_integrals"], out["new_verified"]):
        lines.append(f"    found integral ({'{F, H} = 0 re-checked exactly' if ok else 'RE-CHECK FAILED'}): {f}")
    lines += [f"    {out['message']}  ({out['wall_time_s']:.2f} s)", "", out["statement"]]
    return lines


def _model_text(out: dict) -> str:
    from ..integrability import report_row_details as row_details

    lines = [f"magrod derivation report: model {out['model']} ({out['title']}; source: {out['source']})",
             f"    read from {out['report']}", ""]
    for r in out["results"]:
        lines.append(f"[{r['status']}] {r['title']}")
        lines.append(f"    shown by: {r['method']}")
        lines += row_details(r)
        lines.append("")
    return "\n".join(lines + _search_text(out["search"]))


def format_text(out: dict) -> str:
    if out.get("kind") == "search":
        return "\n".join(_search_text(out))
    if out.get("kind") == "model":
        return _model_text(out)
    if "controls" in out:
        from ..integrability import format_integrals as fmt_integrals

        return fmt_integrals(out)
    from ..integrability import format_report as fmt

    return fmt(out)
