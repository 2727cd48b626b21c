"""The certificate schema of the proof checker: the format, the kinds, what a result is, how a certificate is read,
and the vocabulary every kind's checks share (exact comparisons of balls, the field's structure).

A certificate is a JSON object with "format" = FORMAT and a "kind" of KINDS (absent: the homoclinic kind); each kind's
fields are read by its module (kernel/homoclinic.py, kernel/fixed_point.py, kernel/horseshoe.py), which rejects a
missing or malformed field as `CertificateError` (not a certificate: exit 2) and a failed check as a result with
ok = False (exit 1).  An optional "provenance" (an object of strings: the command or script and the settings that
produced the certificate) is read by no check; only its form is (`check_form`).
"""
from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

from flint import arb

from ...core.errors import ParameterError
from .. import ball, fields, identities

FORMAT = "magrod-proof-certificate/1"
#: the statement kinds a certificate may carry ("kind"; absent means the homoclinic kind, the first one)
HOMOCLINIC, SECTION_FIXED_POINT, SECTION_HORSESHOE = "homoclinic", "section_fixed_point", "section_horseshoe"
KINDS = (HOMOCLINIC, SECTION_FIXED_POINT, SECTION_HORSESHOE)


class CertificateError(ParameterError):
    """The certificate cannot be read (not JSON, wrong format, a missing or malformed field)."""

    def __init__(self, message: str):
        super().__init__("verify", message)


@dataclass
class VerifyResult:
    ok: bool
    reason: str
    checks: list = field(default_factory=list)
    wall_time_s: float = 0.0
    #: the theorem established (generated from the verified content; "" unless ok)
    theorem: str = ""
    #: per verified target: the certificate's enclosure of dtheta_u/dpsi (exact decimal bounds; empty unless ok)
    slopes: dict = field(default_factory=dict)
    #: other verified enclosures by name (kind section_fixed_point: theta*, tr DP(x0), mu_u), exact decimal bounds
    values: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        """Deprecated spelling of to_dict() (kept for one release; written here, not imported, to keep the
        verifier's trust base to the modules magrod/proof/verify.py lists)."""
        import warnings

        warnings.warn("VerifyResult.as_dict() is deprecated: use to_dict()", DeprecationWarning, stacklevel=2)
        return self.to_dict()

    def to_dict(self) -> dict:
        return {"ok": self.ok, "reason": self.reason, "theorem": self.theorem, "slopes": self.slopes,
                "values": self.values, "checks": self.checks, "wall_time_s": round(self.wall_time_s, 3)}


class Reject(Exception):
    pass


def load(path) -> dict:
    """Read a certificate file (CertificateError if unreadable or not a JSON object of the right format)."""
    try:
        text = Path(path).read_text()
    except (OSError, UnicodeDecodeError) as err:
        raise CertificateError(f"cannot read {str(path)[:200]!r}: {getattr(err, 'strerror', None) or err}") from None
    try:
        cert = json.loads(text)
    except json.JSONDecodeError as err:
        raise CertificateError(f"{str(path)[:200]!r} is not JSON ({err.msg} at line {err.lineno})") from None
    if not isinstance(cert, dict) or cert.get("format") != FORMAT:
        raise CertificateError(f"not a {FORMAT} certificate")
    return cert


def check_form(cert) -> str:
    """The certificate's kind (KINDS), and the form of what no check reads ("provenance"); CertificateError if
    either is not a certificate's."""
    kind = cert.get("kind", HOMOCLINIC) if isinstance(cert, dict) else None
    if kind not in KINDS:
        raise CertificateError(f"unknown certificate kind {str(kind)[:40]!r} (recognised: {', '.join(KINDS)})")
    prov = cert.get("provenance")
    if prov is not None and not (isinstance(prov, dict) and all(isinstance(v, str) for v in prov.values())):
        raise CertificateError("provenance must be an object of strings (what produced the certificate)")
    return kind


