"""Independent checker of a proof certificate (`magrod prove --verify CERT`).

It re-runs every rigorous step from the certificate's stored inputs and accepts only if (a) every recomputed
enclosure lies inside the certificate's ball for it and (b) every claimed inequality holds for the certificate's
balls.  Separate code from the prover: it imports neither magrod.proof.search nor the prover's saddle / manifold
modules; the Krawczyk tests, the cone conditions, the lift of the boundary arc, the phase derivatives and the
interval Newton step are implemented again here.  Shared with the prover are only (the trust base; a test fences
it, docs/nonintegrability.md, "The verifier's trust base"):
  - the generated field (generated/validated.py, whose SHA-256 must match the certificate), through
    magrod.proof.fields, which also builds from it the chart field with lambdabar as a fifth state variable
    (lambdabar' = 0; fields.lam_state_field) for the certificates on a lambdabar interval;
  - the ball helpers (magrod.proof.ball);
  - the validated integrator (magrod.proof.taylor), which the verifier drives with the certificate's exact step
    sizes;
  - the validated first return to the section sin psi = 0 (magrod.proof.section_return), for the section
    certificates (fixed point and horseshoe);
  - the field's structure (magrod.proof.identities): reversibility under R, the Hamiltonian form (det DP = 1) and
    chart_jacobian = Df, checked at run time as exact rational-function identities on the field's source before its
    digest, in every kind (_check_structure);
  - the theorem's wording (magrod.proof.theorem), and core.errors for the error type.

Completeness: a certificate is accepted only if what it contains establishes the theorem the verifier prints.  The
targets must be recognised ("0" or "pi", nothing else), distinct, exactly the settings' targets, one crossing each;
the settings must be those the stored data were made with (saddle radius, circle radius, crossing step); and the
certificate's "theorem" text must be the one generated here from the verified parameters and targets (a text that
claims more, or other, than the checks is rejected).  The printed theorem is that generated text, never the
certificate's.

Provenance: a certificate may carry "provenance", an object of strings naming the command or script and the settings
that produced it (`magrod prove` writes it; the shipped certificates' were reconstructed when it was introduced).  No
check reads it and the theorem does not depend on it; only its form is checked (not an object of strings: exit 2).

Failure modes: `CertificateError` (unreadable, wrong format, missing or malformed fields: not a certificate, exit 2)
and a result with ok = False and a one-line reason naming the check that failed and what it requires (a
certificate that fails a check, a working precision too low for its checks included: exit 1).
"""
from __future__ import annotations

import dataclasses
import json
import time
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

import numpy as np
from flint import acb, acb_mat, arb, arb_mat

from ..core.errors import ParameterError
from . import ball, fields, identities, taylor
from .theorem import TARGETS, homoclinic_theorem, section_fixed_point_theorem, section_horseshoe_theorem

FORMAT = "magrod-proof-certificate/1"
#: the statement kinds a certificate may carry ("kind"; absent means the homoclinic kind of issue 21)
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
        verifier's trust base to the modules the docstring lists)."""
        import warnings

        warnings.warn("VerifyResult.as_dict() is deprecated: use to_dict()", DeprecationWarning, stacklevel=2)
        return self.to_dict()

    def to_dict(self) -> dict:
        return {"ok": self.ok, "reason": self.reason, "theorem": self.theorem, "slopes": self.slopes,
                "values": self.values, "checks": self.checks, "wall_time_s": round(self.wall_time_s, 3)}


class _Reject(Exception):
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


def verify(cert: dict, *, module=fields.gen, workers: int | None = None) -> VerifyResult:
    """Re-check a proof certificate with code separate from the prover.

    Parameters
    ----------
    cert : dict
        The certificate (`load(path)` or the prover's dict).
    module : module, optional
        The generated field module; its SHA-256 must equal the certificate's and the installed one's.
    workers : int, optional
        Kind "section_horseshoe" only: the sets are re-flown in this many spawned processes (default: the CPUs this
        process may use; 1: in this process).  The checks, their order and the result are the same for every
        value (each set's checks are replayed in the serial order; Arb is deterministic).

    Returns
    -------
    VerifyResult
        ok, reason (one line: "certificate verified ..." or "certificate rejected: <check>: <why>"), checks.

    Raises
    ------
    CertificateError
        (a ParameterError naming "verify") if a field is missing or malformed.

    Examples
    --------
    >>> from magrod.proof import verify
    >>> res = verify.verify(verify.load("out/certificate.json"))  # doctest: +SKIP
    >>> res.ok  # doctest: +SKIP
    True

    Notes
    -----
    Recomputes the saddle's Krawczyk image, the eigenpairs, the cone conditions, both flights with the stored
    exact steps, the section crossings, the Newton step and dtheta_u/dpsi; every recomputed enclosure must lie in
    the certificate's ball and every claim must hold on the certificate's balls.  Cost: about the prover's
    rigorous part (~30-40 s at the target).
    """
    t0 = time.perf_counter()
    checks: list = []

    def claim(name, holds, how):
        checks.append({"name": name, "holds": bool(holds), "how": how})
        if not holds:
            raise _Reject(f"{name} failed (the check requires: {how})")

    kind = cert.get("kind", HOMOCLINIC) if isinstance(cert, dict) else None
    if kind not in KINDS:
        raise CertificateError(f"unknown certificate kind {str(kind)[:40]!r} (recognised: {', '.join(KINDS)})")
    prov = cert.get("provenance")
    if prov is not None and not (isinstance(prov, dict) and all(isinstance(v, str) for v in prov.values())):
        raise CertificateError("provenance must be an object of strings (what produced the certificate)")
    if kind == SECTION_FIXED_POINT:
        return _verify_fixed_point(cert, module, t0)
    if kind == SECTION_HORSESHOE:
        return _verify_horseshoe(cert, module, t0, workers)
    try:
        p, st = _inputs(cert)
        with ball.workprec(st["prec"], st["series_cap"]):
            targets = _verify(cert, p, st, module, claim)
    except ball.InexactBall as err:  # a well-formed certificate whose precision is too low for its checks
        return _imprecise(checks, t0, err)
    except (KeyError, TypeError, ValueError, IndexError, ZeroDivisionError, AttributeError) as err:
        if isinstance(err, ParameterError):
            raise
        raise CertificateError(f"malformed certificate ({type(err).__name__}: {str(err)[:120]})") from None
    except _Reject as err:
        return VerifyResult(False, f"certificate rejected: {err}", checks, time.perf_counter() - t0)
    slopes = {c["target"]: [ball.decimal(b) for b in ball.json_bounds(c["dtheta_dpsi"])] for c in cert["crossings"]}
    return VerifyResult(True, "certificate verified: every enclosure recomputed and every check holds", checks,
                        time.perf_counter() - t0, homoclinic_theorem(p.as_json(), targets, _lam_rad_text(p)), slopes)


def _imprecise(checks, t0, err) -> VerifyResult:
    """The rejection of a certificate whose working precision cannot hold a value its checks need exactly (exit 1:
    it is a certificate, and it fails a check)."""
    how = f"every value the checks need exactly is exact at the certificate's working precision (settings prec); {err}"
    checks.append({"name": "working precision", "holds": False, "how": how})
    return VerifyResult(False, f"certificate rejected: working precision failed (the check requires: {how})", checks,
                        time.perf_counter() - t0)


def _lam_rad_text(p) -> str:
    w = Fraction(getattr(p, "lam_rad", 0))
    return f"{w.numerator}/{w.denominator}"


def _frac(s) -> Fraction:
    if not isinstance(s, str):
        raise TypeError(f"expected an exact rational string, got {s!r}")
    return Fraction(s)


