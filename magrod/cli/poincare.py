"""`magrod poincare`: one orbit's Poincare section sin(psi) = 0, either a paper panel (--panel 4a .. 5d) or free
parameters (--m --mu --gamma --delta --lam --h --theta0 --ptheta0 [--psi0]).  Options given explicitly override
the panel's values.  With --out DIR the section is written as DIR/<stem>.npz, .json and .png (atomically).

With --starts FILE|GRID many orbits run on the same level (SIMD lanes on all cores) as a section portrait, each
orbit coloured by the chaos indicator of its start (--indicator): FILE holds rows theta0 ptheta0 [psi0
[p_psi0]] (whitespace or commas, # comments; .npy too), GRID is theta0:LO:HI:N,ptheta0:LO:HI:N (the grid points
that reach the level).  Example:  magrod poincare --panel 4a --starts theta0:0.1:3:8,ptheta0:-1:1:8 --out DIR"""
from __future__ import annotations

from ..core.errors import ParameterError
from ..generated.names import PARAMS
from .options import (LIMITS, ROOT_INDEX_HELP, add_model, add_out, add_params, add_precision, add_workers, indicator,
                      system_from, integer, number, out_dir,
                      stem)

_START = ("h", "theta0", "ptheta0", "psi0")
# the choices, known without importing heyoka (checked against magrod.chaos.section in the tests)
DIRECTIONS = ("any", "negative", "positive")
BRANCHES = ("any", "0", "pi")
FORMULATIONS = ("reduced", "body")


def add_arguments(p):
    from .options import add_panel, add_start

    add_panel(p, help="a panel of the paper, giving the rod, level and start (default 4a)")
    add_params(p, help_suffix=" (overrides the panel's)")
    g = p.add_argument_group("level and start (override the panel's)")
    add_start(g, _START)
    g.add_argument("--ppsi0", type=str, default=None, help="give pbar_psi0 instead of --h (then h = Hbar(start))")
    p.add_argument("--iterates", type=str, default="10000", help="number of section points")
    p.add_argument("--root", default="smallest", help=ROOT_INDEX_HELP)
    p.add_argument("--direction", default="positive", choices=DIRECTIONS,
                   help="sign of d/dt sin(psi) at recorded crossings")
    p.add_argument("--branch", default="any", choices=BRANCHES, help="psi = 0, psi = pi or both")
    p.add_argument("--formulation", default="body", choices=FORMULATIONS,
                   help="body: 9-D body frame; reduced: the paper's 4-D system (body frame near chart singularities)")
    p.add_argument("--t-max", type=str, default=None, help=f"max-time guard (default 100 x iterates, at most "
                                                           f"{100 * LIMITS['iterates']:.0e})")
    p.add_argument("--starts", default=None, metavar="FILE|GRID",
                   help="many orbits on the level: a file of rows theta0 ptheta0 [psi0 [p_psi0]], or "
                        "theta0:LO:HI:N,ptheta0:LO:HI:N (grid points that reach the level)")
    p.add_argument("--indicator", default="growth", type=indicator, metavar="{growth,fli,lyap,none}",
                   help="with --starts: colour of each orbit (chaos indicator of its start)")
    p.add_argument("--t-indicator", default="1000", help="with --starts: integration time of the indicator")
    add_workers(p, help="with --starts: threads (default: all cores)", old=("--threads",))
    add_precision(p, help="floating-point precision of the run (the paper's rod)")
    add_out(p, help="write <stem>.npz/.json/.png into this directory")
    p.add_argument("--stem", default=None, help="file name stem (default: fig<PANEL> or poincare)")
    add_model(p, help="a rod model of the family (`magrod models`) or a model file: its energy-level section in "
                      "the body frame (the paper's options above do not apply; default: the paper's rod)")


def _overridden(args) -> bool:
    return any(getattr(args, n, None) is not None for n in (*PARAMS, *_START, "ppsi0"))


def _inputs(args) -> tuple[dict, str | None]:
    from ..core.printed import PANELS, panel

    system, P = system_from(args, default_panel="4a")  # the rod, resolved once (ParameterError naming the field)
    vals = dict(system.params, **P.start())
    # the panel named by the result: the one given, or the default one when nothing of it is overridden
    key = panel(args.panel or "4a").key if args.panel is not None or not _overridden(args) else None
    for name in _START:
        v = getattr(args, name)
        if v is not None:
            vals[name] = number(name, v)
    if args.ppsi0 is not None:
        if args.h is not None:
            raise ParameterError("ppsi0", "give either --h or --ppsi0, not both")
        vals["p_psi0"] = number("ppsi0", args.ppsi0)
        vals.pop("h", None)  # a panel's h is replaced by Hbar at the given start
    vals.setdefault("psi0", 0.0)
    for name in (*PARAMS, "theta0", "ptheta0"):
        if name not in vals:
            raise ParameterError(name, f"missing: give --{name} (or --panel one of {', '.join(PANELS)})")
    if "h" not in vals and "p_psi0" not in vals:
        raise ParameterError("h", "missing: give --h (or --ppsi0, or --panel)")
    return vals, key


