"""The horseshoe prover's design: its settings, the named designs (magrod/proof/designs/NAME.json, data), and the
float design (heyoka, reduced chart) that only chooses where to look -- the W^u point whose n_exc-th image lies on
Fix(R), its pull-back c_1, the frames and the sizes of the h-sets (section_horseshoe.py proves; nothing here decides
anything rigorous)."""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from ...core.eigen import fix_phase
from ...core.errors import ParameterError
from ...core.tolerances import FIXED_POINT_SEARCH_TOL, HORSESHOE_CENTRE_TOL, PROOF_STEP_TOL
from .. import ball, fields
from .transverse_homoclinic import ProofFailure

R2 = np.diag([1.0, -1.0])


@dataclass
class HorseshoeSettings:
    """Numerical choices (recorded; the verifier replays them).  m_back: pull-backs of z_0 (the scale of the sets:
    dist(x0, c_1) = s* mu_u^-m); qu, qs: the design margins per link in the exit / entry direction; pieces: the
    grid (n_u, n_s) of pieces per set (a dict by set index; default (1, 1)); p_rad: half-width of the level's Newton
    box; lead: the crossing step has length 2 lead."""

    prec: int = 128  # bits of the ball arithmetic (Arb) of every flight and check
    order: int = 20  # order of the validated Taylor steps
    tol: float = PROOF_STEP_TOL  # the step tolerance of the sets' flights
    #: the step tolerance of the centres' flights (their enclosures must resolve the sets: section_return.piece_return)
    tol_thin: float = HORSESHOE_CENTRE_TOL
    #: the centres' integrator (section_return.INTEGRATORS): "taylor_model" encloses a return ~1e9 x tighter at the
    #: same tolerance (benchmarks/centre_flight_frontier.py), so its centres fly at a looser tol_thin
    thin_integrator: str = "taylor"
    #: the sets' (box) integrator, likewise ("taylor_model": the C^1 remainder as a Taylor model too)
    integrator: str = "taylor"
    m_back: int = 5
    qu: float = 3.0  # the design margin per link in the exit (unstable) direction
    qs: float = 3.0
    p_rad: Fraction = Fraction(1, 10**6)
    t1: Fraction = Fraction(1, 64)  # length of a return's first phase (leaving the section, d sin(psi)/dt > 0)
    lead: Fraction = Fraction(1, 256)
    newton: int = 12  # interval Newton iterations for the crossing time at the section
    n_exc: int = 8  # returns of the excursion: P^n_exc(x0 + s* e_u) lands on Fix(R) (pbar_theta = 0)
    s_star: float = 2.431508147212876e-06  # first guess of s* along e_u(x0), refined by bisection (float design)
    pieces: dict | None = None
    #: the chain passes' centre-flight tolerances ("tol" or "thin"); a Newton shift after each but the last.  At
    #: Fig 4(b) (17 returns) the tol-1e-25 chain's end differs from the 1e-32 one by 1.6e-8 in pbar_theta, so its
    #: shift must come from a "thin" pass
    passes: tuple = ("tol", "tol", "thin")
    #: N0 => N1 geometry, as fractions of d = dist(x0, c_1): l0 = w0 = l0_frac d, l1 = l1_frac d (disjoint: l0 +
    #: l1 < d; covered: mu_u l0 > d + l1), the entry half-widths capped at w_cap l1 (N1 fat enough for N0's image,
    #: whose entry thickness is l0 / mu_u)
    l0_frac: float = 1 / 3
    l1_frac: float = 1 / 6  # l1 = l1_frac d: the exit half-length of N1 (and the scale of the chain's sets)
    w_cap: float = 1.0  # the entry half-widths are capped at w_cap l1
    #: x0's branch of Sigma+ ("0": psi = 0, psi' > 0 as at Fig 4; "pi": psi = pi, psi' < 0, Fig 5's saddle) and the
    #: root of the level it lifts to (index into the ascending roots of Hbar(theta, psi, 0, .) = h; -1 the largest)
    branch: str = "0"
    root: int = -1  # which root of the level x0 lifts to (index into the ascending roots; -1 the largest)
    #: stop the chain passes early once |pbar_theta(P^(k-1)(c_1))| < stop_frac w_k (0: never; valid only when the
    #: passes share one tolerance, so that the pass that stops is the certificate's: Fig 4(b))
    stop_frac: float = 0.0
    #: the period p of the symmetric orbit of P through x0 (1: the fixed point of statement 11).  p > 1 (even: x0
    #: and x_(p/2) on Fix(R); Fig 4(c)): the cycle N0 => N^1 => ... => N^(p-1) => N0 of sets at the orbit's points
    #: and the excursion N^(p-1) => C_1 => ... => C_k (_prove_cycle); m_back then counts pull-backs by P^p, n_exc
    #: the returns of P from s* to Fix(R)
    period: int = 1
    #: p > 1: the margin per cycle link N^i => N^(i+1) (i < p - 1) in both directions; N^(p-1) => N0 gets
    #: mu_u / q_cycle^(p-1)
    q_cycle: float = 1.2

    def as_json(self) -> dict:
        q = _q
        return {"prec": self.prec, "order": self.order, "tol": repr(self.tol), "tol_thin": repr(self.tol_thin), "m_back": self.m_back,
                "qu": self.qu, "qs": self.qs, "p_rad": q(self.p_rad), "t1": q(self.t1), "lead": q(self.lead),
                "newton": self.newton, "n_exc": self.n_exc, "passes": list(self.passes),
                "l0_frac": self.l0_frac, "l1_frac": self.l1_frac, "w_cap": self.w_cap, "series_cap": ball.SERIES_CAP,
                **({} if (self.branch, self.root) == ("0", -1) else {"branch": self.branch, "root": self.root}),
                **({"stop_frac": self.stop_frac} if self.stop_frac else {}),
                **({} if self.thin_integrator == "taylor" else {"thin_integrator": self.thin_integrator}),
                **({} if self.integrator == "taylor" else {"integrator": self.integrator}),
                **({} if self.period == 1 else {"period": self.period, "q_cycle": self.q_cycle})}