def _inputs(cert):
    """The parameters (lambdabar an interval when the settings carry lam_rad > 0: fields.IntervalParams, so that
    every recomputed enclosure holds for every lambdabar of it) and the numerical settings."""
    p = fields.ExactParams(**{k: _frac(cert["params"][k]) for k in fields.PARAMS})
    s = cert["settings"]
    w = _frac(s.get("lam_rad", "0"))  # absent: a certificate at the point (issue 21's)
    if w < 0:
        raise CertificateError("settings: lam_rad must be >= 0")
    if w:
        p = fields.IntervalParams(p.m, p.mu, p.gamma, p.delta, p.lam, lam_rad=w)
    st = {"prec": int(s["prec"]), "order": int(s["order"]), "series_cap": int(s["series_cap"]),
          "radius": _frac(cert["saddle"]["radius"]), "eig_rad": _frac(s["eig_rad"])}
    if not (64 <= st["prec"] <= 1024 and 4 <= st["order"] < st["series_cap"] <= 256):
        raise CertificateError("settings out of range (prec 64..1024 bits, 4 <= order < series_cap <= 256)")
    return p, st


def _inside(inner: arb, outer: arb) -> bool:
    lo, hi = ball.bounds(inner)
    olo, ohi = ball.bounds(outer)
    return olo < lo and hi < ohi


def _recomputed(claim, name, value: arb, stored):
    claim(f"{name} recomputed", ball.subset(value, stored),
          f"the recomputed enclosure {value} lies inside the certificate's ball [{stored['mid']} +- {stored['rad']}]")


def _stored_claims(cert, claim):
    """The theorem's inequalities on the certificate's own balls (cheap; the recomputation follows)."""
    for c in cert["crossings"]:
        tgt = c["target"]
        a = {k: ball.from_json(v) for k, v in c["arc"]["enclosures"].items()}
        phic, dphi = _frac(c["phi_c"]), _frac(c["dphi"])
        branch = {"0": ball.positive, "pi": ball.negative}[tgt]  # targets were checked recognised
        claim(f"psi={tgt} claims", ball.excludes_zero(a["gdot"]) and ball.excludes_zero(a["dGs"])
              and branch(a["Gc"])
              and _inside(ball.from_json(c["newton"]), ball.interval(phic - dphi, phic + dphi))
              and ball.excludes_zero(ball.from_json(c["dtheta_dpsi"])),
              "the certificate's balls satisfy the claims (section transversal, branch, dGs != 0, Newton inside "
              "the arc, dtheta_u/dpsi excludes 0)")


def _check_statement(cert, p, st, claim) -> list:
    """What the certificate must contain to establish a theorem, and which theorem: returns the targets.

    Cheap, and first: a certificate with a missing, repeated or unknown target, or whose theorem text is not the
    one its content establishes, is rejected before any enclosure is recomputed."""
    targets = cert["settings"]["targets"]
    crossings = cert["crossings"]
    claim("targets recognised", isinstance(targets, list) and all(isinstance(t, str) and t in TARGETS for t in targets),
          f"every target of the settings is one of {sorted(TARGETS)} (psi = 0 or psi = pi on Fix(R)); got "
          f"{str(targets)[:80]}")
    claim("targets distinct", len(targets) > 0 and len(set(targets)) == len(targets),
          f"the settings name at least one target and none twice; got {targets}")
    got = [c["target"] if isinstance(c, dict) else None for c in crossings] if isinstance(crossings, list) else None
    claim("crossings recognised", got is not None and all(isinstance(t, str) and t in TARGETS for t in got),
          f"every crossing's target is one of {sorted(TARGETS)}; got {str(got)[:80]}")
    claim("one crossing per target", len(got) == len(set(got)) and sorted(got) == sorted(targets),
          f"the crossings' targets {got} are exactly the settings' targets {targets}, each once")
    s = cert["settings"]
    claim("settings match the data",
          _frac(cert["saddle"]["radius"]) == _frac(s["saddle_radius"]) and _frac(cert["manifold"]["r"]) == _frac(s["r"])
          and all(_frac(c["h_cross"]) == 2 * _frac(s["lead"]) for c in crossings)
          and all(_frac(c["dphi"]) >= _frac(s["dphi"]) for c in crossings),
          "the saddle box radius, the circle radius, the crossing step (2 lead) and the phase arcs (>= dphi) are "
          "the recorded settings")
    want = homoclinic_theorem(p.as_json(), targets, _lam_rad_text(p))
    stated = cert["theorem"]
    claim("theorem text", isinstance(stated, str) and stated == want,
          "the certificate's theorem is the one its verified content establishes"
          + ("" if stated == want else f" (expected: {want[:160]}...; the certificate states: {str(stated)[:160]}...)"))
    return targets


def _verify(cert, p, st, module, claim):
    targets = _check_statement(cert, p, st, claim)
    _stored_claims(cert, claim)
    _check_structure(module, claim)
    claim("field digest", cert["field_digest"] == fields.source_digest(module) == fields.source_digest(fields.gen),
          "the certificate's vector field is the installed derive-generated one (SHA-256 of generated/validated.py)")
    lam_hi = p.lam + getattr(p, "lam_rad", 0)
    claim("parameters", p.mu > 2 * lam_hi and p.m > 0 and p.m ** 2 < 4 * (1 + p.gamma) and min(p.gamma, p.delta) >= 0,
          "mu > 2 lambdabar (on the whole lambdabar interval), 0 < m < m_c = 2 sqrt(1 + gamma), gamma, delta >= 0")
    fld = fields.chart_field(p, module)
    xhat, K = _check_saddle(cert, p, st, fld, claim)
    _check_eigen(cert, fld, K, st, claim)
    V, rho_eff, L, r = _check_manifold(cert, fld, xhat, K, claim)
    fb = fields.body_field(p, module)
    order = st["order"]
    for c in cert["crossings"]:
        _check_crossing(c, p, fb, xhat, V, rho_eff, L, r, order, module, claim)
    return targets


def _check_structure(module, claim) -> None:
    """The structure every kind's chain uses, checked at run time on the field the certificate names (its source,
    whose SHA-256 the next check compares): reversibility under R, the Hamiltonian form (det DP = 1), the
    variational field, each an exact rational-function identity (magrod.proof.identities).  Before the digest, so
    that a field without the structure is rejected by the identity it lacks."""
    for name, holds, how in identities.check(fields.source(module), fields.PARAMS):
        claim(name, holds, how)


# --------------------------------------------------------------------------------------------------------------
def _check_saddle(cert, p, st, fld, claim):
    xhat = [ball.q(_frac(v)) for v in cert["saddle"]["xhat"]]
    n = fld.n
    rad = st["radius"]
    sym = (fields.PSI, fields.PTHETA)
    claim("saddle box R-symmetric", all(ball.fraction(xhat[i]) == 0 for i in sym),
          "the box centre has psi = pbar_theta = 0, so R(box) = box and the unique zero lies on Fix(R)")
    X = [ball.interval(ball.fraction(v) - rad, ball.fraction(v) + rad) for v in xhat]
    # Krawczyk: K = xhat - C F(xhat) + (I - C DF(X)) (X - xhat), any C
    Cf = np.linalg.inv(ball.to_floats(fld.df(xhat).mid()))
    C = arb_mat(n, n, [ball.dyadic(v) for v in Cf.flatten()])
    I = arb_mat(n, n, [arb(int(i == j)) for i in range(n) for j in range(n)])
    Kv = ball.vec(xhat) - C * ball.vec(fld.f(xhat)) + (I - C * fld.df(X)) * ball.vec([a - b for a, b in zip(X, xhat)])
    K = ball.column(Kv)
    claim("saddle Krawczyk", all(_inside(k, x) for k, x in zip(K, X)),
          "K(X) lies in the interior of the box X: exactly one zero of the chart field in X")
    for i, (k, s) in enumerate(zip(K, cert["saddle"]["K"])):
        _recomputed(claim, f"saddle K[{i}]", k, s)
    return xhat, K


