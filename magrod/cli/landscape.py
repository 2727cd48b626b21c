"""`magrod landscape`: every line of the paper's sec. 1 re-derived from the rod models, with labelled evidence and
reference keys, and the anisotropic B1:B2:C scan (magrod.integrability.landscape).  Imports neither heyoka nor
matplotlib at module level."""
from __future__ import annotations


def add_arguments(p):
    p.add_argument("--degree", type=str, default="4", help="degree D of the exact searches (1 <= D <= 12)")
    p.add_argument("--quick", action="store_true", help="a smaller scan grid {1/2, 1, 2, 4} and t = 500 (seconds)")
    p.add_argument("--no-scan", action="store_true", help="skip the anisotropic B1:B2:C scan")
    p.add_argument("--no-splitting", action="store_true",
                   help="skip the homoclinic splitting of the anisotropic and curved rods")
    p.add_argument("--t-max", type=str, default=None, help="length of the Lyapunov runs (default 2000, quick 500)")
    p.add_argument("--seed", type=str, default="20", help="seed of the rational parameters and the starts")


def run(args) -> dict:
    from ..integrability import MAX_DEGREE
    from ..integrability import rod_landscape as landscape
    from . import options

    degree = options.integer("degree", args.degree, 1, MAX_DEGREE)
    seed = options.integer("seed", args.seed, 0, 2**62)
    t_max = None if args.t_max is None else options.number("t_max", args.t_max)
    d = landscape(degree, quick=args.quick, scan=not args.no_scan, t_max=t_max, seed=seed,
                  splitting=not args.no_splitting).to_dict()
    d["ok"] = True
    return d


def format_text(out: dict) -> str:
    from ..integrability import format_landscape as fmt

    return fmt(out)