def design(name: str) -> HorseshoeSettings:
    """The prover's named design `name`: magrod/proof/designs/NAME.json holds the settings that differ from
    HorseshoeSettings' defaults (a tolerance may be named by its constant in magrod.core.tolerances) and, under
    "why", how they were chosen (the float margins, the failed attempts, the measured costs).  "proving": False would
    mark a design recorded for what it shows (none now: fig4d was one until its centres flew by the Taylor-model
    integrator and N31 was cut in 8 x 8 pieces).

    Examples
    --------
    >>> design("fig4b").n_exc, design("fig4c").period
    (14, 6)
    """
    import json
    from importlib import resources

    from ...core import tolerances

    try:
        data = json.loads(resources.files("magrod.proof").joinpath("designs", f"{name}.json").read_text())
    except (FileNotFoundError, TypeError):
        raise ParameterError("design", f"no horseshoe design {name!r} (magrod/proof/designs: "
                                       f"{', '.join(design_names(proving_only=False))})") from None
    kw = {}
    for k, v in data["settings"].items():
        if k in ("tol", "tol_thin") and isinstance(v, str):
            v = getattr(tolerances, v)  # a named tolerance: its rationale lives beside it
        elif k in ("p_rad", "t1", "lead"):
            v = Fraction(v)
        elif k == "passes":
            v = tuple(v)
        elif k == "pieces":
            v = {int(i): tuple(g) for i, g in v.items()}
        kw[k] = v
    return HorseshoeSettings(**kw)


def design_names(*, proving_only: bool = True) -> list:
    """The names of the designs in magrod/proof/designs (the proving ones by default)."""
    import json
    from importlib import resources

    out = []
    for f in sorted(resources.files("magrod.proof").joinpath("designs").iterdir(), key=lambda f: f.name):
        if f.name.endswith(".json") and (not proving_only or json.loads(f.read_text())["proving"]):
            out.append(f.name[:-5])
    return out


#: the proving designs (magrod prove --horseshoe ... --design NAME), each a callable giving its HorseshoeSettings;
#: "fig4a" is the default HorseshoeSettings()
DESIGNS = {n: functools.partial(design, n) for n in design_names()}