def _check_eigen(cert, fld, K, st, claim):
    A = acb_mat(fld.df(K))
    n = fld.n
    for key, want in (("u", (1, 1)), ("s", (-1, 1))):
        inp = cert["saddle"][f"eig_input_{key}"]
        lam0 = complex(float(_frac(inp["lam"][0])), float(_frac(inp["lam"][1])))
        k = int(inp["k"])
        v0 = [complex(float(_frac(a)), float(_frac(b))) for a, b in inp["v"]]
        zc = [acb(ball.q(_frac(inp["lam"][0])), ball.q(_frac(inp["lam"][1])))] + \
             [acb(ball.q(_frac(a)), ball.q(_frac(b))) for j, (a, b) in enumerate(inp["v"]) if j != k]
        rad = st["eig_rad"]
        Z = [acb(ball.interval(ball.fraction(z.real.mid()) - rad, ball.fraction(z.real.mid()) + rad),
                 ball.interval(ball.fraction(z.imag.mid()) - rad, ball.fraction(z.imag.mid()) + rad)) for z in zc]
        G, DG = _eigen_system(A, n, k)
        D0 = DG(zc)
        Cf = np.linalg.inv(np.array([[complex(float(D0[i, j].real.mid()), float(D0[i, j].imag.mid()))
                                      for j in range(n)] for i in range(n)]))
        C = acb_mat(n, n, [acb(ball.dyadic(c.real), ball.dyadic(c.imag)) for c in Cf.flatten()])
        I = acb_mat(n, n, [acb(int(i == j)) for i in range(n) for j in range(n)])
        Kz = acb_mat(n, 1, zc) - C * acb_mat(n, 1, G(zc)) + (I - C * DG(Z)) * acb_mat(n, 1, [a - b for a, b in zip(Z, zc)])
        Kl = [Kz[i, 0] for i in range(n)]
        claim(f"eigenpair {key} Krawczyk", all(_inside(a.real, b.real) and _inside(a.imag, b.imag) for a, b in zip(Kl, Z)),
              f"Krawczyk image inside the box around (lambda_{key}, v_{key}), v_k = 1, k = {k}")
        lam = Kl[0]
        ok = (ball.positive(lam.real) if want[0] > 0 else ball.negative(lam.real)) and ball.positive(lam.imag)
        claim(f"eigenvalue {key}", ok, f"lambda_{key} = {lam}: Re {'>' if want[0] > 0 else '<'} 0, Im > 0")
        stored = cert["saddle"][f"lam_{key}"]
        _recomputed(claim, f"lambda_{key} (re)", lam.real, stored["re"])
        _recomputed(claim, f"lambda_{key} (im)", lam.imag, stored["im"])
        del lam0, v0


def _eigen_system(A, n, k):
    """G(lam, v) = (A - lam I) v with v_k = 1 (unknowns: lam and the other n - 1 entries of v), and DG."""
    idx = [j for j in range(n) if j != k]

    def full(z):
        v = list(z[1:])
        v.insert(k, acb(1))
        return z[0], v

    def G(z):
        lam, v = full(z)
        return [sum((A[i, j] * v[j] for j in range(n)), acb(0)) - lam * v[i] for i in range(n)]

    def DG(z):
        lam, v = full(z)
        M = acb_mat(n, n)
        for i in range(n):
            M[i, 0] = -v[i]
            for c, j in enumerate(idx, start=1):
                M[i, c] = A[i, j] - (lam if i == j else 0)
        return M

    return G, DG


def _abs_up(x) -> arb:
    return ball.q(max(abs(v) for v in ball.bounds(x)))


def _norm2(entries) -> Fraction:
    return ball.bounds(sum((_abs_up(e) * _abs_up(e) for e in entries), arb(0)).sqrt())[1]


def _sym2(M):
    a, d = M[0][0], M[1][1]
    b = (M[0][1] + M[1][0]) / 2
    mean = (a + d) / 2
    rad = (_abs_up((a - d) / 2) * _abs_up((a - d) / 2) + _abs_up(b) * _abs_up(b)).sqrt()
    return ball.bounds(mean - rad)[0], ball.bounds(mean + rad)[1]


def _check_manifold(cert, fld, xhat, K, claim):
    m = cert["manifold"]
    n = fld.n
    V = arb_mat(n, n, [ball.q(_frac(v)) for row in m["V"] for v in row])
    rb, rho, L, r = (_frac(m[k]) for k in ("r_block", "rho", "L", "r"))
    Vi = V.inv()
    ybox = [ball.interval(-rb, rb)] * 2 + [ball.interval(-rho, rho)] * 2
    G = Vi * fld.df(ball.column(ball.vec(xhat) + V * ball.vec(ybox))) * V
    blk = {(a, b): [[G[i, j] for j in b] for i in a] for a in ((0, 1), (2, 3)) for b in ((0, 1), (2, 3))}
    u, s = (0, 1), (2, 3)
    m_u = _sym2(blk[u, u])[0]
    M_s = _sym2(blk[s, s])[1]
    c_us = _norm2([e for row in blk[u, s] for e in row])
    c_su = _norm2([e for row in blk[s, u] for e in row])
    N_uu = _norm2([e for row in blk[u, u] for e in row])
    N_ss = _norm2([e for row in blk[s, s] for e in row])
    y = ball.column(Vi * ball.vec([a - b for a, b in zip(K, xhat)]))
    U, S = _norm2(y[:2]), _norm2(y[2:])
    claim("manifold outflow", m_u * rb > N_uu * U + c_us * (rho + S), "u . u' > 0 on |u| = r_block")
    claim("manifold inflow", -M_s * rho > c_su * (rb + U) + N_ss * S, "s . s' < 0 on |s| = rho")
    claim("manifold cone", L * (m_u - M_s) > c_su + L * L * c_us, "the cone |ds| <= L |du| is forward invariant")
    claim("manifold growth", M_s + c_su / L < 0 and m_u - c_us * L > 0,
          "outside the cone |ds| grows backwards, inside |du| shrinks backwards")
    claim("manifold saddle inside", U < rb and S < rho and 0 < r < rb, "the saddle and the circle lie inside the block")
    rho_eff = min(rho, S + L * (r + U))
    claim("manifold rho_eff", _frac(m["rho_eff"]) >= rho_eff,
          "the certificate's C^0 bound of the boundary circle is at least the recomputed min(rho, S + L (r + U))")
    return V, _frac(m["rho_eff"]), L, r


def _lift(p, V, xhat, rho_eff, L, r, lo, hi, module):
    Phi = ball.interval(lo, hi)
    rq = ball.q(r)
    ybox = [rq * Phi.cos(), rq * Phi.sin(), ball.interval(-rho_eff, rho_eff), ball.interval(-rho_eff, rho_eff)]
    lr = L * r
    dy = [-rq * Phi.sin(), rq * Phi.cos(), ball.interval(-lr, lr), ball.interval(-lr, lr)]
    yc = [y.mid() for y in ybox]
    Q = ball.column(ball.vec(xhat) + V * ball.vec(ybox))
    qc = ball.column(ball.vec(xhat) + V * ball.vec(yc))
    JV = fields.lift_jacobian(p, Q, module) * V
    C0 = JV.mid()
    dyb = ball.vec([y - c for y, c in zip(ybox, yc)])
    err = ball.column((JV - C0) * dyb)
    S = taylor.initial_set([a + e for a, e in zip(fields.lift(p, qc, module), err)], c1=True)
    S.C, S.r0 = C0, dyb
    return S, JV * ball.vec(dy)


