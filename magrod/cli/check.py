"""`magrod check`: the integrability report (magrod.integrability.report), from generated/report.json, re-derived
(--rederive) or for a modified model (--subs).  Imports neither heyoka nor matplotlib."""
from __future__ import annotations


def add_arguments(p):
    p.add_argument("--rederive", action="store_true",
                   help="re-run the SymPy derivation instead of reading generated/report.json (slower)")
    p.add_argument("--all", action="store_true", help="include every derived result, not only the integrability ones")
    p.add_argument("--subs", metavar="NAME=VALUE,...",
                   help="compute the involution table of H, I1, I2 and the Casimirs live for a modified model, e.g. "
                        "'B2=B1,c_J=c_H,lambda=0' (symbols: B1 B2 C c_H c_J c_K lambda; c = 1/stiffness, so "
                        "c_H=0,c_J=0,c_K=0 is the inextensible, unshearable rod); needs sympy")


def run(args) -> dict:
    from ..integrability.report import custom_involution, summary

    from ..core.errors import ParameterError

    if args.subs is not None:
        if args.rederive or args.all:
            raise ParameterError("subs", "computes one custom table: do not combine it with --rederive or --all")
        return custom_involution(args.subs)
    return summary(args.rederive, args.all)


def format_text(out: dict) -> str:
    from ..integrability.report import format_text as fmt

    return fmt(out)