def imprecise(checks, t0, err) -> VerifyResult:
    """The rejection of a certificate whose working precision cannot hold a value its checks need exactly (exit 1:
    it is a certificate, and it fails a check)."""
    how = f"every value the checks need exactly is exact at the certificate's working precision (settings prec); {err}"
    checks.append({"name": "working precision", "holds": False, "how": how})
    return VerifyResult(False, f"certificate rejected: working precision failed (the check requires: {how})", checks,
                        time.perf_counter() - t0)


def checked(t0, body):
    """The frame every kind's checks run in: `body(claim)` runs them, `claim(name, holds, how)` records each and stops
    at the first that fails.  Returns (checks, body's value, None), or (checks, None, the failed VerifyResult) for a
    failed check or a working precision too low for one; a malformed certificate raises CertificateError naming
    what is wrong (exit 2)."""
    checks: list = []

    def claim(name, holds, how):
        checks.append({"name": name, "holds": bool(holds), "how": how})
        if not holds:
            raise Reject(f"{name} failed (the check requires: {how})")

    try:
        return checks, body(claim), None
    except ball.InexactBall as err:  # a well-formed certificate whose precision is too low for its checks
        return checks, None, imprecise(checks, t0, err)
    except (KeyError, TypeError, ValueError, IndexError, ZeroDivisionError, AttributeError) as err:
        if isinstance(err, ParameterError):
            raise
        raise CertificateError(f"malformed certificate ({type(err).__name__}: {str(err)[:120]})") from None
    except Reject as err:
        return checks, None, VerifyResult(False, f"certificate rejected: {err}", checks, time.perf_counter() - t0)


def section_settings(cert):
    """(exact parameters, prec, series_cap, order) of a section certificate (fixed point, horseshoe), in range."""
    p = fields.ExactParams(**{k: frac(cert["params"][k]) for k in fields.PARAMS})
    s = cert["settings"]
    prec, cap, order = int(s["prec"]), int(s["series_cap"]), int(s["order"])
    if not (64 <= prec <= 1024 and 4 <= order < cap <= 256):
        raise CertificateError("settings out of range (prec 64..1024 bits, 4 <= order < series_cap <= 256)")
    return p, prec, cap, order


def frac(s) -> Fraction:
    if not isinstance(s, str):
        raise TypeError(f"expected an exact rational string, got {s!r}")
    return Fraction(s)


def inside(inner: arb, outer: arb) -> bool:
    lo, hi = ball.bounds(inner)
    olo, ohi = ball.bounds(outer)
    return olo < lo and hi < ohi


def recomputed(claim, name, value: arb, stored):
    claim(f"{name} recomputed", ball.subset(value, stored),
          f"the recomputed enclosure {value} lies inside the certificate's ball [{stored['mid']} +- {stored['rad']}]")


def recomputed_meet(claim, name, values, stored):
    """recomputed for a quantity enclosed by several formulas: their intersection (exact bounds) lies in the ball."""
    try:
        lo, hi = ball.meet_bounds(values)
    except ValueError:  # disjoint enclosures of one quantity: never for a sound field and integrator
        lo, hi = math.inf, -math.inf
    slo, shi = ball.json_bounds(stored)
    claim(f"{name} recomputed", slo <= lo <= hi <= shi,
          f"the recomputed enclosure [{float(lo):.12g}, {float(hi):.12g}] lies inside the certificate's ball "
          f"[{stored['mid']} +- {stored['rad']}]")


def check_structure(module, claim) -> None:
    """The structure every kind's chain uses, checked at run time on the field the certificate names (its source,
    whose SHA-256 the next check compares): reversibility under R, the Hamiltonian form (det DP = 1), the
    variational field, each an exact rational-function identity (magrod.proof.identities).  Before the digest, so
    that a field without the structure is rejected by the identity it lacks."""
    for name, holds, how in identities.check(fields.source(module), fields.PARAMS):
        claim(name, holds, how)