def _check_crossing(c, p, fb, xhat, V, rho_eff, L, r, order, module, claim):
    tgt = c["target"]
    phic, dphi, t_a, h = (_frac(c[k]) for k in ("phi_c", "dphi", "t_a", "h_cross"))
    e33 = fields.E33

    def g(x):
        return fields.body_events(p, x, module)["g"]

    def dg(x):
        return fields.body_event_gradient(p, x, "g", module)

    def guard(Y):
        return [1 - Y[e33], 1 + Y[e33], fields.body_events(p, Y, module)["rad"]]

    vals = {}
    for kind, lo, hi in (("thin", phic, phic), ("arc", phic - dphi, phic + dphi)):
        steps = [_frac(s) for s in c[kind]["steps"]]
        claim(f"psi={tgt} {kind} steps", sum(steps) == t_a and all(s > 0 for s in steps),
              f"the {len(steps)} exact step sizes add up to t_a = {float(t_a):.9g}")
        S, tangent = _lift(p, V, xhat, rho_eff, L, r, lo, hi, module)
        try:
            S = taylor.propagate(fb, S, steps=steps, order=order, guard=guard)
            cr = taylor.cross_section(fb, S, g, dg, h, order, guard=guard)
        except (taylor.EnclosureError, taylor.GuardError, taylor.CrossingError) as err:
            claim(f"psi={tgt} {kind} flight", False, str(err))
        ev = fields.body_events(p, cr.x, module)
        q = {"Gs": ev["Gs"], "Gc": ev["Gc"], "s2": ev["s2"], "gdot": cr.gdot, "tau": cr.tau}
        u = ball.column(cr.W * tangent)
        grad = dg(cr.x)
        gu = sum((a * b for a, b in zip(grad, u)), arb(0))
        gf = sum((a * b for a, b in zip(grad, cr.fx)), arb(0))
        v = [ui - fi * gu / gf for ui, fi in zip(u, cr.fx)]
        q["dGs"] = sum((a * b for a, b in zip(fields.body_event_gradient(p, cr.x, "Gs", module), v)), arb(0))
        q["de33"] = v[e33]
        stored = c[kind]["enclosures"]
        for k, val in q.items():
            _recomputed(claim, f"psi={tgt} {kind} {k}", val, stored[k])
        vals[kind] = q
    thin, arc = vals["thin"], vals["arc"]
    # the claims are made on the certificate's balls (each contains its recomputation, checked above)
    sarc = {k: ball.from_json(v) for k, v in c["arc"]["enclosures"].items()}
    claim(f"psi={tgt} section transversal", ball.excludes_zero(sarc["gdot"]),
          "d/dt (sin theta pbar_theta) excludes 0 over the crossing step")
    claim(f"psi={tgt} branch", {"0": ball.positive, "pi": ball.negative}[tgt](sarc["Gc"]),
          f"sin(theta) rho cos(psi) {'>' if tgt == '0' else '<'} 0 at the crossing")
    claim(f"psi={tgt} dGs/dphi", ball.excludes_zero(sarc["dGs"]), "dGs/dphi excludes 0 over the arc")
    N = ball.q(phic) - thin["Gs"] / arc["dGs"]
    _recomputed(claim, f"psi={tgt} Newton", N, c["newton"])
    claim(f"psi={tgt} unique zero", _inside(ball.from_json(c["newton"]), ball.interval(phic - dphi, phic + dphi)),
          "the interval Newton image lies inside the phase arc: one phi* with psi = "
          + ("0" if tgt == "0" else "pi"))
    dtdp = -arc["de33"] * arc["Gc"] / (arc["s2"].sqrt() * arc["dGs"])
    _recomputed(claim, f"psi={tgt} dtheta/dpsi", dtdp, c["dtheta_dpsi"])
    claim(f"psi={tgt} transversality", ball.excludes_zero(ball.from_json(c["dtheta_dpsi"])),
          "dtheta_u/dpsi excludes 0 (transverse intersection of W^u and W^s)")


# --------------------------------------------------------------------------------------------------------------
# kind "section_fixed_point": a symmetric hyperbolic fixed point of the section map sin psi = 0 on Hbar = h
# (the prover is magrod/proof/periodic.py; everything below is re-implemented from its module docstring)
# --------------------------------------------------------------------------------------------------------------
def _verify_fixed_point(cert, module, t0) -> VerifyResult:
    checks: list = []

    def claim(name, holds, how):
        checks.append({"name": name, "holds": bool(holds), "how": how})
        if not holds:
            raise _Reject(f"{name} failed (the check requires: {how})")

    try:
        p = fields.ExactParams(**{k: _frac(cert["params"][k]) for k in fields.PARAMS})
        s = cert["settings"]
        prec, cap, order = int(s["prec"]), int(s["series_cap"]), int(s["order"])
        if not (64 <= prec <= 1024 and 4 <= order < cap <= 256):
            raise CertificateError("settings out of range (prec 64..1024 bits, 4 <= order < series_cap <= 256)")
        with ball.workprec(prec, cap):
            vals = _fixed_point(cert, p, order, module, claim)
    except ball.InexactBall as err:  # a well-formed certificate whose precision is too low for its checks
        return _imprecise(checks, t0, err)
    except (KeyError, TypeError, ValueError, IndexError, ZeroDivisionError, AttributeError) as err:
        if isinstance(err, ParameterError):
            raise
        raise CertificateError(f"malformed certificate ({type(err).__name__}: {str(err)[:120]})") from None
    except _Reject as err:
        return VerifyResult(False, f"certificate rejected: {err}", checks, time.perf_counter() - t0)
    return VerifyResult(True, "certificate verified: every enclosure recomputed and every check holds", checks,
                        time.perf_counter() - t0,
                        section_fixed_point_theorem(p.as_json(), cert["level"], cert["settings"].get("lam_rad", "0"),
                                                    cert["point"].get("branch", "0")),  # the branch _fixed_point flew
                        {}, vals)


def _fp_hamgrad(pars, x, module):
    from flint import arb_series

    out = []
    for i in range(len(x)):
        y = [arb_series([v, 1 if j == i else 0], prec=2) for j, v in enumerate(x)]
        c = module.chart_hamiltonian(y, pars)[0]
        cs = c.coeffs() if isinstance(c, arb_series) else [c]
        out.append(cs[1] if len(cs) > 1 else arb(0))
    return out


