"""`magrod saddle`: the saddle of the rod at given parameters (`mr.saddle`): the straight rod when mu = 2 lambdabar,
the helical periodic saddle (a relative equilibrium) when mu > 2 lambdabar; its energy level Hbar, its eigenvalues or
Floquet multipliers and their checks.  The rod is a paper panel's (--panel, default 4a) with any parameter overridden.

This module is the worked example of docs/architecture.md, "Adding a subcommand": it parses, calls one public
function and prints the result's to_dict().

Example:  magrod saddle --panel 4a --json"""
from __future__ import annotations

from .options import add_model, add_panel, add_params, add_precision, system_from


def add_arguments(p):
    add_panel(p, help="the paper panel whose rod is used (default 4a; parameters given below override its own)")
    add_params(p, help_suffix=" (overrides the panel's)")
    add_precision(p)
    add_model(p, help="the rod model: a registered name (`magrod models`) or a model file, whose saddle (the "
                      "straight twisted rod or the relative equilibrium next to it) is found (default: the paper's "
                      "rod)")


def run(args) -> dict:
    import magrod as mr

    system, _ = system_from(args, default_panel="4a")
    system = system.replace(precision=args.precision)
    if not system.is_paper:
        s = mr.saddle(system)
        d = s.to_dict()
        return {"ok": bool(s.success), "model": system.model, "kind": s.kind, "params": system.params,
                "H": float(s.H), "unstable_eigenvalue": d.get("unstable_eigenvalue"),
                "eigenvalues": d.get("eigenvalues"), "accuracy": s.accuracy, "message": s.message}
    s = mr.saddle(system)
    return {"ok": bool(s.success), "kind": s.kind, **s.to_dict(), "accuracy": s.accuracy}


def format_text(d: dict) -> str:
    p = ", ".join(f"{k} = {v:g}" for k, v in d["params"].items())
    if d.get("model"):
        re_, im = d["unstable_eigenvalue"] or (float("nan"), float("nan"))
        return "\n".join([f"{d['kind']} of the model {d['model']} at {p}", f"  H = {d['H']:.12g}",
                          f"  unstable eigenvalue {re_:.10g} {im:+.10g}i",
                          "  checks: " + ", ".join(f"{k} {v:.1e}" if isinstance(v, float) else f"{k} {v}"
                                                   for k, v in d["accuracy"].items())])
    head = f"{'straight rod (equilibrium)' if d['kind'] == 'equilibrium' else 'helical periodic saddle'} at {p}"
    lines = [head, f"  Hbar = {d['H']:.12g}"]
    if d["kind"] == "equilibrium":
        re_, im = d["unstable_eigenvalue"]
        lines.append(f"  unstable eigenvalue {re_:.10g} {im:+.10g}i")
    else:
        re_, im = d["unstable_multiplier"]
        lines.append(f"  period T = {d['T']:.10g}, unstable multiplier {re_:.6g} {im:+.6g}i, hyperbolic: "
                     f"{d['hyperbolic']}")
    lines.append("  checks: " + ", ".join(f"{k} {v:.1e}" if isinstance(v, float) else f"{k} {v}"
                                          for k, v in d["accuracy"].items()))
    return "\n".join(lines)
