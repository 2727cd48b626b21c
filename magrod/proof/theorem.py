"""The theorem a homoclinic certificate establishes, as text generated from what was verified.

The verifier (verify.py) prints this text, built from the parameters and the targets it has checked, and requires
the certificate's own "theorem" field to be this text exactly: a certificate cannot state more (or other) than its
checks establish.  The prover (provers/transverse_homoclinic.py) writes the same function's output into the certificate it issues.

The targets are the symmetric points psi = 0 and psi = pi of Fix(R) on Sigma = {pbar_theta = 0}.  Two distinct
targets give two distinct orbits: a homoclinic orbit that meets Fix(R) twice would be R-symmetric about two points,
hence periodic (Devaney 1976, reversible systems), which a homoclinic orbit is not.
"""
from __future__ import annotations

from fractions import Fraction

#: the recognised targets: certificate spelling -> the value of psi on Fix(R)
TARGETS = {"0": "psi = 0", "pi": "psi = pi"}
#: the order in which the targets are listed in the theorem (independent of the certificate's order)
ORDER = ("0", "pi")


def _rational(s: str) -> str:
    f = Fraction(s)
    return str(f.numerator) if f.denominator == 1 else f"{f.numerator}/{f.denominator}"


def homoclinic_theorem(params: dict, targets, lam_rad: str = "0") -> str:
    """The statement established by a verified homoclinic certificate.

    Parameters
    ----------
    params : dict
        Exact parameters as strings "p/q", keys m, mu, gamma, delta, lam.
    targets : iterable of str
        The verified, distinct, recognised targets (a non-empty subset of TARGETS).
    lam_rad : str
        Half-width of the lambdabar interval the certificate carries (exact rational string; "0": the point, and
        the text of the certificates before lambdabar intervals, unchanged).

    Returns
    -------
    str
        One paragraph; the number of orbits and the points are those of `targets`.

    Raises
    ------
    ValueError
        If a target is not recognised, repeated, or the set is empty (a caller's bug: the verifier checks first).

    Examples
    --------
    >>> from magrod.proof.theorem import homoclinic_theorem
    >>> p = {"m": "17/10", "mu": "1/25", "gamma": "1/1", "delta": "1/1", "lam": "1/100"}
    >>> homoclinic_theorem(p, ["pi"])[:60]
    'At (m, mu, gamma, delta, lambdabar) = (17/10, 1/25, 1, 1, 1/'

    Notes
    -----
    The wording names the chart system only; the 9-D statement is conditional (docs/nonintegrability.md,
    statement 7) and is not part of what a certificate establishes.
    """
    targets = list(targets)
    if not targets or len(set(targets)) != len(targets) or any(t not in TARGETS for t in targets):
        raise ValueError(f"targets must be distinct elements of {sorted(TARGETS)}, got {targets!r}")
    pts = [TARGETS[t] for t in ORDER if t in targets]
    n = len(pts)
    w = Fraction(lam_rad)
    where = " and at ".join(f"a point with {p}" for p in pts)
    what = ("one transverse symmetric homoclinic orbit" if n == 1 else
            f"{'two' if n == 2 else n} distinct transverse symmetric homoclinic orbits")
    each = "" if w == 0 else " (for each lambdabar its own q*, W^u(q*) and orbits)"
    return (f"{_where(params, w, 'and every')}, for the reduced chart field of Hbar "
            f"(eq:full_ham_nondim){each}: the certificate's saddle box contains exactly one equilibrium q*, it lies on "
            f"Fix(R) and is a saddle-focus; its unstable manifold W^u(q*) meets Sigma = {{pbar_theta = 0}} on "
            f"Fix(R) at {where}, with dtheta_u/dpsi != 0 there, so W^u(q*) and W^s(q*) = R(W^u(q*)) intersect "
            f"transversally inside the energy level: {what} to q* "
            f"(docs/nonintegrability.md, Theorem (computer-assisted)).")


def _where(params: dict, w: Fraction, every: str) -> str:
    """"At (m, mu, gamma, delta, lambdabar) = (...)" for a point (w = 0), else "At (m, mu, gamma, delta) = (...)
    {every} lambdabar in [lam - w, lam + w]" (exact rationals)."""
    if w < 0:
        raise ValueError(f"lam_rad must be >= 0, got {w}")
    if w == 0:
        vals = ", ".join(_rational(params[k]) for k in ("m", "mu", "gamma", "delta", "lam"))
        return f"At (m, mu, gamma, delta, lambdabar) = ({vals})"
    vals = ", ".join(_rational(params[k]) for k in ("m", "mu", "gamma", "delta"))
    lam = Fraction(params["lam"])
    return (f"At (m, mu, gamma, delta) = ({vals}) {every} lambdabar in [{_rational(str(lam - w))}, "
            f"{_rational(str(lam + w))}]")