def _fixed_point(cert, p, order, module, claim) -> dict:
    TH, PS, PT, PP = fields.THETA, fields.PSI, fields.PTHETA, fields.PPSI
    s, pt = cert["settings"], cert["point"]
    h = _frac(cert["level"])
    r, prad, t1, lead = (_frac(s[k]) for k in ("r", "p_rad", "t1", "lead"))
    thc, pc, t_a, hc = (_frac(pt[k]) for k in ("theta_c", "p_c", "t_a", "h_cross"))
    # what the certificate must contain, and which theorem (cheap, first)
    lam_rad = _frac(s.get("lam_rad", "0"))  # absent: a certificate at the point (issue 27's first ones)
    branch = pt.get("branch", "0")  # absent: psi = 0 (the Fig 4 certificates)
    if branch not in ("0", "pi"):
        raise ValueError("the point's branch is '0' or 'pi'")
    psi0 = arb(0) if branch == "0" else arb.pi()
    want = section_fixed_point_theorem(p.as_json(), cert["level"], s.get("lam_rad", "0"), branch)
    claim("theorem text", cert["theorem"] == want,
          "the certificate's theorem is the one its verified content establishes"
          + ("" if cert["theorem"] == want else f" (expected: {want[:120]}...; states: {str(cert['theorem'])[:120]}...)"))
    claim("settings match the data", hc == 2 * lead and r > 0 and prad > 0 and 0 < t1 < t_a and thc > 0
          and lam_rad >= 0,
          "the crossing step is 2 lead; r, p_rad > 0; 0 < t1 < t_a; theta_c > 0; lam_rad >= 0")
    fl = cert["flights"]
    claim("flights present", isinstance(fl, dict) and set(fl) == {"thin", "box"},
          f"exactly the thin flight (theta_c) and the box flight (Theta); got {sorted(fl) if isinstance(fl, dict) else fl}")
    sb = {k: ball.from_json(v) for k, v in fl["box"]["enclosures"].items()}
    tr_s = ball.from_json(cert["trace"])
    claim("claims on the certificate's balls", ball.negative(sb["gdot"]) and ball.excludes_zero(sb["dth_ptheta"])
          and _inside(ball.from_json(cert["newton"]), ball.interval(thc - r, thc + r))
          and ball.bounds(abs(tr_s))[0] > 2,
          "negative crossing, F' excludes 0, Newton inside Theta, |tr DP| > 2")
    _check_structure(module, claim)
    claim("field digest", cert["field_digest"] == fields.source_digest(module) == fields.source_digest(fields.gen),
          "the certificate's vector field is the installed derive-generated one (SHA-256 of generated/validated.py)")
    claim("parameters", p.m > 0 and min(p.gamma, p.delta, p.mu) >= 0, "m > 0; gamma, delta, mu >= 0")
    pars = list(p.balls())
    ilam, imu = fields.PARAMS.index("lam"), fields.PARAMS.index("mu")
    if lam_rad:  # lambdabar as the ball [lam - lam_rad, lam + lam_rad]: every enclosure holds on the interval
        pars[ilam] = ball.interval(p.lam - lam_rad, p.lam + lam_rad)
    pars = tuple(pars)
    # a lambdabar interval rides in the state (fields.lam_state_field: lambdabar' = 0), a point in the parameters
    fld = fields.lam_state_field(p, module) if lam_rad else fields.chart_field(p, module)
    Lam = [pars[ilam]] if lam_rad else []

    def H(x):
        return module.chart_hamiltonian(x, pars)[0]

    # 1. the level: pbar_psi(theta) by interval Newton, on the box and at the centre
    Theta = ball.interval(thc - r, thc + r)
    Pb = ball.interval(pc - prad, pc + prad)
    levels = {}
    for key, th in (("box", Theta), ("centre", ball.q(thc))):
        dH = _fp_hamgrad(pars, [th, psi0, arb(0), Pb], module)[PP]
        N = ball.q(pc) - (H([th, psi0, arb(0), ball.q(pc)]) - ball.q(h)) / dH
        claim(f"level Newton ({key})", ball.excludes_zero(dH) and _inside(N, Pb),
              f"a unique pbar_psi(theta) with Hbar(theta, {branch}, 0, pbar_psi) = h in the box, inside {N}")
        _recomputed(claim, f"level ({key})", N, pt["level_newton"][key])
        levels[key] = N

    # 2-3. the flights (exact steps), two phases, one negative crossing of sin psi = 0
    def base(Y):
        return [Y[TH], arb.pi() - Y[TH], pars[imu] - 2 * (Y[4] if len(Y) > 4 else pars[ilam]) * Y[PP]]

    def sdot(Y):
        return Y[PS].cos() * fld.f(Y)[PS]

    def first(Y):
        return base(Y) + [sdot(Y)]

    def second(Y):
        sn = Y[PS].sin()
        return base(Y) + [sn if ball.positive(sn) else -sdot(Y)]

    def g(x):
        return x[PS].sin()

    def dg(x):
        return [arb(0), x[PS].cos()] + [arb(0)] * (len(x) - 2)

    got = {}
    for kind, th, pbox in (("thin", ball.q(thc), levels["centre"]), ("box", Theta, levels["box"])):
        st1 = [_frac(v) for v in fl[kind]["steps1"]]
        st2 = [_frac(v) for v in fl[kind]["steps2"]]
        claim(f"{kind} steps", sum(st1) == t1 and sum(st1) + sum(st2) == t_a and all(v > 0 for v in st1 + st2),
              f"the exact steps add up to t1 = {float(t1):.6g} (phase 1) and t_a = {float(t_a):.9g} (both phases)")
        x = [th, psi0, arb(0), pbox] + Lam
        xc = [v.mid() for v in x]
        S = taylor.initial_set(xc, c1=True)
        S.r0 = ball.vec([a - b for a, b in zip(x, xc)])
        try:
            S = taylor.propagate(fld, S, steps=st1, order=order, guard=first)
            S = taylor.propagate(fld, S, steps=st2, order=order, guard=second)
            cr = taylor.cross_section(fld, S, g, dg, hc, order, guard=base)
        except (taylor.EnclosureError, taylor.GuardError, taylor.CrossingError) as err:
            claim(f"{kind} flight", False, str(err))
        gH = _fp_hamgrad(pars, x[:4], module)
        z = [arb(0)] * len(Lam)
        tang = {"th": [arb(1), arb(0), arb(0), -gH[TH] / gH[PP]] + z,
                "pt": [arb(0), arb(0), arb(1), -gH[PT] / gH[PP]] + z}
        gg = dg(cr.x)
        gf = sum((a * b for a, b in zip(gg, cr.fx)), arb(0))
        q = {"ptheta": cr.x[PT], "theta": cr.x[TH], "cospsi": cr.x[PS].cos(), "gdot": cr.gdot, "tau": cr.tau}
        for name, t in tang.items():
            u = ball.column(cr.W * ball.vec(t))
            gu = sum((a * b for a, b in zip(gg, u)), arb(0))
            v = [ui - fi * gu / gf for ui, fi in zip(u, cr.fx)]
            q[f"d{name}_theta"], q[f"d{name}_ptheta"] = v[TH], v[PT]
        for k, val in q.items():
            _recomputed(claim, f"{kind} {k}", val, fl[kind]["enclosures"][k])
        got[kind] = q
    thin, bx = got["thin"], got["box"]
    claim("negative crossing", ball.negative(sb["gdot"]),
          "d(sin psi)/dt < 0 over the crossing step: the half-way point on Fix(R), not a return to Sigma+")
    # 4. Fix(R): one theta* in Theta whose orbit meets pbar_theta = 0 at the crossing
    N = ball.q(thc) - thin["ptheta"] / bx["dth_ptheta"]
    _recomputed(claim, "Fix(R) Newton", N, cert["newton"])
    claim("unique theta*", ball.excludes_zero(sb["dth_ptheta"]) and _inside(ball.from_json(cert["newton"]), Theta),
          "the interval Newton image lies inside Theta: exactly one theta* in Theta, its orbit meets Fix(R)")
    # 5. hyperbolicity: DP(x0) = R A^-1 R A, tr = 2 (ad + bc) / (ad - bc)
    a, b, c, d = bx["dth_theta"], bx["dpt_theta"], bx["dth_ptheta"], bx["dpt_ptheta"]
    tr = 2 * (a * d + b * c) / (a * d - b * c)
    _recomputed(claim, "tr DP(x0)", tr, cert["trace"])
    claim("hyperbolic", ball.bounds(abs(tr_s))[0] > 2, f"|tr DP(x0)| > 2 on the certificate's ball {tr_s}: a saddle")
    sq = (tr_s * tr_s - 4).sqrt()
    mu = (tr_s + sq) / 2 if ball.positive(tr_s) else (tr_s - sq) / 2
    _recomputed(claim, "mu_u", mu, cert["mu_u"])
    T = ball.q(2 * t_a) + 2 * ball.from_json(fl["box"]["enclosures"]["tau"])
    return {k: [ball.decimal(v) for v in ball.json_bounds(x)]
            for k, x in (("theta*", cert["newton"]), ("tr DP(x0)", cert["trace"]), ("mu_u", cert["mu_u"]),
                         ("return time T", ball.to_json(T)))}


# --------------------------------------------------------------------------------------------------------------
# kind "section_horseshoe": covering relations of the section map on Hbar = h (the prover is
# magrod/proof/horseshoe.py).  The flights are section_return.piece_return driven with the certificate's exact steps (as
# the integrator is shared); the covering conditions, the cover by pieces, the symmetry, the disjointness, the
# chain's completeness and the entropy bound are checked again here, in exact rationals where they are geometric.
# Cost (issue 27: reproduce verifies it): the Taylor coefficients by Newton's iteration on series instead of the
# prover's Picard iteration (taylor._newton_series), the centres flown as C^0 sets, and the sets re-flown in parallel
# child processes (_hs_sources_parallel; the same checks in the same order): 44-58 s of CPU instead of ~150-220 s.
# --------------------------------------------------------------------------------------------------------------
def _verify_horseshoe(cert, module, t0, workers=None) -> VerifyResult:
    checks: list = []

    def claim(name, holds, how):
        checks.append({"name": name, "holds": bool(holds), "how": how})
        if not holds:
            raise _Reject(f"{name} failed (the check requires: {how})")

    try:
        p = fields.ExactParams(**{k: _frac(cert["params"][k]) for k in fields.PARAMS})
        s = cert["settings"]
        prec, cap, order = int(s["prec"]), int(s["series_cap"]), int(s["order"])
        if not (64 <= prec <= 1024 and 4 <= order < cap <= 256):
            raise CertificateError("settings out of range (prec 64..1024 bits, 4 <= order < series_cap <= 256)")
        with ball.workprec(prec, cap):
            vals = _horseshoe(cert, p, order, module, claim, workers)
    except ball.InexactBall as err:  # a well-formed certificate whose precision is too low for its checks
        return _imprecise(checks, t0, err)
    except (KeyError, TypeError, ValueError, IndexError, ZeroDivisionError, AttributeError) as err:
        if isinstance(err, ParameterError):
            raise
        raise CertificateError(f"malformed certificate ({type(err).__name__}: {str(err)[:120]})") from None
    except _Reject as err:
        return VerifyResult(False, f"certificate rejected: {err}", checks, time.perf_counter() - t0)
    return VerifyResult(True, "certificate verified: every link re-flown and every check holds", checks,
                        time.perf_counter() - t0,
                        section_horseshoe_theorem(p.as_json(), cert["level"], vals["k"], vals["L"], vals["rho"],
                                                  vals["lam_rad"], period=vals["period"]),
                        {}, {})