def parse_starts(value):
    """--starts: ("grid", (theta0 axis, ptheta0 axis)) for THETA0:LO:HI:N,PTHETA0:LO:HI:N, else ("file", array)
    read from the file (ParameterError("starts") if unreadable, of the wrong shape, empty or non-finite)."""
    import os

    text = str(value)
    parts = text.split(",")
    if all(q.count(":") == 3 for q in parts) and not os.path.exists(text):
        axes = {}
        for q in parts:
            name, lo, hi, n = q.split(":")
            if name not in ("theta0", "ptheta0") or name in axes:
                raise ParameterError("starts", f"a GRID is theta0:LO:HI:N,ptheta0:LO:HI:N, got {text[:80]!r}")
            axes[name] = (number("starts", lo), number("starts", hi), integer("starts", n, maximum=4096))
        if set(axes) != {"theta0", "ptheta0"}:
            raise ParameterError("starts", f"a GRID needs both theta0:LO:HI:N and ptheta0:LO:HI:N, got {text[:80]!r}")
        return "grid", (axes["theta0"], axes["ptheta0"])
    import numpy as np

    if not os.path.isfile(text):
        raise ParameterError("starts", f"no such file {text[:120]!r} (and not a GRID theta0:LO:HI:N,ptheta0:LO:HI:N)")
    try:
        if text.endswith(".npy"):
            a = np.load(text, allow_pickle=False)
        else:
            with open(text) as fh:
                rows = [ln.split("#")[0].replace(",", " ").split() for ln in fh]
            rows = [r for r in rows if r]
            a = np.array([[float(x) for x in r] for r in rows]) if rows else np.zeros((0, 2))
    except (OSError, ValueError) as exc:
        raise ParameterError("starts", f"cannot read {text[:120]!r}: {str(exc)[:120]}") from None
    from ..chaos import start_table

    return "file", start_table(a, "starts")


def _run_portrait(args, vals, key, params) -> dict:
    from .. import section_portrait
    from ..chaos import grid_starts
    from ..core.progress import bar

    for name in ("theta0", "ptheta0", "psi0", "ppsi0"):
        if getattr(args, name) is not None:
            raise ParameterError(name, "the starts come from --starts: do not also give --" + name)
    if "h" not in vals:
        raise ParameterError("h", "missing: give --h (or --panel) for the level of the portrait")
    kind, what = parse_starts(args.starts)
    iterates = integer("iterates", args.iterates)
    t_ind = number("t_indicator", args.t_indicator, bound=1e7)
    if t_ind <= 0:
        raise ParameterError("t_indicator", f"must be > 0, got {t_ind}")
    workers = None if args.workers is None else integer("workers", args.workers, maximum=256)
    t_max = None if args.t_max is None else number("t_max", args.t_max, bound=100.0 * LIMITS["iterates"])
    if t_max is not None and t_max <= 0:
        raise ParameterError("t_max", f"must be > 0, got {t_max}")
    if args.stem is not None and args.out is None:
        raise ParameterError("stem", "names the files written into --out: give --out too")
    name = stem("stem", args.stem) if args.stem is not None else (f"portrait{key}" if key else "portrait")
    out = out_dir("out", args.out) if args.out is not None else None
    if args.root not in ("largest", "smallest"):
        raise ParameterError("root", "with --starts give largest or smallest")
    if args.formulation != "body" or args.branch != "any":
        raise ParameterError("starts", "portraits run the body formulation with branch any")
    starts = grid_starts(params, vals["h"], theta0=what[0], ptheta0=what[1], psi0=0.0) if kind == "grid" else what
    if starts.shape[0] * iterates > 10 * LIMITS["iterates"]:
        raise ParameterError("starts", f"{starts.shape[0]} orbits x {iterates} iterates: at most "
                                       f"{10 * LIMITS['iterates']} section points in one command")
    indicator = None if args.indicator == "none" else args.indicator
    with bar(starts.shape[0] * iterates, "portrait", not args.quiet) as update:
        res = section_portrait(params, vals["h"], starts=starts, iterates=iterates, indicator=indicator,
                               t_indicator=t_ind, root=args.root, direction=args.direction, t_max=t_max,
                               workers=workers, progress=update)
    res.panel = key
    paths = {}
    if res.success and out is not None:
        from ..core.io import ensure_writable_dir
        from ..figures.portrait import save_portrait

        paths = save_portrait(res, ensure_writable_dir(out), name)
    d = {"ok": bool(res.success), "panel": key, "portrait": True, **res.summary(), "output": paths}
    if not res.success:
        d["error"] = res.message + ("; nothing written" if out is not None else "")
    return d


