"""`magrod models`: the registered rod models with their parameters (meaning, admissible range,
default), state, Casimirs found, candidates and whether the Euler-angle chart applies; `--model ./my_rod.py`
checks and lists a model file instead (it is compiled into the cache, never into the package).  Imports neither
heyoka nor matplotlib.

Also the parser of `--model-params NAME=VALUE,...` and `--level NAME=VALUE,...` used by `check --model` and
`landscape`: values are exact rationals (integers, decimals or p/q), names are checked against the model."""
from __future__ import annotations

import re

from ..core.errors import ParameterError

_ITEM = re.compile(r"^\s*([A-Za-z_][A-Za-z_0-9]*)\s*=\s*([-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d{1,3})?"
                   r"(?:\s*/\s*\d+)?)\s*$")


def parse_assignments(option: str, text, allowed) -> dict:
    """{name: Fraction} from 'NAME=VALUE,...' (VALUE an integer, a decimal or p/q); ParameterError naming the
    option for anything else (user input is data: no eval)."""
    from fractions import Fraction

    if text is None:
        return {}
    if not isinstance(text, str) or not text.strip() or len(text) > 1000:
        raise ParameterError(option, "must be NAME=VALUE[,NAME=VALUE...] (at most 1000 characters)")
    out = {}
    for item in text.split(","):
        m = _ITEM.match(item)
        if not m:
            raise ParameterError(option, f"cannot read {item.strip()[:40]!r}: expected NAME=VALUE with VALUE an "
                                         "integer, a decimal (1e-8) or p/q")
        name, val = m.group(1), m.group(2).replace(" ", "")
        if name not in allowed:
            raise ParameterError(option, f"{name!r} is not one of {', '.join(allowed)}")
        if name in out:
            raise ParameterError(option, f"{name} is given twice")
        try:
            out[name] = Fraction(val)
        except ZeroDivisionError:
            raise ParameterError(option, f"{name} = {val}: division by zero") from None
        except ValueError:  # e.g. 1e-8/3: an exponent and a quotient together
            raise ParameterError(option, f"cannot read {name} = {val}: give a decimal or p/q") from None
    return out


def add_arguments(p):
    p.add_argument("--model", default=None, metavar="NAME|FILE.py",
                   help="list only this model; a path ./my_rod.py is a model file (code you run on purpose: it is "
                        "executed, checked and compiled into the cache keyed by its content hash)")


def describe(mc) -> dict:
    n = mc.names
    return {"name": mc.name, "title": n.TITLE, "source": n.SOURCE, "origin": mc.origin, "state": list(n.STATE),
            "parameters": [{"name": k, "meaning": m, "range": [str(r[0]), str(r[1])], "default": d}
                           for k, m, r, d in zip(n.PARAMS, n.MEANINGS, n.RANGES, n.DEFAULTS)],
            "casimirs": {k: v for k, v in _casimirs(mc).items()}, "candidates": list(n.CANDIDATES),
            "s1_symmetric": n.S1_SYMMETRIC,
            "euler_chart": ("generated (the paper's reduced system)" if mc.name == "magnetic-extensible" else
                            "applicable, not generated" if n.S1_SYMMETRIC else "not applicable (no S^1 symmetry)")}


def _casimirs(mc) -> dict:
    for r in mc.report["results"]:
        if r["key"] == "casimirs":
            return dict(r["details"]["basis_found"])
    return {}


def run(args) -> dict:
    from ..core.models import registered, resolve

    names = [args.model] if args.model is not None else list(registered())
    return {"ok": True, "default": "magnetic-extensible", "models": [describe(resolve(n)) for n in names]}


def format_text(out: dict) -> str:
    lines = []
    for m in out["models"]:
        star = " (default)" if m["name"] == out["default"] else ""
        lines.append(f"{m['name']}{star}: {m['title']}  [{m['source']}]")
        lines.append(f"    state ({len(m['state'])}): {', '.join(m['state'])}")
        for p in m["parameters"]:
            lines.append(f"    --  {p['name']:<6} {p['meaning']}; range ({p['range'][0]}, {p['range'][1]}), "
                         f"default {p['default']:g}")
        lines.append("    Casimirs found: " + "; ".join(f"{k} = {v}" for k, v in m["casimirs"].items()))
        lines.append(f"    candidates: {', '.join(m['candidates']) or '-'}; Euler chart: {m['euler_chart']}")
        lines.append("")
    return "\n".join(lines).rstrip()