def section_fixed_point_theorem(params: dict, level: str, lam_rad: str = "0", branch: str = "0",
                                moving: bool = False) -> str:
    """The statement established by a verified section-fixed-point certificate (kind "section_fixed_point").

    Parameters
    ----------
    params : dict
        Exact parameters as strings "p/q", keys m, mu, gamma, delta, lam.
    level : str
        The level h as an exact rational string.
    lam_rad : str
        Half-width of the lambdabar interval the certificate carries (exact rational string; "0": the point).
    branch : {"0", "pi"}
        x0's branch of the section: psi = 0 (Fig 4) or psi = pi (Fig 5).
    moving : bool
        The certificate's box moves with lambdabar along its v (theta = theta_c + v (lambdabar - lam) + s).

    Returns
    -------
    str
        One paragraph.

    Notes
    -----
    The periodic orbit's hyperbolicity is what the certificate establishes; it is not chaos: positive topological
    entropy needs a transverse homoclinic point as well (docs/nonintegrability.md, statement 11).
    """
    w = Fraction(lam_rad)
    if branch not in ("0", "pi"):
        raise ValueError(f"branch must be '0' or 'pi', got {branch!r}")
    where = _where(params, w, "and every")
    each = "" if w == 0 else (" (for each lambdabar its own x0, unique in the certificate's box"
                              + (", which moves with lambdabar along the certificate's v)" if moving else ")"))
    return (f"{where}, on the level Hbar = {_rational(level)} of the reduced "
            f"chart field of Hbar (eq:full_ham_nondim): the section map P of {{sin psi = 0, d(sin psi)/dt > 0}} "
            f"has a fixed point x0{each} on Fix(R) (psi = {branch}, pbar_theta = 0) with theta"
            f"{' - v (lambdabar - lam)' if moving and w else ''} in the certificate's Newton ball, whose orbit is R-symmetric and periodic with period twice the certificate's crossing time, "
            f"and DP(x0) is hyperbolic: det DP(x0) = 1 and |tr DP(x0)| > 2, so its eigenvalues are real, mu and "
            f"1/mu with |mu| > 1 (a saddle of P; docs/nonintegrability.md, statement 11).")


def section_horseshoe_theorem(params: dict, level: str, k: int, loop_length: int, rho_lower: str,
                              lam_rad: str = "0", period: int = 1) -> str:
    """The statement established by a verified horseshoe certificate (kind "section_horseshoe").

    Parameters
    ----------
    params : dict
        Exact parameters as strings "p/q", keys m, mu, gamma, delta, lam.
    level : str
        The level h (exact rational string).
    k : int
        The chain N0 => N1 => ... => Nk (k covering relations after N0 => N0).
    loop_length : int
        L = 2k, the length of the second closed chain through N0.
    rho_lower : str
        An exact rational below the largest root rho of x^L = x^(L-1) + 1.
    lam_rad : str
        Half-width of the lambdabar interval the certificate carries (exact rational string; "0": the point).
        The sets then move with lambdabar (N_j(lambdabar) = c_j + v_j (lambdabar - lambdabar_0) + A_j [-1, 1]^2).
    period : int
        p > 1: the sets N0 .. Nk are a cycle N0 => N1 => ... => N(p-1) => N0 around a symmetric periodic orbit of
        period p and the chain N(p-1) => Np => ... => Nk (provers/section_horseshoe.py, _prove_cycle); L = 2k and rho is the largest
        root of x^L = x^(L-p) + 1 (the blocks 1 0^(p-1) and 1 0^(L-1)).  p = 1: the text above, unchanged.

    Returns
    -------
    str
        One paragraph.
    """
    rho = Fraction(rho_lower)
    import math

    w = Fraction(lam_rad)
    where = _where(params, w, "and for every")
    sets = "h-sets" if w == 0 else "h-sets (moving with lambdabar along the certificate's v_j)"
    if period != 1:
        q = period
        return (f"{where}, on the level Hbar = {_rational(level)}, the section map "
                f"P of {{sin psi = 0, d(sin psi)/dt > 0}} (section coordinates (theta, pbar_theta)) has {sets} N0, "
                f"..., N{k} with the covering relations N0 => N1 => ... => N{q - 1} => N0 (a cycle of length {q}) "
                f"and N{q - 1} => N{q} => ... => N{k} (Zgliczynski-Gidea 2004), N0 and N{k} symmetric under the "
                f"reversor R, N0 disjoint from the other sets of the loops; by reversibility the chain N0 => ... => "
                f"N{k} closes through back-coverings into a loop of length {loop_length} through N0, so P has a "
                f"compact forward-invariant set Lambda on which it is semiconjugate to the shift on concatenations "
                f"of the blocks 1 0^{q - 1} and 1 0^{loop_length - 1} (the visits to N0): h_top(P|Lambda) >= log rho "
                f"> {math.floor(math.log(float(rho)) * 1e4) / 1e4}, rho the largest root of x^{loop_length} = "
                f"x^{loop_length - q} + 1, rho > {_rational(rho_lower)}.")
    return (f"{where}, on the level Hbar = {_rational(level)}, the section map "
            f"P of {{sin psi = 0, d(sin psi)/dt > 0}} (section coordinates (theta, pbar_theta)) has {sets} N0, ..., "
            f"N{k} with the covering relations N0 => N0 and N0 => N1 => ... => N{k} (Zgliczynski-Gidea 2004), N0 "
            f"and N{k} symmetric under the reversor R, N0 disjoint from the other sets of the loops; by reversibility "
            f"the chain closes through back-coverings into a loop of length {loop_length} through N0, so P has a "
            f"compact forward-invariant set Lambda on which it is semiconjugate to the shift on concatenations of the "
            f"blocks 1 and 1 0^{loop_length - 1} (the visits to N0): h_top(P|Lambda) >= log rho > "
            f"{math.floor(math.log(float(rho)) * 1e4) / 1e4}"
            f", rho the largest root of x^{loop_length} = x^{loop_length - 1} + 1, rho > {_rational(rho_lower)}.")