def _q(x) -> str:
    f = ball.fraction(x)
    return f"{f.numerator}/{f.denominator}"


def dyadic(x: float, bits: int = 62) -> Fraction:
    """x rounded to a dyadic rational with `bits` significant bits (set data exact in binary)."""
    if x == 0:
        return Fraction(0)
    e = math.floor(math.log2(abs(x))) - bits + 1
    return Fraction(round(x / 2.0**e)) * Fraction(2) ** e if e < 0 else Fraction(round(x))


def dyadic_of(v, bits: int = 100) -> Fraction:
    """The exact rational v (a Fraction or an exact arb) rounded to `bits` significant bits, dyadic."""
    f = ball.fraction(v)
    if f == 0:
        return f
    e = (abs(f.numerator).bit_length() - abs(f.denominator).bit_length()) - bits
    return Fraction(round(f / Fraction(2) ** e)) * Fraction(2) ** e


class FloatMap:
    """P on (theta, pbar_theta) in float64 (heyoka, tol 1e-15): the first positive crossing of sin psi = 0 after
    t > 1e-3; a point (theta, pbar_theta) is lifted to the branch psi = 0 or pi (`branch`, that of x0) with pbar_psi
    the level's root of index `root` (ascending; -1: the largest, the Fig 4 choice)."""

    def __init__(self, p: fields.ExactParams, h, branch: str = "0", root: int = -1):
        self.branch, self.root = branch, root
        self.psi = {"0": 0.0, "pi": math.pi}[branch]
        import heyoka as hy

        from ...core import systems
        from ...core.params import RodParams

        self.params, self.h = RodParams(*p.floats()), float(h)
        v = hy.make_vars(*systems.STATE["reduced"])
        ev = hy.t_event(hy.sin(v[fields.PSI]), direction=hy.event_direction.positive)
        self.ta = systems.taylor(systems.system("reduced"), [1.0, 0.0, 0.0, 1.0], self.params.array(),
                                 t_events=[ev], tol=FIXED_POINT_SEARCH_TOL)

    def lift(self, z):
        from ...chaos.section import solve_p_psi

        x = np.zeros(4)
        x[fields.THETA], x[fields.PSI], x[fields.PTHETA] = z[0], self.psi, z[1]
        x[fields.PPSI] = solve_p_psi(self.params, self.h, z[0], z[1], self.psi)[self.root]
        return x

    def full4(self, x):
        """(the 4-D state at the first positive crossing after t > 1e-3, its time) from the 4-D state x."""
        ta = self.ta
        ta.time = 0.0
        ta.state[:] = x
        ta.reset_cooldowns()
        while True:
            oc = ta.propagate_until(ta.time + 100.0)[0]
            if int(oc) != -1:
                raise ProofFailure("design: no return of the float section map within t = 100")
            if ta.time > 1e-3:
                break
        return ta.state.copy(), float(ta.time)

    def full(self, z):
        """((theta, pbar_theta) at the first positive crossing after t > 1e-3, its time) from the section point z."""
        y, t = self.full4(self.lift(z))
        return np.array([y[fields.THETA], y[fields.PTHETA]]), t

    def __call__(self, z):
        return self.full(z)[0]

    def inv(self, z):
        return R2 @ self(R2 @ np.asarray(z))

    def jac(self, z, eps=1e-7):
        D = np.empty((2, 2))
        for j in range(2):
            dz = np.zeros(2)
            dz[j] = eps
            D[:, j] = (self(z + dz) - self(z - dz)) / (2 * eps)
        return D


def unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def unstable_eigen(D) -> tuple[float, np.ndarray]:
    """(mu_u, e_u) of a real 2 x 2 saddle matrix D (a float DP or DP^p): the eigenvalue of largest modulus and its
    eigenvector, unit, real, theta-component > 0.  Independent of LAPACK's order, phase and sign (core.eigen: they
    differ between CPUs and BLAS kernels); on LAPACK's real output, v / |v| with its sign fixed to <= 1 ulp (bit for
    bit at the certificates' Fig 4(a) DP and Fig 4(c) DP^6)."""
    w, V = np.linalg.eig(D)
    iu = int(np.argmax(abs(w)))
    return float(np.real(w[iu])), np.real(fix_phase(V[:, iu], prefer=(0,)))