def _psi_periodic(module) -> bool:
    """The generated chart_rhs and chart_jacobian use psi only as (psi).sin() and (psi).cos() (after the state's
    unpacking and the docstring), so the chart field is 2 pi-periodic in psi."""
    import re

    src = fields.inspect.getsource(module)
    for fn in ("chart_rhs", "chart_jacobian"):
        seg = src[src.index(f"def {fn}("):]
        seg = seg[: seg.find("\ndef ", 1) if seg.find("\ndef ", 1) > 0 else None]
        if '"""' in seg:
            a = seg.index('"""')
            seg = seg[:a] + seg[seg.index('"""', a + 3) + 3:]
        seg = seg.replace("(psi).sin()", "").replace("(psi).cos()", "")
        seg = re.sub(r"theta, psi, ptheta, ppsi, = x", "", seg)
        if re.search(r"\bpsi\b", seg):
            return False
    return True


def _hs_set(d):
    c = [_frac(v) for v in d["c"]]
    A = [[_frac(v) for v in row] for row in d["A"]]
    if len(c) != 2 or len(A) != 2 or any(len(r) != 2 for r in A):
        raise ValueError("a set is c (2) and A (2 x 2)")
    return c, A


def _hs_inv(A):
    det = A[0][0] * A[1][1] - A[0][1] * A[1][0]
    return [[A[1][1] / det, -A[0][1] / det], [-A[1][0] / det, A[0][0] / det]]


def _hs_vertices(c, A):
    return [(c[0] + A[0][0] * a + A[0][1] * b, c[1] + A[1][0] * a + A[1][1] * b)
            for a, b in ((1, 1), (1, -1), (-1, -1), (-1, 1))]


def _hs_separated(P1, P2) -> bool:
    for poly in (P1, P2):
        for i in range(4):
            (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % 4]
            n = (y2 - y1, x1 - x2)
            a = [n[0] * x + n[1] * y for x, y in P1]
            b = [n[0] * x + n[1] * y for x, y in P2]
            if max(a) < min(b) or max(b) < min(a):
                return True
    return False


def _hs_cover(pieces) -> bool:
    """The pieces (yu, ys, hu, hs) cover [-1, 1]^2: each inside it, pairwise interiors disjoint, total area 4
    (closed boxes of full total area with disjoint interiors inside the square cover it)."""
    boxes = []
    for yu, ys, hu, hs in pieces:
        if hu <= 0 or hs <= 0 or yu - hu < -1 or yu + hu > 1 or ys - hs < -1 or ys + hs > 1:
            return False
        boxes.append((yu - hu, yu + hu, ys - hs, ys + hs))
    for i in range(len(boxes)):
        for j in range(i):
            a, b = boxes[i], boxes[j]
            if a[0] < b[1] and b[0] < a[1] and a[2] < b[3] and b[2] < a[3]:
                return False
    return sum((b[1] - b[0]) * (b[3] - b[2]) for b in boxes) == 4


def _hs_lam(cert, p, module=fields.gen):
    """A lambdabar interval (settings "lam_rad" > 0; horseshoe.widen): (w, pars with lambdabar's ball, the ball,
    ball - lam, [v_j] exact) -- the sets move, N_j(s) = c_j + v_j (s - lam) + A_j [-1, 1]^2; None for a point."""
    w = _frac(cert["settings"].get("lam_rad", "0"))
    if w < 0:
        raise ValueError("lam_rad must be >= 0")
    if w == 0:
        if any("v" in d for d in cert["sets"]):
            raise ValueError("a point certificate's sets do not move (no 'v')")
        return None
    vs = [tuple(_frac(x) for x in d["v"]) for d in cert["sets"]]
    if any(len(v) != 2 for v in vs):
        raise ValueError("a set's v has 2 entries")
    pars = fields.parameter_balls(p, w)
    lam = pars[fields.LAM]
    return w, pars, lam, lam - ball.q(p.lam), vs


def _hs_separated_moving(P1, P2, dv, w) -> bool:
    """P1 and P2 + s dv disjoint for every s in [-w, w]: a separating axis (edge normals, the normal of dv) between
    P1 and the vertices of P2 at s = -w and s = w (convex hull of the swept set)."""
    axes = []
    for poly in (P1, P2):
        for i in range(4):
            (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % 4]
            axes.append((y2 - y1, x1 - x2))
    if dv != (0, 0):
        axes.append((-dv[1], dv[0]))
    swept = [(x + t * dv[0], y + t * dv[1]) for x, y in P2 for t in (-w, w)]
    for n in axes:
        a = [n[0] * x + n[1] * y for x, y in P1]
        b = [n[0] * x + n[1] * y for x, y in swept]
        if max(a) < min(b) or max(b) < min(a):
            return True
    return False


def _hs_branch_boxes(cert, pars, sets, brs, module, claim=None) -> list:
    """[(ok, B)] per set: the level's root pbar_psi by interval Newton over the set's hull, B its Newton box (each
    claimed as it is computed when `claim` is given)."""
    from . import section_return

    h, prad = _frac(cert["level"]), _frac(cert["settings"]["p_rad"])
    U = ball.interval(-1, 1)
    mv = _hs_lam(cert, fields.ExactParams(**{kk: _frac(cert["params"][kk]) for kk in fields.PARAMS}), module)
    if mv is not None:
        pars = mv[1]
    out = []
    for j, (c, A) in enumerate(sets):
        U0 = ball.q(c[0]) + ball.q(A[0][0]) * U + ball.q(A[0][1]) * U
        U1 = ball.q(c[1]) + ball.q(A[1][0]) * U + ball.q(A[1][1]) * U
        if mv is not None:  # the hull swept over the lambdabar interval
            U0, U1 = U0 + ball.q(mv[4][j][0]) * mv[3], U1 + ball.q(mv[4][j][1]) * mv[3]
        _, B, ok = section_return.level_newton_section(pars, h, U0, U1, _frac(cert["sets"][j]["p_c"]), prad, module,
                                                       brs[j])
        if claim is not None:
            claim(f"N{j} branch box", ok, "the level's root pbar_psi is unique in the set's branch box over its hull")
        out.append((ok, B))
    return out


def _hs_graph(cert, n: int) -> tuple:
    """(period p, the links the certificate must have) for n sets.  p = 1 (no "period" in the settings): N0 => N0,
    N0 => N1 => ... => N(n-1).  p > 1 (horseshoe._prove_cycle): the cycle N0 => N1 => ... => N(p-1) => N0 and the
    chain N(p-1) => Np => ... => N(n-1) (at least two sets after the cycle, so that Np and N(n-1) differ)."""
    per = int(cert["settings"].get("period", 1))
    if per == 1:
        return 1, [[0, 0], [0, 1]] + [[j, j + 1] for j in range(1, n - 1)]
    if not 2 <= per <= n - 3:
        raise ValueError(f"period {per} out of range for {n} sets")
    return per, ([[i, i + 1] for i in range(per - 1)] + [[per - 1, 0], [per - 1, per]]
                 + [[j, j + 1] for j in range(per, n - 1)])


