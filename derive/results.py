"""A named result of the derivation: the paper label it belongs to, a status, and how it was shown."""
from __future__ import annotations

import random
from dataclasses import dataclass, field

import mpmath
import sympy as sp

HOLDS = "holds"
DISAGREES = "disagrees"
CONDITIONAL = "holds under stated assumptions"


@dataclass
class Result:
    key: str  # stable identifier, e.g. "casimirs"
    label: str  # paper label(s), e.g. "eq:magnetic_casimirs1-3"
    title: str
    status: str  # HOLDS / DISAGREES / CONDITIONAL
    method: str  # "symbolic: ..." or "numeric: N points, 50 digits, max residual ..."
    details: dict = field(default_factory=dict)  # JSON-able strings / numbers / lists

    def as_dict(self):
        return {"key": self.key, "label": self.label, "title": self.title, "status": self.status,
                "method": self.method, "details": self.details}


def is_zero(expr, trig=False) -> bool:
    """Symbolic zero test: expand (optionally with trig simplification)."""
    e = sp.expand(expr)
    if e == 0:
        return True
    e = sp.simplify(sp.together(e))
    if e == 0:
        return True
    if trig:
        return sp.simplify(sp.trigsimp(sp.expand_trig(e))) == 0
    return False


def numeric_max_residual(expr, ranges: dict, n: int = 200, seed: int = 2026, dps: int = 50) -> float:
    """max |expr| at n seeded random points (uniform in the given ranges), evaluated with mpmath at `dps`
    digits.  Returns the max residual as a float (report it: "numeric, n points, max residual ...")."""
    rng = random.Random(seed)
    syms = list(ranges)
    f = sp.lambdify(syms, expr, modules="mpmath")
    worst = mpmath.mpf(0)
    with mpmath.workdps(dps):
        for _ in range(n):
            vals = [mpmath.mpf(lo) + (mpmath.mpf(hi) - mpmath.mpf(lo)) * mpmath.mpf(rng.random())
                    for lo, hi in (ranges[s] for s in syms)]
            r = abs(f(*vals))
            if r > worst:
                worst = r
    return float(worst)


def fmt(expr) -> str:
    """Stable string form of a SymPy expression for the report."""
    return sp.sstr(expr, order="lex")