def float_design(P: FloatMap, x0, m: int, s_star: float, n_exc: int = 8) -> dict:
    """e_u(x0), the refined s* (pbar_theta(P^n_exc(x0 + s e_u)) = 0 by bisection) and c_1 = P^-m(z_0)."""
    D0 = P.jac(x0)
    mu, eu = unstable_eigen(D0)

    s = _float_s_star(P, x0, eu, s_star, n_exc)  # the excursion may visit the psi = pi branch: 4-D states
    # c_1 = P^-m(z_0) on the local W^u, to O(t^2): x0 + t e_u, t = s* mu_u^-m (not the float P^-m: its error
    # in the stable direction grows by mu_u per pull-back); mu_u < 0 (Fig 5: a flip saddle) alternates the side
    t = s / mu ** m
    return {"e_u0": eu, "mu_u": mu, "s_star": s, "t": t, "c1": x0 + t * eu}


class NearMap:
    """The float section map on (theta, pbar_theta) of a branch, pbar_psi the level's root nearest to a reference
    value (the orbit point's own: along a period-p orbit the root's index need not be constant)."""

    def __init__(self, P: FloatMap):
        self.P = P

    def lift(self, z, br, pref):
        from ...chaos.section import solve_p_psi

        roots = solve_p_psi(self.P.params, self.P.h, float(z[0]), float(z[1]), 0.0 if br == "0" else math.pi)
        x = np.zeros(4)
        x[fields.THETA], x[fields.PTHETA] = z[0], z[1]
        x[fields.PSI] = 0.0 if br == "0" else math.pi
        x[fields.PPSI] = roots[int(np.argmin(abs(roots - pref)))]
        return x

    def step4(self, x):
        y, t = self.P.full4(x)
        return y, ("0" if math.cos(y[fields.PSI]) > 0 else "pi"), t

    def __call__(self, z, br, pref):
        y, b, _ = self.step4(self.lift(z, br, pref))
        return np.array([y[fields.THETA], y[fields.PTHETA]]), b

    def jac(self, z, br, pref, eps=1e-7):
        D = np.empty((2, 2))
        for j in range(2):
            dz = np.zeros(2)
            dz[j] = eps
            D[:, j] = (self(z + dz, br, pref)[0] - self(z - dz, br, pref)[0]) / (2 * eps)
        return D


