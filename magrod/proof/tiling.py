"""A lambdabar interval covered by a chain of certificates, each for its own lambdabar box.

A certificate with lam_rad = w > 0 states its theorem for every lambdabar in [lam - w, lam + w] (the parameters and the
level otherwise fixed).  A chain of such certificates states it on the union of their boxes, and that union is an
interval only if the boxes, sorted, leave no gap: `chain_interval` decides this exactly (rational arithmetic) and
returns the interval, or raises ChainError naming the first gap.  It checks only what the chain adds -- one kind, one
statement apart from lambdabar (same m, mu, gamma, delta, level, branch), every box non-degenerate, no gap; each
certificate's own theorem is the verifier's business (`verify.verify` on every member: `chain_interval(certs,
verify=True)`).
"""
from __future__ import annotations

from fractions import Fraction

from ..core.errors import ParameterError


class ChainError(ParameterError):
    """The certificates do not cover one lambdabar interval (another statement, a degenerate box, a gap)."""

    def __init__(self, message: str):
        super().__init__("chain", message)


def _box(c: dict) -> tuple[Fraction, Fraction]:
    w = Fraction(c["settings"].get("lam_rad", "0"))
    lam = Fraction(c["params"]["lam"])
    if w <= 0:
        raise ChainError(f"a member is a point certificate (lam_rad = {w}), not a lambdabar box")
    return lam - w, lam + w


def _statement(c: dict) -> tuple:
    """What must agree across the chain: the kind, the parameters other than lambdabar, the level and the branch."""
    return (c.get("kind"), tuple(sorted((k, Fraction(v)) for k, v in c["params"].items() if k != "lam")),
            Fraction(c["level"]) if "level" in c else None, c.get("point", {}).get("branch", "0"))


def chain_interval(certs, *, verify: bool = False) -> tuple[Fraction, Fraction]:
    """The exact lambdabar interval [lo, hi] on which a chain of interval certificates states one theorem.

    Parameters
    ----------
    certs : iterable of dict
        The certificates (any order).
    verify : bool
        Also re-check every member with the complete verifier (verify.verify); the first that fails raises.

    Returns
    -------
    (Fraction, Fraction)
        The union of the members' boxes, which is an interval.

    Raises
    ------
    ChainError
        No member, members of different statements, a point certificate, or a gap between sorted boxes (named).
    """
    certs = list(certs)
    if not certs:
        raise ChainError("no certificate")
    keys = {_statement(c) for c in certs}
    if len(keys) != 1:
        raise ChainError(f"the members state different theorems apart from lambdabar ({len(keys)} kinds/parameters)")
    boxes = sorted(_box(c) for c in certs)
    hi = boxes[0][1]
    for a, b in boxes[1:]:
        if a > hi:
            raise ChainError(f"gap in lambdabar between {hi} and {a}: no member covers it")
        hi = max(hi, b)
    if verify:
        from . import verify as _verify

        for c in certs:
            res = _verify.verify(c)
            if not res.ok:
                raise ChainError(f"a member (lambdabar {c['params']['lam']}) fails: {res.reason[:200]}")
    return boxes[0][0], hi