def _hs_source(cert, i, order, module, claim, branch) -> None:
    """The checks of set N_i as a source, in the verifier's order: its pieces re-flown (steps, flight, level,
    positive return), then every link N_i => N_j of the chain.  Depends only on the certificate, i and the branch
    boxes, so the sets can be checked in separate processes (_hs_sources_parallel) with the same checks."""
    from . import section_return

    s = cert["settings"]
    h = _frac(cert["level"])
    prad, t1, lead = (_frac(s[kk]) for kk in ("p_rad", "t1", "lead"))
    newton = int(s["newton"])
    p = fields.ExactParams(**{kk: _frac(cert["params"][kk]) for kk in fields.PARAMS})
    sets = [_hs_set(d) for d in cert["sets"]]
    brs = [d.get("branch", "0") for d in cert["sets"]]
    want = _hs_graph(cert, len(sets))[1]
    fl = {int(f["set"]): f for f in cert["flights"]}[i]
    pieces = [tuple(_frac(v) for v in r["piece"]) for r in fl["pieces"]]
    pars = p.balls()
    # the flights' Taylor coefficients by Newton's iteration on series (taylor._newton_series: as rigorous as the
    # prover's Picard iteration, other balls, ~1/4 of the cost), the centres as C^0 sets (their DP is not read here)
    fld = dataclasses.replace(fields.chart_field(p, module), series="newton")
    lm = _hs_lam(cert, p, module)
    mv = None if lm is None else section_return.Moving(
        tuple(lm[1]), dataclasses.replace(fields.lam_state_field(p, module), series="newton"), lm[2], p.lam, lm[4][i])
    U = ball.interval(-1, 1)
    c, A = sets[i]
    images = []
    for n, (r, pc) in enumerate(zip(fl["pieces"], pieces)):
        yu, ys, hu, hs = pc
        cX = [c[0] + A[0][0] * yu + A[0][1] * ys, c[1] + A[1][0] * yu + A[1][1] * ys]
        AX = [[A[0][0] * hu, A[0][1] * hs], [A[1][0] * hu, A[1][1] * hs]]
        steps = {kk: [[_frac(x) for x in ph] for ph in r["steps"][kk]] for kk in ("thin", "box")}
        t_a = _frac(r["t_a"])
        for kk in ("thin", "box"):
            claim(f"N{i} piece {n} {kk} steps", len(steps[kk]) == 2 and sum(steps[kk][0]) == t1 and
                  sum(steps[kk][0]) + sum(steps[kk][1]) == t_a and all(x > 0 for ph in steps[kk] for x in ph),
                  "phase 1 on [0, t1], phase 2 on [t1, t_a], positive exact steps")
        try:
            f = section_return.piece_return(pars, h, fld, cX, AX, _frac(r["p_c"]), prad, t_a, lead, t1=t1,
                                            order=order, steps=steps, newton=newton, thin_c1=False, branch=brs[i],
                                            integrator=section_return.integrator(s.get("integrator", "taylor")),
                                            thin_integrator=section_return.integrator(s.get("thin_integrator",
                                                                                            "taylor")),
                                            moving=mv, module=module)
        except (taylor.EnclosureError, taylor.GuardError, taylor.CrossingError) as err:
            claim(f"N{i} piece {n} flight", False, str(err)[:200])
        claim(f"N{i} piece {n} level", f["level_ok"] and ball.subset(f["ppsi_hull"], branch[i]),
              "the piece's pbar_psi: unique in its Newton box over the piece, inside the set's branch box")
        claim(f"N{i} piece {n} positive return", all(ball.positive(f[x]) for x in ("gdot_thin", "gdot_box")),
              "the first return is a transversal positive crossing")
        images.append((pc, AX, f))
    for src, j in want:
        if src != i:
            continue
        cM, AM = sets[j]
        Ai = [[ball.q(v) for v in row] for row in _hs_inv(AM)]
        right, left = [], []
        for n, (pc, AX, f) in enumerate(images):
            d = [f["Pc"][0] - ball.q(cM[0]), f["Pc"][1] - ball.q(cM[1])]
            if lm is not None:  # in M's moving coordinates: + (dP/ds - v_M)(s - lam), s in the interval
                d = [d[a] + (f["dPds"][a] - ball.q(lm[4][j][a])) * lm[3] for a in range(2)]
            off = [Ai[a][0] * d[0] + Ai[a][1] * d[1] for a in range(2)]
            DA = [[f["DP"][a][0] * ball.q(AX[0][b]) + f["DP"][a][1] * ball.q(AX[1][b]) for b in range(2)]
                  for a in range(2)]
            G = [[Ai[a][0] * DA[0][b] + Ai[a][1] * DA[1][b] for b in range(2)] for a in range(2)]
            yu = off[0] + G[0][0] * U + G[0][1] * U
            ys = off[1] + G[1][0] * U + G[1][1] * U
            lu, hu_ = ball.bounds(yu)
            ls_, hs_ = ball.bounds(ys)
            claim(f"N{i} => N{j} piece {n} psi branch", all((ball.positive(f[x]) if brs[j] == "0" else
                                                              ball.negative(f[x])) for x in ("cospsi_thin",
                                                                                              "cospsi_box")),
                  f"the image is on M's branch psi = {brs[j]} mod 2 pi (the sign of cos psi at the crossing)")
            claim(f"N{i} => N{j} piece {n} (a)", -1 < ls_ and hs_ < 1,
                  f"the image lies in |y_s| < 1 (y_s {ys}), so it never meets M's entry edges and the straight-line "
                  f"homotopy to (a y_u, 0) keeps |y_s| < 1")
            if lu <= 1 and hu_ >= -1:
                # where the image can land in M, its pbar_psi is M's root: inside M's branch box
                claim(f"N{i} => N{j} piece {n} branch", ball.subset(f["ppsi_box"], branch[j]),
                      "the image's pbar_psi lies in M's branch box (the level's root unique there over M)")
            if pc[0] - pc[2] == -1:
                left.append(off[0] - G[0][0] + G[0][1] * U)
            if pc[0] + pc[2] == 1:
                right.append(off[0] + G[0][0] + G[0][1] * U)
        claim(f"N{i} => N{j} exit edges", bool(right) and bool(left), "pieces on both exit edges")
        o = 1 if ball.bounds(right[0])[0] > 1 else -1
        okb = all(ball.bounds(e)[0] > 1 if o == 1 else ball.bounds(e)[1] < -1 for e in right) and \
            all(ball.bounds(e)[1] < -1 if o == 1 else ball.bounds(e)[0] > 1 for e in left)
        claim(f"N{i} => N{j} (b)", okb, "the images of the exit edges lie beyond M's exit edges, on opposite sides")


def _hs_workers(workers) -> int:
    """The number of processes for the horseshoe's sets: `workers`, or None: the CPUs this process may use."""
    if workers is not None:
        return max(1, int(workers))
    import os

    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


class _Stop(Exception):
    """A worker's recorded check failed: stop there (the parent raises the rejection when it replays it)."""


_MALFORMED = (KeyError, TypeError, ValueError, IndexError, ZeroDivisionError, AttributeError)


def _hs_record(cert, i, boxes: list) -> dict:
    """One set's checks (_hs_source, with the branch boxes of every set), recorded: {"i", "recs": [(name, holds,
    how)], "err": None or [type name, message, malformed?]}; the recording stops at the first check that fails (as
    the serial verifier does)."""
    recs = []

    def rec(name, holds, how):
        recs.append((name, bool(holds), how))
        if not holds:
            raise _Stop

    err = None
    try:
        s = cert["settings"]
        with ball.workprec(int(s["prec"]), int(s["series_cap"])):
            _hs_source(cert, i, int(s["order"]), fields.gen, rec, boxes)
    except _Stop:
        pass
    except Exception as e:  # noqa: BLE001 - handed to the parent, which raises it where the serial run would
        err = [type(e).__name__, str(e)[:120], isinstance(e, _MALFORMED) and not isinstance(e, (ParameterError,
                                                                                                ball.InexactBall))]
    return {"i": i, "recs": recs, "err": err}


def _hs_worker_boxes(cert) -> tuple:
    """The branch boxes of every set, once per worker process (they depend on the certificate only), or the error
    that each of the worker's sets then reports."""
    try:
        s = cert["settings"]
        p = fields.ExactParams(**{kk: _frac(cert["params"][kk]) for kk in fields.PARAMS})
        with ball.workprec(int(s["prec"]), int(s["series_cap"])):
            sets = [_hs_set(d) for d in cert["sets"]]
            brs = [d.get("branch", "0") for d in cert["sets"]]
            return [B for _ok, B in _hs_branch_boxes(cert, p.balls(), sets, brs, fields.gen)], None
    except Exception as e:  # noqa: BLE001 - handed to the parent, which raises it where the serial run would
        return None, [type(e).__name__, str(e)[:120], isinstance(e, _MALFORMED) and not isinstance(e, (ParameterError,
                                                                                                       ball.InexactBall))]