def _inputs_portrait(args) -> tuple[dict, str | None]:
    from ..core.printed import PANELS, panel

    system, P = system_from(args, default_panel="4a")
    vals = dict(system.params, h=P.h)
    key = panel(args.panel or "4a").key if args.panel is not None or not _overridden(args) else None
    if args.h is not None:
        vals["h"] = number("h", args.h)
    for name in PARAMS:
        if name not in vals:
            raise ParameterError(name, f"missing: give --{name} (or --panel one of {', '.join(PANELS)})")
    return vals, key


def run(args) -> dict:
    """Parse, call magrod.chaos.section.poincare_section (which validates the start and checks its own accuracy),
    write the files of a successful run."""
    from .. import poincare_section
    from ..core.params import RodParams
    from ..core.progress import bar

    if args.model is not None:
        return _run_model(args)
    if args.model_params is not None:
        raise ParameterError("model-params", "applies only with --model")
    if args.starts is not None:
        vals, key = _inputs_portrait(args)
        return _run_portrait(args, vals, key, RodParams(**{k: vals[k] for k in PARAMS}))
    vals, key = _inputs(args)
    params = RodParams(**{k: vals[k] for k in PARAMS})
    iterates = integer("iterates", args.iterates)
    t_max = None if args.t_max is None else number("t_max", args.t_max, bound=100.0 * LIMITS["iterates"])
    if t_max is not None and t_max <= 0:
        raise ParameterError("t_max", f"must be > 0, got {t_max}")
    if args.stem is not None and args.out is None:
        raise ParameterError("stem", "names the files written into --out: give --out too")
    name = stem("stem", args.stem) if args.stem is not None else (f"fig{key}" if key else "poincare")
    out = out_dir("out", args.out) if args.out is not None else None
    root = args.root if args.root in ("largest", "smallest") else integer("root", args.root, minimum=-10**9,
                                                                          maximum=10**9)
    kw = dict(h=vals.get("h"), theta0=vals["theta0"], ptheta0=vals["ptheta0"], psi0=vals["psi0"],
              p_psi0=vals.get("p_psi0"), iterates=iterates, root=root, direction=args.direction, branch=args.branch,
              formulation=args.formulation, t_max=t_max, verify=True, precision=args.precision)
    try:
        with bar(iterates, "poincare", not args.quiet) as update:
            res = poincare_section(params, **kw, progress=update)
    except ParameterError as exc:
        if exc.name == "p_psi0":  # the library's name of --ppsi0
            raise ParameterError("ppsi0", exc.message) from None
        raise
    res.panel = key
    paths = {}
    if res.success and out is not None:
        from ..core.io import ensure_writable_dir
        from ..core.printed import PANELS
        from ..figures.poincare import save_result

        paths = save_result(res, ensure_writable_dir(out), name, key=key, label=PANELS[key]["label"] if key else None)
    out_d = {"ok": bool(res.success), "panel": key, **res.summary(), "output": paths}
    if not res.success:
        out_d["error"] = res.message + ("; nothing written" if out is not None else "")
    return out_d