def float_cycle(P: FloatMap, theta_guess: float, period: int, window: float = 0.02, eps: float = 1e-7) -> dict:
    """A symmetric period-p orbit of P through x0 = (theta*, 0) on Fix(R), p even: x_{p/2} = P^{p/2}(x0) lies on
    Fix(R) too (R(x_i) = x_{p-i}), so theta* is a zero of pbar_theta(P^{p/2}(theta, 0)) (bisection on the window).
    Returns the 4-D orbit points x_0 .. x_{p-1}, branches, return times, the float DP_i at x_i (central
    differences, step eps), DP^p = DP_{p-1} ... DP_0, e_u(x0) (its unstable eigenvector, theta-component > 0),
    mu_u, det, the frames e_u^i = DP_{i-1} e_u^{i-1} (normalised), e_s^i (R e_u(x0) pulled back from x0 = x_p)
    and the per-return stretches lam_i = |DP_i e_u^i|, sig_i = |DP_i e_s^i| (product mu_u and 1 / mu_u)."""
    if period % 2:
        raise ProofFailure("float_cycle: only even periods (x_{p/2} on Fix(R)) are handled")
    M = NearMap(P)

    def half(th):
        x = P.lift([th, 0.0])
        for _ in range(period // 2):
            x = P.full4(x)[0]
        return x[fields.PTHETA]

    a, b = theta_guess - window, theta_guess + window
    th = _bisect_zero(half, a, b, f"float_cycle: no sign change of pbar_theta at return {period // 2} on "
                      f"[{a:.6g}, {b:.6g}]")
    xs, brs, ts = [P.lift([th, 0.0])], [P.branch], []
    for _ in range(period):
        y, br, t = M.step4(xs[-1])
        xs.append(y)
        brs.append(br)
        ts.append(t)
    closure = float(np.hypot(xs[-1][fields.THETA] - th, xs[-1][fields.PTHETA]))
    xs, brs = xs[:period], brs[:period]
    zs = [np.array([x[fields.THETA], x[fields.PTHETA]]) for x in xs]
    DPs = [M.jac(z, br, x[fields.PPSI], eps) for z, br, x in zip(zs, brs, xs)]
    Dp = np.eye(2)
    for D in DPs:
        Dp = D @ Dp
    mu, eu = unstable_eigen(Dp)
    eus = [eu]
    for D in DPs[:-1]:
        eus.append(unit(D @ eus[-1]))
    ess = [R2 @ eu]  # e_s(x0) = R e_u(x0) (x0 symmetric); pulled back x_p = x0 -> x_{p-1} -> ... -> x_1
    for D in reversed(DPs[1:]):
        ess.append(unit(np.linalg.solve(D, ess[-1])))
    ess = [ess[0]] + ess[1:][::-1]
    lam = [float(np.linalg.norm(D @ u)) for D, u in zip(DPs, eus)]
    sig = [float(np.linalg.norm(D @ s)) for D, s in zip(DPs, ess)]
    return {"theta": th, "xs": xs, "zs": zs, "branches": brs, "times": ts, "closure": closure, "DPs": DPs,
            "DPp": Dp, "mu_u": mu, "det": float(np.linalg.det(Dp)),
            "trace": float(np.trace(Dp)), "e_u": eus, "e_s": ess, "lam": lam, "sig": sig,
            "angles_deg": [float(np.degrees(np.arccos(min(1.0, abs(float(np.dot(u, s))))))) for u, s in
                           zip(eus, ess)]}


def sizes(lam, sig, L, qu, qs, Lw=None):
    """Half-lengths l_j (exit) and half-widths w_j (entry) of N_1 .. N_k from the frame stretches lam_j = |DP e_u^j|
    and sig_j = |DP e_s^j| (unit frame vectors, link j -> j+1): l_1 = L, l_{j+1} = min(L, lam_j l_j / qu) (constant
    where the map stretches enough, shrinking where it does not); w_k = l_k (Nk symmetric), backwards
    w_j = min(L, w_{j+1} / (qs sig_j)), so that every link has the margin qu in (b) and qs in (a)."""
    k = len(lam) + 1
    Lw = L if Lw is None else Lw
    ls = [L]
    for j in range(k - 1):
        ls.append(min(L, lam[j] * ls[-1] / qu))
    ws = [ls[-1]]
    for j in reversed(range(k - 1)):
        ws.append(min(Lw, ws[-1] / (qs * sig[j])))
    return ls, ws[::-1]


def _float_s_star(P: FloatMap, x0, eu, s_guess: float, n_exc: int) -> float:
    """s with pbar_theta(P^n_exc(x0 + s e_u)) = 0 near s_guess (bisection on s_guess (1 -+ 1e-4), 4-D states)."""
    def end(s):
        x = P.lift(x0 + s * eu)
        for _ in range(n_exc):
            x = P.full4(x)[0]
        return x[fields.PTHETA]

    return _bisect_zero(end, s_guess * (1 - 1e-4), s_guess * (1 + 1e-4),
                        f"design: no sign change of pbar_theta at return {n_exc} around s* = {s_guess:.6g}")


def _bisect_zero(fn, a: float, b: float, fail: str) -> float:
    """The float designs' root: 60 bisections of a sign change of fn on [a, b] (ProofFailure(fail) if there is
    none: the design's guess is off)."""
    fa = fn(a)
    if fa * fn(b) > 0:
        raise ProofFailure(fail)
    for _ in range(60):
        c = 0.5 * (a + b)
        fc = fn(c)
        if (fc > 0) == (fa > 0):
            a, fa = c, fc
        else:
            b = c
    return 0.5 * (a + b)