def _hs_worker_main() -> None:
    """A worker process of _hs_sources_parallel: the certificate and its set indices on stdin (one JSON document),
    one JSON line per set on stdout, in the order of the indices."""
    import sys

    job = json.loads(sys.stdin.read())
    boxes, err = _hs_worker_boxes(job["cert"])
    for i in job["sets"]:
        r = {"i": int(i), "recs": [], "err": err} if err is not None else _hs_record(job["cert"], int(i), boxes)
        sys.stdout.write(json.dumps(r) + "\n")
        sys.stdout.flush()


def _hs_sources_parallel(cert, k, workers, claim) -> None:
    """_hs_source for i = 0 .. k-1 in `workers` child processes (fresh interpreters running _hs_worker_main on
    sets i = w, w + workers, ...: no multiprocessing, so nothing of the caller's __main__ is re-run and no
    process-wide state is changed), their records replayed through `claim` in the order of i, so the checks, the
    first rejection and its reason are the serial verifier's; on a rejection the workers are stopped."""
    import os
    import subprocess
    import sys

    root = str(Path(__file__).resolve().parents[2])  # the magrod the caller runs, for the children too
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([root] + [v for v in [os.environ.get("PYTHONPATH")] if v]))
    # one thread each (the QR of Lohner's step is 4 x 4): BLAS threads of two workers would compete for the cores
    env.update(OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")
    code = "from magrod.proof.verify import _hs_worker_main; _hs_worker_main()"
    procs = []
    try:
        for w in range(workers):
            pr = subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                  env=env, text=True)
            procs.append(pr)
            pr.stdin.write(json.dumps({"cert": cert, "sets": list(range(w, k, workers))}))
            pr.stdin.close()
        for i in range(k):
            line = procs[i % workers].stdout.readline()
            if not line:
                raise RuntimeError(f"the horseshoe verifier's worker for N{i} ended without a result "
                                   f"(exit status {procs[i % workers].wait()})")
            r = json.loads(line)
            if r["i"] != i:
                raise RuntimeError(f"worker result for N{r['i']} where N{i} was expected")
            for name, holds, how in r["recs"]:
                claim(name, holds, how)
            if r["err"] is not None:
                kind, msg, malformed = r["err"]
                if kind == "InexactBall":
                    raise ball.InexactBall(msg)
                if malformed:
                    raise CertificateError(f"malformed certificate ({kind}: {msg})")
                raise RuntimeError(f"horseshoe verifier worker, N{i}: {kind}: {msg}")
    finally:
        for pr in procs:
            if pr.poll() is None:
                pr.kill()
            pr.wait()
            pr.stdout.close()


def _horseshoe(cert, p, order, module, claim, workers=None) -> dict:
    _check_structure(module, claim)
    claim("field digest", cert["field_digest"] == fields.source_digest(module) == fields.source_digest(fields.gen),
          "the certificate's field is the installed derive-generated one")
    claim("2 pi-periodic in psi", _psi_periodic(module),
          "the chart field uses psi only through sin psi, cos psi (the return at psi = 2 pi is a point of Sigma)")
    sets = [_hs_set(d) for d in cert["sets"]]
    brs = [d.get("branch", "0") for d in cert["sets"]]
    if any(b not in ("0", "pi") for b in brs):
        raise ValueError("a set's branch is '0' or 'pi'")
    k = len(sets) - 1
    claim("chain length", k >= 2, f"{k + 1} sets")
    per, want = _hs_graph(cert, k + 1)
    claim("links", [list(map(int, lk)) for lk in cert["links"]] == want,
          "exactly N0 => N0, N0 => N1 => ... => Nk (a complete chain)" if per == 1 else
          f"exactly the cycle N0 => N1 => ... => N{per - 1} => N0 and the chain N{per - 1} => N{per} => ... => N{k}")
    for i, (_c, A) in enumerate(sets):
        claim(f"N{i} nondegenerate", A[0][0] * A[1][1] - A[0][1] * A[1][0] != 0, "det A != 0")
    lm = _hs_lam(cert, p, module)
    for i in (0, k):
        c, A = sets[i]
        claim(f"N{i} symmetric", c[1] == 0 and A[0][1] == A[0][0] and A[1][1] == -A[1][0] and
              (lm is None or lm[4][i][1] == 0),
              "centre on Fix(R) and A = [a, R a], so R(N)^T = N exactly" +
              ("" if lm is None else "; it moves along Fix(R) (v's pbar_theta = 0)"))
    V0 = _hs_vertices(*sets[0])
    for j in range(1, k + 1):
        if lm is None:
            sep = _hs_separated(V0, _hs_vertices(*sets[j]))
        else:
            sep = _hs_separated_moving(V0, _hs_vertices(*sets[j]), (lm[4][j][0] - lm[4][0][0],
                                                                    lm[4][j][1] - lm[4][0][1]), lm[0])
        claim(f"N0, N{j} disjoint", brs[j] != brs[0] or sep,
              "another branch of psi, or a separating edge normal" + ("" if lm is None else " for every lambdabar"))
    for j in range(1, k):
        RV = [(x, -y) for x, y in _hs_vertices(*sets[j])]
        if lm is None:
            sep = _hs_separated(V0, RV)
        else:
            sep = _hs_separated_moving(V0, RV, (lm[4][j][0] - lm[4][0][0], -lm[4][j][1] - lm[4][0][1]), lm[0])
        claim(f"N0, R(N{j}) disjoint", brs[j] != brs[0] or sep,
              "another branch of psi (R keeps it), or a separating edge normal" +
              ("" if lm is None else " for every lambdabar"))
    L = 2 * k
    claim("loop length", int(cert["loop_length"]) == L, f"the loop N0 => ... => N{k} <= ... <= N0 has length 2k = {L}")
    rho = _frac(cert["entropy"]["rho_lower"])
    # the other loop through N0 has length p (p = 1: N0 => N0): blocks 1 0^(p-1) and 1 0^(L-1), x^L = x^(L-p) + 1
    # (f(1) = -1, f increasing on [1, 2]: f(rho_lower) < 0 puts rho_lower below the largest root)
    claim("entropy bound", 1 < rho < 2 and rho**L - rho ** (L - per) - 1 < 0,
          f"rho_lower = {float(rho):.12g} is below the largest root of x^{L} = x^{L - per} + 1 (f(rho_lower) < 0)")
    w_txt = "0" if lm is None else f"{lm[0].numerator}/{lm[0].denominator}"
    text = section_horseshoe_theorem(p.as_json(), cert["level"], k, L, cert["entropy"]["rho_lower"], w_txt,
                                     period=per)
    claim("theorem", cert.get("theorem") == text, "the certificate states exactly the theorem generated here")
    fl_by_set = {int(f["set"]): f for f in cert["flights"]}
    claim("flights", sorted(fl_by_set) == list(range(k)), "one flight record per set N0 .. N(k-1)")
    pieces = {}
    for i in range(k):
        pieces[i] = [tuple(_frac(v) for v in r["piece"]) for r in fl_by_set[i]["pieces"]]
        claim(f"N{i} cover", _hs_cover(pieces[i]), f"the {len(pieces[i])} pieces cover [-1, 1]^2 exactly")
    pars = p.balls()
    boxes = [B for _ok, B in _hs_branch_boxes(cert, pars, sets, brs, module, claim)]
    w = 1 if module is not fields.gen else min(_hs_workers(workers), k)
    if w <= 1:
        for i in range(k):
            _hs_source(cert, i, order, module, claim, boxes)
    else:
        _hs_sources_parallel(cert, k, w, claim)
    return {"k": k, "L": L, "rho": cert["entropy"]["rho_lower"], "lam_rad": w_txt, "period": per}
