"""`magrod spectrum`: the Lyapunov spectrum (all 9 exponents, QR/Benettin on the body frame's variational system)
of one orbit, and with --gali its GALI_2..4 (Skokos et al. 2007).  The orbit is a paper panel (--panel 4a ..
5d, default 4a) with any value overridden, or free parameters and a start (--m --mu --gamma --delta --lam --h
--theta0 --ptheta0 [--psi0]).  With --out DIR: DIR/<stem>.json and DIR/<stem>.png (the running exponents, and
GALI against t) written atomically.

Example:  magrod spectrum --panel 4a --t-max 3000 --gali --out DIR"""
from __future__ import annotations

from ..core.errors import ParameterError
from ..generated.names import PARAMS
from .options import ROOT_HELP, add_model, add_panel, add_params, add_start, number, out_dir, stem, system_from

_START = ("h", "theta0", "ptheta0", "psi0")


def add_arguments(p):
    add_panel(p, help="the paper panel whose orbit is used (default 4a)")
    add_model(p, help="the rod model: a registered name (`magrod models`) or a model file, whose orbit from its "
                      "reference state is used (default: the paper's rod)")
    add_params(p, help_suffix=" (overrides the panel's)")
    add_start(p.add_argument_group("start (overrides the panel's)"), _START, suffix=" (overrides the panel's)")
    p.add_argument("--root", default="smallest", choices=["smallest", "largest"], help=ROOT_HELP)
    p.add_argument("--t-max", default="3000", help="integration length T")
    p.add_argument("--renorm-dt", default="10", help="interval between QR re-orthonormalisations (GALI samples)")
    p.add_argument("--tol", default=None, help="Taylor tolerance (default: machine epsilon; 0 means it too)")
    p.add_argument("--gali", action="store_true", help="also GALI_2, GALI_3, GALI_4 of the orbit")
    p.add_argument("--out", default=None, help="write <stem>.json and <stem>.png into this directory")
    p.add_argument("--stem", default="spectrum", help="file name stem")


def run(args) -> dict:
    system, P = system_from(args, default_panel="4a")  # what is studied, resolved once (ParameterError naming it)
    if not system.is_paper:
        for opt in (*_START, "root"):
            if opt != "root" and getattr(args, opt) is not None:
                raise ParameterError(opt, "is a start on the paper's chart: another model's orbit starts at its "
                                          "reference state")
        start = None
    else:
        start = dict(P.start())
        for name in _START:
            v = getattr(args, name)
            if v is not None:
                start[name] = number(name, v)
    t_max = number("t_max", args.t_max, bound=1e7)
    renorm_dt = number("renorm_dt", args.renorm_dt)
    tol = 0.0 if args.tol is None else number("tol", args.tol, bound=1.0)
    if tol < 0:
        raise ParameterError("tol", f"must be >= 0 (0 = machine epsilon), got {tol:g}")
    name = stem("stem", args.stem)
    out = out_dir("out", args.out) if args.out is not None else None
    overridden = any(getattr(args, k) is not None for k in (*PARAMS, *_START))
    if not system.is_paper:
        what, overridden = system, True
        kw = dict(t_max=t_max, renorm_dt=renorm_dt, tol=tol or None)
    else:
        what = P.key if not overridden else system.rod  # the panel key itself when nothing is overridden
        kw = dict(h=start["h"], theta0=start["theta0"], ptheta0=start["ptheta0"], psi0=start.get("psi0", 0.0),
                  root=args.root, t_max=t_max, renorm_dt=renorm_dt, tol=tol or None)
        if not overridden:
            kw = dict(root=args.root, t_max=t_max, renorm_dt=renorm_dt, tol=tol or None)

    from .. import gali, lyapunov_spectrum

    sp = lyapunov_spectrum(what, **kw)
    g = gali(what, **kw) if args.gali else None
    res = {"ok": bool(sp.success and (g is None or g.success)), "panel": P.key if not overridden else None,
           **({} if system.is_paper else {"model": system.model}),
           "params": dict(system.params), "start": start, "t_max": t_max, "renorm_dt": sp.renorm_dt,
           "exponents": sp.exponents.tolist(), "pairing": sp.pairing.tolist(), "accuracy": sp.accuracy,
           "message": sp.message}
    if g is not None:
        res["gali"] = {"final": g.final, "decay": {str(k): v for k, v in g.decay().items()}, "message": g.message}
    if out is not None:
        from ..core.io import atomic_write_json, ensure_writable_dir, versions
        from ..figures.chaos import draw_spectrum

        out = ensure_writable_dir(out)
        png = draw_spectrum(sp, g, out / f"{name}.png")
        res["output"] = {"png": str(png), "json": str(out / f"{name}.json")}
        from ..core.results import jsonable

        atomic_write_json(out / f"{name}.json", jsonable({**res, "versions": versions()}))
    return res


def format_text(d: dict) -> str:
    ex = ", ".join(f"{v:+.4g}" for v in d["exponents"])
    what = f"model {d['model']}" if d.get("model") else ('panel ' + d['panel'] if d['panel'] else 'given orbit')
    lines = [f"Lyapunov spectrum ({what}, T = {d['t_max']:g}, "
             f"renorm every {d['renorm_dt']:g}): {ex}",
             f"  pairing lambda_i + lambda_(n+1-i): max {d['accuracy']['max_pairing']:.2g}; sum "
             f"{d['accuracy']['sum']:.2g}; |dH| {d['accuracy']['max_abs_dH']:.1e}, Casimirs "
             f"{d['accuracy']['casimir_drift']:.1e}"]
    if "gali" in d:
        lines.append("  GALI at T: " + ", ".join(f"{k} = {v:.3g}" for k, v in d["gali"]["final"].items())
                     + "; decay rates " + ", ".join(f"{k}: {v['rate']:.3g}/t, power {v['power']:.2f}"
                                                    for k, v in d["gali"]["decay"].items()))
    for k, v in d.get("output", {}).items():
        lines.append(f"  {k}: {v}")
    return "\n".join(lines)