def _run_model(args) -> dict:
    """`poincare --model NAME|FILE`: the model's section (magrod.chaos.model_chaos), files <stem>.npz/.json."""
    import magrod as mr

    from ..core.io import atomic_savez, atomic_write_json, versions
    from ..core.models import resolve
    from .models import parse_assignments

    for opt in ("panel", "starts", *PARAMS, *_START, "ppsi0"):
        if getattr(args, opt, None) is not None:
            raise ParameterError(opt, "is an option of the paper's rod: with --model give --model-params")
    if args.precision != "double":
        raise ParameterError("precision", "the section of a model other than the paper's rod runs in double "
                                          "precision in this release")
    mc = resolve(args.model)
    params = {k: float(v) for k, v in parse_assignments("model-params", args.model_params, mc.names.PARAMS).items()}
    iterates = integer("iterates", args.iterates)
    t_max = None if args.t_max is None else number("t_max", args.t_max, bound=100.0 * LIMITS["iterates"])
    if args.stem is not None and args.out is None:
        raise ParameterError("stem", "names the files written into --out: give --out too")
    name = stem("stem", args.stem) if args.stem is not None else mc.name.replace("-", "_")
    out = out_dir("out", args.out) if args.out is not None else None
    import numpy as np

    from ..core.system import as_system

    system = as_system(mc.name if mc.origin == "registry" else mc.origin, **params)[0]
    secs = mr.poincare_sections(system, starts=4, iterates=iterates, t_max=t_max, formulation=args.formulation)
    bad = [r for r in secs if not r.success]
    if bad:
        raise ParameterError("model", bad[0].message)
    points = np.full((len(secs), iterates, len(secs[0].points[0]) if secs[0].n_points else 0), np.nan)
    for k, r in enumerate(secs):
        points[k, : r.n_points] = r.points
    from ..core import systems as _systems

    mb = _systems.model_body(system)
    lvl = mb.level(secs[0].body_points[0], system.array()) if secs[0].n_points else []
    d = {"success": True, "message": secs[0].message, "model": mc.name, "params": system.params,
         "system": system.to_dict(), "state_names": list(mb.state),
         "level": {k: float(v) for k, v in zip(("H", *mc.names.CASIMIRS), lvl)},
         "counts": [r.n_points for r in secs], "points_shape": list(points.shape),
         "energy_error": max(r.max_abs_dH for r in secs),
         "casimir_error": max(r.casimir_drift or 0.0 for r in secs)}
    d["model_section"] = True
    if out is not None:
        d["files"] = [str(atomic_savez(out / f"{name}.npz", points=points)),
                      str(atomic_write_json(out / f"{name}.json", {**d, "versions": versions()}))]
    d["ok"] = True
    return d


def format_text(r: dict) -> str:
    if r.get("model_section"):
        return (f"model {r['model']}: section {r['state_names'][0]} ... , level {r['level']}\n"
                f"  {r['points_shape'][0]} orbits x {r['points_shape'][1]} crossings (counts {r['counts']}); "
                f"max |H - h| = {r['energy_error']:.1e}, max |C - C0| = {r['casimir_error']:.1e}"
                + ("".join(f"\n  wrote {f}" for f in r.get("files", []))))
    if r.get("portrait"):
        p = r["parameters"]
        lines = [f"Section portrait sin(psi) = 0{' (Fig. ' + r['panel'] + ')' if r.get('panel') else ''}: "
                 + ", ".join(f"{k} = {v:g}" for k, v in p.items()) + f", h = {r['h']:.12g}",
                 f"  {r['n_orbits']} orbits, {min(r['iterates'])}..{max(r['iterates'])} iterates each, wall "
                 f"{r['wall_s']:.2f} s, max |Hbar - h| = {r['accuracy']['max_abs_dH']:.2e}"]
        if r.get("indicator"):
            fc = r.get("fraction_chaotic")
            lines.append(f"  indicator {r['indicator']} (T = {r['t_indicator']:g})"
                         + (f": fraction chaotic {fc:.2f}" if fc is not None else ""))
        if not r["success"]:
            lines.append(f"  FAILED: {r['message']}")
        for kind, path in (r.get("output") or {}).items():
            lines.append(f"  wrote {kind}: {path}")
        return "\n".join(lines)
    p = r["parameters"]
    lines = [f"Poincare section sin(psi) = 0{' (Fig. ' + r['panel'] + ')' if r.get('panel') else ''}: "
             + ", ".join(f"{k} = {v:g}" for k, v in p.items()) + f", h = {r['h']:.12g}",
             f"  start theta0 = {r['theta0']:g}, pbar_theta0 = {r['ptheta0']:g}, psi0 = {r['psi0']:g}; "
             f"roots pbar_psi = {', '.join(f'{x:.15g}' for x in r['roots'])}; using {r['p_psi0']:.15g}",
             f"  {r['n_points']} of {r['iterates_requested']} iterates ({r['formulation']} formulation, direction "
             f"{r['direction']}, branch {r['branch']}), final t = {r['final_time']:.6g}, wall {r['wall_s']:.2f} s",
             f"  max |Hbar - h| = {r['max_abs_dH']:.2e}"
             + (f", Casimir drift {r['casimir_drift']:.2e}" if r.get("casimir_drift") is not None else "")
             + f", max section residual {r['max_abs_section_residual']:.1e}"]
    if not r["success"]:
        lines.append(f"  FAILED: {r['message']}")
    for kind, path in (r.get("output") or {}).items():
        lines.append(f"  wrote {kind}: {path}")
    return "\n".join(lines)
