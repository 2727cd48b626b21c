"""The prover of a horseshoe of the section map on Fig 4's level: covering relations
(Zgliczynski & Gidea 2004) along the homoclinic orbit of the saddle x0 of statement 11, one return per flight.

What is proved (docs/nonintegrability.md, statement 12): at exact (m, mu, gamma, delta, lambdabar) and level h, the
section map P of Sigma+ = {sin psi = 0, d sin psi/dt > 0} on {Hbar = h}, in the section coordinates
(theta, pbar_theta) (psi = 0 or pi: each set's branch; pbar_psi the root of the level in the set's Newton box), has
h-sets (parallelograms
N = c + A [-1, 1]^2, first column of A the exit, second the entry direction) with
    N0 =>_P N0,   N0 =>_P N1 =>_P N2 => ... =>_P Nk,
N0 and Nk symmetric (centre on Fix(R) = {pbar_theta = 0}, A = [a, R a], R = diag(1, -1): R(N)^T = N), N0 disjoint
from N1 .. Nk and from R(N1) .. R(N_{k-1}).  Reversibility (R P R = P^-1) turns the chain into back-coverings
    Nk = R(Nk)^T <=_P R(N_{k-1})^T <=_P ... <=_P R(N1)^T <=_P R(N0)^T = N0
(lemma: N =>_P M implies R(M)^T <=_P R(N)^T), so N0 has two closed chains, of lengths 1 and L = 2k, and the
covering-chain theorem gives, for every sequence of these loops, an orbit realising it; coding the visits to N0 gives
a semiconjugacy onto the shift of concatenations of the blocks "1" and "1 0^(L-1)": h_top(P) >= log rho,
rho the largest root of x^L = x^(L-1) + 1.

The covering N =>_P M (dimension 2, one exit direction) is checked by the sufficient conditions of Zgliczynski &
Gidea (their theorem for u = 1 with the straight-line homotopy): in M's coordinates y = A_M^-1 (x - c_M), (a) the
image of N meets {|y_u| <= 1} only inside {|y_s| < 1}, (b) the images of N's exit edges {y_u = -1}, {y_u = +1} lie in
{y_u < -1} and {y_u > 1} (or the reverse), P continuous on N.  N is cut into pieces X = c_X + A_X [-1, 1]^2
(a product grid in N's coordinates); each is flown ONE return (periodic.piece_return: the centre and the piece,
validated C^1 Lohner flights with the phases of statement 11 and the crossing enclosed), and its image is enclosed by
the mean-value form P(X) in P(c_X) + [DP(X)] A_X [-1, 1]^2.

Method of the design (float, heyoka; only chooses where to look): the W^u point z_0 = x0 + s* e_u whose 8th image lies
on Fix(R), pulled back m times along the local W^u (c_1 = x0 + s* mu_u^-m e_u, to second order); the chain c_{j+1} = P(c_j) is then recomputed with the validated
thin flights (their midpoints: 128 bits), c_1 shifted along e_u by one Newton step so that P^(k-1)(c_1) lies on
Fix(R); frames: e_u^j (W^u tangents, pushed forward by DP) and e_s^j (W^s tangents, R e_u^k pulled back), so that DP
maps frame to frame; sizes by the rule of `sizes`.

Over a lambdabar interval (`widen`): the point certificate's sets move with lambdabar along the chain's motion v_j,
every condition checked for all lambdabar of the interval at once (statement 12 on a lambdabar interval).
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from ..core.eigen import fix_phase
from ..core.errors import ParameterError
from ..core.tolerances import FIXED_POINT_SEARCH_TOL, HORSESHOE_CENTRE_TOL, PROOF_STEP_TOL
from ..generated import validated as gen
from . import ball, fields, periodic, section_return
from .search import ProofFailure, ProofResult, run_checked, stored
from .theorem import section_horseshoe_theorem

FORMAT = "magrod-proof-certificate/1"
KIND = "section_horseshoe"
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
    #: the step tolerance of the centres' flights (their enclosures must resolve the sets: periodic.piece_return)
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

    from ..core import tolerances

    try:
        data = json.loads(resources.files(__package__).joinpath("designs", f"{name}.json").read_text())
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
    for f in sorted(resources.files(__package__).joinpath("designs").iterdir(), key=lambda f: f.name):
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


# --------------------------------------------------------------------------------------------------------------
# float design (heyoka, reduced chart): only chooses where to look
# --------------------------------------------------------------------------------------------------------------
class FloatMap:
    """P on (theta, pbar_theta) in float64 (heyoka, tol 1e-15): the first positive crossing of sin psi = 0 after
    t > 1e-3; a point (theta, pbar_theta) is lifted to the branch psi = 0 or pi (`branch`, that of x0) with pbar_psi
    the level's root of index `root` (ascending; -1: the largest, the Fig 4 choice)."""

    def __init__(self, p: fields.ExactParams, h, branch: str = "0", root: int = -1):
        self.branch, self.root = branch, root
        self.psi = {"0": 0.0, "pi": math.pi}[branch]
        import heyoka as hy

        from ..core import systems
        from ..core.params import RodParams

        self.params, self.h = RodParams(*p.floats()), float(h)
        v = hy.make_vars(*systems.STATE["reduced"])
        ev = hy.t_event(hy.sin(v[fields.PSI]), direction=hy.event_direction.positive)
        self.ta = systems.taylor(systems.system("reduced"), [1.0, 0.0, 0.0, 1.0], self.params.array(),
                                 t_events=[ev], tol=FIXED_POINT_SEARCH_TOL)

    def lift(self, z):
        from ..chaos.section import solve_p_psi

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


# --------------------------------------------------------------------------------------------------------------
# a symmetric periodic orbit of period p (Fig 4(c): no hyperbolic fixed point of P; float design only)
# --------------------------------------------------------------------------------------------------------------
class NearMap:
    """The float section map on (theta, pbar_theta) of a branch, pbar_psi the level's root nearest to a reference
    value (the orbit point's own: along a period-p orbit the root's index need not be constant)."""

    def __init__(self, P: FloatMap):
        self.P = P

    def lift(self, z, br, pref):
        from ..chaos.section import solve_p_psi

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


# --------------------------------------------------------------------------------------------------------------
# h-sets and pieces (exact data)
# --------------------------------------------------------------------------------------------------------------
def hset(c, A) -> dict:
    return {"c": [_q(v) for v in c], "A": [[_q(v) for v in row] for row in A]}


def set_data(s) -> tuple:
    c = [Fraction(v) for v in s["c"]]
    A = [[Fraction(v) for v in row] for row in s["A"]]
    return c, A


def grid_pieces(nu: int, ns: int) -> list:
    """The product grid of nu x ns pieces of [-1, 1]^2: [(yu, ys, hu, hs)] (centres and half sizes, dyadic if nu, ns
    are powers of two)."""
    out = []
    for i in range(nu):
        for j in range(ns):
            out.append((Fraction(2 * i + 1, nu) - 1, Fraction(2 * j + 1, ns) - 1, Fraction(1, nu), Fraction(1, ns)))
    return out


def piece_geometry(c, A, piece):
    """(c_X, A_X) of the piece (yu, ys, hu, hs) of N = c + A [-1, 1]^2: c_X = c + A (yu, ys), A_X = A diag(hu, hs)."""
    yu, ys, hu, hs = piece
    cX = [c[0] + A[0][0] * yu + A[0][1] * ys, c[1] + A[1][0] * yu + A[1][1] * ys]
    AX = [[A[0][0] * hu, A[0][1] * hs], [A[1][0] * hu, A[1][1] * hs]]
    return cX, AX


def t_approach(T: float, lead: Fraction) -> Fraction:
    return Fraction(math.floor((T - float(lead)) * 2**20), 2**20)


# --------------------------------------------------------------------------------------------------------------
# the covering conditions on a piece's image (the verifier has its own copy: kernel/horseshoe.py)
# --------------------------------------------------------------------------------------------------------------
def image_in(M, fl, AX):
    """y = A_M^-1 (P(c_X) - c_M) + A_M^-1 [DP(X)] A_X v, v in [-1, 1]^2: (off, G) as balls (off 2, G 2 x 2)."""
    cM, AM = M
    det = AM[0][0] * AM[1][1] - AM[0][1] * AM[1][0]
    Ai = [[AM[1][1] / det, -AM[0][1] / det], [-AM[1][0] / det, AM[0][0] / det]]
    Aib = [[ball.q(v) for v in row] for row in Ai]
    d = [fl["Pc"][0] - ball.q(cM[0]), fl["Pc"][1] - ball.q(cM[1])]
    off = [Aib[i][0] * d[0] + Aib[i][1] * d[1] for i in range(2)]
    DP = fl["DP"]
    DA = [[DP[i][0] * ball.q(AX[0][j]) + DP[i][1] * ball.q(AX[1][j]) for j in range(2)] for i in range(2)]
    G = [[Aib[i][0] * DA[0][j] + Aib[i][1] * DA[1][j] for j in range(2)] for i in range(2)]
    return off, G


def piece_checks(off, G, piece):
    """(a_ok, a_margin, edge images): (a') the piece's image lies in {|y_s| < 1} (stronger than (a): then the
    straight-line homotopy to (a y_u, 0) never meets M's entry edges);
    the images of the piece's parts of N's exit edges (y_u(N) = -1 and +1) as y_u balls."""
    U = ball.interval(-1, 1)
    yu = off[0] + G[0][0] * U + G[0][1] * U
    ys = off[1] + G[1][0] * U + G[1][1] * U
    lo_u, hi_u = ball.bounds(yu)
    lo_s, hi_s = ball.bounds(ys)
    del lo_u, hi_u
    inside = -1 < lo_s and hi_s < 1
    margin = float(1 - max(abs(lo_s), abs(hi_s)))
    edges = {}
    pu, _, hu, _ = piece
    if pu - hu == -1:
        edges[-1] = off[0] - G[0][0] + G[0][1] * U
    if pu + hu == 1:
        edges[1] = off[0] + G[0][0] + G[0][1] * U
    return bool(inside), margin, edges


# --------------------------------------------------------------------------------------------------------------
# the prover
# --------------------------------------------------------------------------------------------------------------
def prove(params: fields.ExactParams, h: Fraction, x0_theta: Fraction, settings: HorseshoeSettings | None = None, *,
          module=gen, progress=None) -> ProofResult:
    """Prove (or fail to prove) the covering-relation horseshoe of the section map (module docstring).

    Parameters
    ----------
    params, h : the exact parameters and level.
    x0_theta : float or Fraction
        Where the float search (periodic.float_fixed_point, within 0.02) looks for the symmetric saddle
        x0 = (theta*, psi, pbar_theta = 0) of P (statement 11; psi = 0, or pi with settings.branch = "pi": Fig 5,
        statement 13); N0 is centred at the float theta*.
    settings : HorseshoeSettings, optional
    module : the generated field module (a mutated copy for controls).
    progress : callable, optional

    Returns
    -------
    ProofResult
        ok, certificate (kind "section_horseshoe"), reason, checks, wall_time_s.
    """
    st = settings or HorseshoeSettings()
    run = _prove if st.period == 1 else _prove_cycle
    return run_checked(st.prec, lambda check: run(params, h, x0_theta, st, module, check,
                                                  progress or (lambda s: None)), flights=True)


def _frame_from(DPs, e_u1):
    """W^u tangents pushed forward and W^s tangents (R e_u^k) pulled back along float DP's; the stretches."""
    eus = [unit(e_u1)]
    for D in DPs:
        eus.append(unit(D @ eus[-1]))
    if eus[-1][1] < 0:
        eus[-1] = -eus[-1]
    ess = [R2 @ eus[-1]]
    for D in reversed(DPs):
        ess.append(unit(np.linalg.solve(D, ess[-1])))
    ess = ess[::-1]
    lam = [float(np.linalg.norm(D @ u)) for D, u in zip(DPs, eus[:-1])]
    sig = [float(np.linalg.norm(D @ s)) for D, s in zip(DPs, ess[:-1])]
    return eus, ess, lam, sig


def _mid_matrix(DP):
    return np.array([[float(v.mid()) for v in row] for row in DP])


def _chain_passes(fly_chain, c1, e_u1, x0, n_flights, st, say):
    """The chain by the validated centre flights fly_chain(c1, tol) -> (centres, pbar_psi, branches, flights), one
    pass per st.passes; after each pass but the last a Newton step along e_u^1 moves c_1 so that the chain's end
    lies on Fix(R) (with st.stop_frac, the passes stop once it is within stop_frac of the end set's width).
    Returns the last pass's chain, its frames (e_u, e_s, stretches) and the end residual of every pass."""
    passes = []
    sched = [st.tol if kind == "tol" else st.tol_thin for kind in st.passes]
    for n_pass, tl in enumerate(sched):
        say(f"chain pass {n_pass + 1} ({n_flights} centre flights, tol {tl:g})")
        cs, pcs, brs, fls = fly_chain(c1, tl)
        DPs = [_mid_matrix(f["DPc"]) for f in fls]
        eus, ess, lam, sig = _frame_from(DPs, e_u1)
        delta = float(fls[-1]["Pc"][1].mid())
        passes.append(delta)
        if n_pass == len(sched) - 1:
            break
        if st.stop_frac and len(set(sched[n_pass:])) == 1:
            d_ = float(np.hypot(float(cs[0][0]) - x0[0], float(cs[0][1])))
            w_end = sizes(lam, sig, d_ * st.l1_frac, st.qu, st.qs, st.w_cap * d_ * st.l1_frac)[1][-1]
            if abs(delta) < st.stop_frac * w_end:
                say(f"  pbar_theta at the end {delta:.3g} < {st.stop_frac:g} w_k: the chain passes stop")
                break
        v = eus[0]
        for D in DPs:
            v = D @ v
        shift = -delta / v[1]
        say(f"  pbar_theta at the end {delta:.3g}: shift {shift:.3g} along e_u")
        c1 = [dyadic_of(c1[0] + Fraction(shift) * Fraction(eus[0][0])),
              dyadic_of(c1[1] + Fraction(shift) * Fraction(eus[0][1]))]
    return cs, pcs, brs, fls, (eus, ess, lam, sig), passes


def _branch_boxes(pars, h, sets, p_rad, module, check) -> dict:
    """{i: B}: the level's root pbar_psi unique in B = [p_c - p_rad, p_c + p_rad] over each set's hull."""
    branch = {}
    for i, sd in enumerate(sets):
        c, A = set_data(sd)
        _, B, ok = periodic.level_newton_section(pars, h, *_hull(c, A), Fraction(sd["p_c"]), p_rad, module,
                                                 sd["branch"])
        check(f"N{i} branch box", ok, "pbar_psi unique in the branch box over the set's hull")
        branch[i] = B
    return branch


def _fly_sets(sets, n_src, grids, fly, thin_of, branch, check, say):
    """Every piece of the sources N_0 .. N_(n_src - 1) flown one return (fly: periodic.piece_return with the
    prover's settings; thin_of[i], when given, is N_i's centre flight already taken, reused for a one-piece set), its
    level and positive return checked.  Returns the certificate's flight records and images[(i, n)] = (piece,
    A_X, flight) for _check_links."""
    flights, images = [], {}
    for i in range(n_src):
        cN, AN = set_data(sets[i])
        pieces = grid_pieces(*grids[i])
        recs = []
        for n, pc in enumerate(pieces):
            say(f"set N{i}: piece {n + 1}/{len(pieces)}")
            cX, AX = piece_geometry(cN, AN, pc)
            ppc = Fraction(sets[i]["p_c"])
            fl = fly(cX, AX, ppc, sets[i]["branch"], thin=thin_of.get(i) if len(pieces) == 1 else None)
            check(f"N{i} piece {n} level", fl["level_ok"] and ball.subset(fl["ppsi_hull"], branch[i]),
                  "pbar_psi unique in its Newton box over the piece, inside the set's branch box")
            check(f"N{i} piece {n} positive return", ball.positive(fl["gdot_thin"]) and ball.positive(fl["gdot_box"]),
                  f"d(sin psi)/dt = {fl['gdot_box']} > 0 at the crossing")
            recs.append({"piece": [_q(v) for v in pc], "p_c": _q(ppc), "t_a": _q(fl["t_a"]),
                         "steps": {kk: [[ball.decimal(s) for s in ph] for ph in vv] for kk, vv in fl["steps"].items()},
                         "n_steps": sum(len(ph) for vv in fl["steps"].values() for ph in vv),
                         "enclosures": {"Pc": [stored(v) for v in fl["Pc"]],
                                        "DP": [[stored(v) for v in row] for row in fl["DP"]],
                                        "ppsi_box": stored(fl["ppsi_box"])}})
            images[(i, n)] = (pc, AX, fl)
        flights.append({"set": i, "grid": list(grids[i]), "pieces": recs})
    return flights, images


def _symmetric_and_disjoint(sets, check) -> None:
    """N0 and the end set N_last symmetric (R(N)^T = N), N0 disjoint from every other set and from the reversed
    copies R(N_j) of the inner ones (exact rationals: the coding by visits to N0 is then well defined), every A
    nondegenerate."""
    last = len(sets) - 1
    for idx in (0, last):
        c, A = set_data(sets[idx])
        check(f"N{idx} symmetric", c[1] == 0 and A[0][1] == A[0][0] and A[1][1] == -A[1][0],
              "centre on Fix(R) and A = [a, R a]: R(N)^T = N")
    polys = [_vertices(*set_data(s)) for s in sets]
    for j in range(1, last + 1):
        other = sets[j]["branch"] != sets[0]["branch"]
        check(f"N0, N{j} disjoint", other or _disjoint(polys[0], polys[j]), "another branch of psi, or a separating "
              "axis (exact rationals)")
    for j in range(1, last):
        other = sets[j]["branch"] != sets[0]["branch"]
        check(f"N0, R(N{j}) disjoint", other or _disjoint(polys[0], [(x, -y) for x, y in polys[j]]),
              "another branch of psi (R keeps it), or a separating axis (exact)")
    for i, s in enumerate(sets):
        c, A = set_data(s)
        check(f"N{i} nondegenerate", A[0][0] * A[1][1] - A[0][1] * A[1][0] != 0, "det A != 0")


def _fliers(P: FloatMap, pars, h, fld, st: HorseshoeSettings, module, check):
    """The provers' validated flights with the settings st: fly(c, A, pc, branch, ...) one return of the set
    c + A [-1, 1]^2 (periodic.piece_return, t_a from the float return time), pc_of(c) the float level root at c,
    orbit(c1, pc1, n, tol_thin, name) the centres, pbar_psi, branches ("0": cos psi > 0, "pi": cos psi < 0) and
    flights of n validated returns from c1 (the centres: the flights' 128-bit midpoints)."""
    zero = [[Fraction(0), Fraction(0)], [Fraction(0), Fraction(0)]]

    def fly(c, A, pc, br, steps=None, box=True, tol_thin=None, thin=None):
        x4 = np.zeros(4)
        x4[fields.THETA], x4[fields.PTHETA], x4[fields.PPSI] = float(c[0]), float(c[1]), float(pc)
        x4[fields.PSI] = 0.0 if br == "0" else math.pi
        T = P.full4(x4)[1]
        t_a = t_approach(T, st.lead)
        fl = periodic.piece_return(pars, h, fld, c, A, pc, st.p_rad, t_a, st.lead, t1=st.t1, order=st.order,
                                   tol=st.tol, tol_thin=tol_thin or st.tol_thin, steps=steps, newton=st.newton,
                                   box=box, thin=thin, branch=br, module=module,
                                   integrator=section_return.integrator(st.integrator),
                                   thin_integrator=section_return.integrator(st.thin_integrator))
        fl["t_a"] = t_a
        return fl

    def pc_of(c):
        return dyadic(float(P.lift([float(c[0]), float(c[1])])[fields.PPSI]), 50)

    def orbit(c1, pc1, n, tol_thin, name):
        cs, pcs, brs, fls = [c1], [pc1], [st.branch], []
        for j in range(n):
            fl = fly(cs[-1], zero, pcs[-1], brs[-1], box=False, tol_thin=tol_thin)
            check(f"{name} flight {j + 1}", fl["level_ok"], "the level's Newton at the centre")
            cp = fl["cospsi_thin"]
            check(f"{name} flight {j + 1} branch", ball.excludes_zero(cp), f"cos psi = {cp} at the crossing")
            fls.append(fl)
            cs.append([dyadic_of(fl["Pc"][0].mid()), dyadic_of(fl["Pc"][1].mid())])
            pcs.append(dyadic_of(fl["ppsi_thin"].mid(), 60))
            brs.append("0" if ball.positive(cp) else "pi")
        return cs, pcs, brs, fls

    return fly, pc_of, orbit


def _prover_field(p, module, st: HorseshoeSettings):
    """The chart field the prover flies.  With the Taylor-model integrator its Taylor coefficients come from Newton's
    iteration on series, as the verifier's do (kernel/horseshoe_sets.py): the Taylor-model remainder is validated
    on the box's own coefficient balls, and Picard's balls (taylor.py's default, narrower on some boxes) let the
    prover accept a step that the verifier's replay on Newton's balls rejects (seen: Fig 4(b)'s N1, the variational
    remainder).  taylor.py's a priori enclosure does not depend on them that way, so its flights keep Picard's."""
    import dataclasses

    fld = fields.chart_field(p, module)
    if "taylor_model" in (st.integrator, st.thin_integrator):
        fld = dataclasses.replace(fld, series="newton")
    return fld


def _chain_sets(cs, pcs, brs, eus, ess, ls, ws) -> list:
    """The chain's h-sets (exact dyadic data): N_j = c_j + [l_j e_u^j, w_j e_s^j] [-1, 1]^2 for the inner centres,
    the last one symmetric, c + l [e_u, R e_u] (its centre is on Fix(R))."""
    out = []
    for j in range(len(cs) - 1):
        u, s = eus[j], ess[j]
        out.append(hset(cs[j], [[dyadic(ls[j] * u[0]), dyadic(ws[j] * s[0])],
                                [dyadic(ls[j] * u[1]), dyadic(ws[j] * s[1])]]))
        out[-1]["p_c"], out[-1]["branch"] = _q(pcs[j]), brs[j]
    ak = [dyadic(ls[-1] * eus[-1][0]), dyadic(ls[-1] * eus[-1][1])]
    out.append(hset(cs[-1], [[ak[0], ak[0]], [ak[1], -ak[1]]]))
    out[-1]["p_c"], out[-1]["branch"] = _q(pcs[-1]), brs[-1]
    return out


def _prove(p, h, x0_theta, st, module, check, say) -> dict:
    pars = p.balls()
    fld = _prover_field(p, module, st)
    P = FloatMap(p, h, st.branch, st.root)
    say("float search for x0")
    th_f = periodic.float_fixed_point(p, h, float(x0_theta), root=st.root, branch=st.branch)[0]
    x0_theta = dyadic(float(th_f), 53)
    x0 = np.array([float(x0_theta), 0.0])
    say("float design")
    fd = float_design(P, x0, st.m_back, st.s_star, st.n_exc)
    k = st.n_exc + st.m_back + 1  # N_1 at z_-m .. N_k at z_n_exc

    fly, pc_of, orbit = _fliers(P, pars, h, fld, st, module, check)

    def chain(c1, tol_thin):
        return orbit(c1, pc_of(c1), k - 1, tol_thin, "chain")

    c1 = [x0_theta + Fraction(fd["t"]) * Fraction(fd["e_u0"][0]), Fraction(fd["t"]) * Fraction(fd["e_u0"][1])]
    c1 = [dyadic_of(v) for v in c1]
    # the chain by the validated centre flights; Newton steps along e_u^1 put P^(k-1)(c_1) on Fix(R): two passes
    # at the design tolerance, the last at tol_thin (its flights are the certificate's centre flights)
    cs, pcs, brs, fls, (eus, ess, lam, sig), passes = _chain_passes(chain, c1, fd["e_u0"], x0, k - 1, st, say)
    resid = passes[-1]
    cs[-1] = [dyadic_of(fls[-1]["Pc"][0].mid()), Fraction(0)]
    dist = float(np.hypot(float(cs[0][0]) - x0[0], float(cs[0][1])))
    L = dist * st.l1_frac
    ls, ws = sizes(lam, sig, L, st.qu, st.qs, st.w_cap * L)
    check("end on Fix(R)", abs(resid) < ws[-1] / 4,
          f"pbar_theta(P^(k-1)(c_1)) = {resid:.3g} after the Newton shift, against the size {ws[-1]:.3g} of Nk")
    # the sets (exact dyadic data)
    a0 = [dyadic(dist * st.l0_frac * fd["e_u0"][0]), dyadic(dist * st.l0_frac * fd["e_u0"][1])]
    sets = [hset([dyadic_of(x0_theta, 62), Fraction(0)], [[a0[0], a0[0]], [a0[1], -a0[1]]])]
    sets[0]["p_c"], sets[0]["branch"] = _q(pc_of([x0_theta, Fraction(0)])), st.branch
    sets += _chain_sets(cs, pcs, brs, eus, ess, ls, ws)
    # the branch boxes: the level's root unique in [p_c - p_rad, p_c + p_rad] over each set's hull
    branch = _branch_boxes(pars, h, sets, st.p_rad, module, check)
    # links, pieces, flights
    links = [(0, 0), (0, 1)] + [(j, j + 1) for j in range(1, k)]
    grids = {i: (1, 1) for i in range(k)}
    grids.update(st.pieces or {})
    # the chain's flight from c_i is N_i's centre flight (one piece: c_X = c_i)
    flights, images = _fly_sets(sets, k, grids, fly, {i: fls[i - 1] for i in range(1, k)}, branch, check, say)
    link_rec = _check_links(sets, links, grids, images, branch, check, say)
    # symmetry, disjointness, entropy
    _symmetric_and_disjoint(sets, check)
    Lloop = 2 * k
    rho = entropy_root_lower(Lloop)
    digest = fields.source_digest(module)
    check("field_is_derived", digest == fields.source_digest(gen),
          "the vector field is the derive-generated generated/validated.py (SHA-256 of its source)")
    pj = p.as_json()
    return {
        "format": FORMAT, "kind": KIND,
        "theorem": section_horseshoe_theorem(pj, _q(h), k, Lloop, _q(rho)),
        "params": pj, "level": _q(h), "settings": st.as_json(), "field_digest": digest,
        "sets": sets, "links": [[i, j] for i, j in links], "flights": flights, "link_margins": link_rec,
        "loop_length": Lloop, "entropy": {"rho_lower": _q(rho), "log_rho_lower": math.log(float(rho))},
        "hypotheses_symbolic": ["reversor_reduced", "validated_fields", "full_ham_nondim"],
        "design": {"x0_theta": _q(x0_theta), "s_star": fd["s_star"], "m_back": st.m_back, "dist_c1": dist,
                   "L": L, "l": ls, "w": ws, "stretch_u": lam, "stretch_s": sig, "end_residual": resid, "end_residual_passes": passes,
                   "angles_deg": [float(np.degrees(np.arccos(min(1.0, abs(float(np.dot(u, s))))))) for u, s in
                                  zip(eus, ess)]},
    }


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


def _prove_cycle(p, h, x0_theta, st, module, check, say) -> dict:
    """The horseshoe around a symmetric period-p orbit of P (st.period = p > 1; module docstring of
    research/fig4c_horseshoe_design.py for the design).  Sets (certificate order): N0 (symmetric, at x0), the
    cycle sets N1 .. N(p-1) at x_1 .. x_(p-1), the excursion sets N(p) .. N(n-1) (C_1 .. C_k, C_1 on W^u(x0) at
    distance d, C_(j+1) = P(C_j), C_k symmetric).  Links: N_i => N_(i+1) (i < p - 1), N(p-1) => N0,
    N(p-1) => N(p), N_j => N_(j+1) (p <= j < n - 1).  Loops through N0: the cycle (length p) and, closed by the
    reversed chain, L = 2 (n - 1) = 2 (p + k - 1); the coding of the visits to N0 gives the blocks 1 0^(p-1) and
    1 0^(L-1): h_top >= log rho, x^L = x^(L-p) + 1."""
    per = st.period
    pars = p.balls()
    fld = _prover_field(p, module, st)
    P = FloatMap(p, h, st.branch, st.root)
    say(f"float search for the period-{per} orbit")
    cyc = float_cycle(P, float(x0_theta), per)
    x0_theta = dyadic(cyc["theta"], 53)
    x0 = np.array([float(x0_theta), 0.0])

    fly, pc_of, orbit = _fliers(P, pars, h, fld, st, module, check)

    # the cycle: x_0 .. x_(p-1) by validated returns from x0 (x_p = P^p(x0) closes on x0 up to the float theta*)
    say(f"cycle: {per} centre flights (tol {st.tol_thin:g})")
    ccs, cpcs, cbrs, cfls = orbit([dyadic_of(x0_theta, 62), Fraction(0)], pc_of([x0_theta, Fraction(0)]), per,
                                  st.tol_thin, "cycle")
    close = float(np.hypot(float(ccs[-1][0]) - x0[0], float(ccs[-1][1])))
    check("cycle closes", close < 1e-12 and cbrs[-1] == st.branch,
          f"|P^{per}(x0) - x0| = {close:.3g} (float theta*) on x0's branch")
    ccs, cpcs, cbrs = ccs[:per], cpcs[:per], cbrs[:per]
    CD = [_mid_matrix(f["DPc"]) for f in cfls]
    Dp = np.eye(2)
    for D in CD:
        Dp = D @ Dp
    mu, eu = unstable_eigen(Dp)
    ceu = [eu]
    for D in CD[:-1]:
        ceu.append(unit(D @ ceu[-1]))
    ces = [R2 @ eu]
    for D in reversed(CD[1:]):
        ces.append(unit(np.linalg.solve(D, ces[-1])))
    ces = [ces[0]] + ces[1:][::-1]
    clam = [float(np.linalg.norm(D @ u)) for D, u in zip(CD, ceu)]
    csig = [float(np.linalg.norm(D @ s)) for D, s in zip(CD, ces)]
    say(f"  mu_u(DP^{per}) = {mu:.6g}, stretches {[round(v, 3) for v in clam]}")
    check("cycle hyperbolic (design)", abs(mu) > st.q_cycle ** per,
          f"|mu_u(DP^p)| = {abs(mu):.4g} > q_cycle^p (the float design's margins around the cycle)")
    # the excursion chain C_1 .. C_k from C_1 = x0 + t e_u, t = s* mu_u^-m (m pull-backs by P^p)
    k = st.n_exc + per * st.m_back + 1
    s_star = _float_s_star(P, x0, eu, st.s_star, st.n_exc)
    t = s_star / abs(mu) ** st.m_back
    c1 = [dyadic_of(x0_theta + Fraction(t) * Fraction(eu[0])), dyadic_of(Fraction(t) * Fraction(eu[1]))]
    cs, pcs, brs, fls, (eus, ess, lam, sig), passes = _chain_passes(
        lambda c, tl: orbit(c, pc_of(c), k - 1, tl, "chain"), c1, eu, x0, k - 1, st, say)
    resid = passes[-1]
    cs[-1] = [dyadic_of(fls[-1]["Pc"][0].mid()), Fraction(0)]
    dist = float(np.hypot(float(cs[0][0]) - x0[0], float(cs[0][1])))
    L = dist * st.l1_frac
    ls, ws = sizes(lam, sig, L, st.qu, st.qs, st.w_cap * L)
    check("end on Fix(R)", abs(resid) < ws[-1] / 4,
          f"pbar_theta(P^(k-1)(C_1)) = {resid:.3g} after the Newton shift, against the size {ws[-1]:.3g} of C_k")
    # the cycle's sizes: l_(i+1) = lam_i l_i / q, w_(i+1) = q sig_i w_i from l_0 = w_0 = l0_frac d
    l0 = dist * st.l0_frac
    lc, wc = [l0], [l0]
    for i in range(per - 1):
        lc.append(clam[i] * lc[-1] / st.q_cycle)
        wc.append(st.q_cycle * csig[i] * wc[-1])
    a0 = [dyadic(l0 * eu[0]), dyadic(l0 * eu[1])]
    sets = [hset(ccs[0], [[a0[0], a0[0]], [a0[1], -a0[1]]])]
    sets[0]["p_c"], sets[0]["branch"] = _q(cpcs[0]), cbrs[0]
    for i in range(1, per):
        u, s = ceu[i], ces[i]
        sets.append(hset(ccs[i], [[dyadic(lc[i] * u[0]), dyadic(wc[i] * s[0])],
                                  [dyadic(lc[i] * u[1]), dyadic(wc[i] * s[1])]]))
        sets[-1]["p_c"], sets[-1]["branch"] = _q(cpcs[i]), cbrs[i]
    sets += _chain_sets(cs, pcs, brs, eus, ess, ls, ws)
    n = len(sets)
    branch = _branch_boxes(pars, h, sets, st.p_rad, module, check)
    links = cycle_links(per, n)
    grids = {i: (1, 1) for i in range(n - 1)}
    grids.update(st.pieces or {})
    thin_of = {i: cfls[i] for i in range(per)}
    thin_of.update({per + j: fls[j] for j in range(k - 1)})  # C_(j+1)'s centre flight is the chain's j-th
    flights, images = _fly_sets(sets, n - 1, grids, fly, thin_of, branch, check, say)
    link_rec = _check_links(sets, links, grids, images, branch, check, say)
    _symmetric_and_disjoint(sets, check)
    Lloop = 2 * (n - 1)
    rho = entropy_root_lower_cycle(per, Lloop)
    digest = fields.source_digest(module)
    check("field_is_derived", digest == fields.source_digest(gen),
          "the vector field is the derive-generated generated/validated.py (SHA-256 of its source)")
    pj = p.as_json()
    return {
        "format": FORMAT, "kind": KIND,
        "theorem": section_horseshoe_theorem(pj, _q(h), n - 1, Lloop, _q(rho), period=per),
        "params": pj, "level": _q(h), "settings": st.as_json(), "field_digest": digest,
        "sets": sets, "links": [[i, j] for i, j in links], "flights": flights, "link_margins": link_rec,
        "loop_length": Lloop, "loop_lengths": [per, Lloop],
        "entropy": {"rho_lower": _q(rho), "log_rho_lower": math.log(float(rho))},
        "hypotheses_symbolic": ["reversor_reduced", "validated_fields", "full_ham_nondim"],
        "design": {"x0_theta": _q(x0_theta), "period": per, "mu_u_cycle": mu, "cycle_closure": close,
                   "cycle_stretch_u": clam, "cycle_stretch_s": csig, "l_cycle": lc, "w_cycle": wc,
                   "s_star": s_star, "m_back": st.m_back, "dist_c1": dist, "L": L, "l": ls, "w": ws,
                   "stretch_u": lam, "stretch_s": sig, "end_residual": resid, "end_residual_passes": passes,
                   "angles_deg": [float(np.degrees(np.arccos(min(1.0, abs(float(np.dot(u, s))))))) for u, s in
                                  zip(ceu + eus, ces + ess)]},
    }


def cycle_links(period: int, n: int) -> list:
    """The links of the period-p graph on n sets (_prove_cycle; the verifier requires exactly these): the cycle
    N0 => N1 => ... => N(p-1) => N0, then N(p-1) => N(p) => ... => N(n-1)."""
    return ([(i, i + 1) for i in range(period - 1)] + [(period - 1, 0), (period - 1, period)]
            + [(j, j + 1) for j in range(period, n - 1)])


def _check_links(sets, links, grids, images, branch, check, say, shift=None) -> list:
    """The covering conditions (a'), (b), the image's psi branch and pbar_psi branch of every link i => j from the
    pieces' flights images[(i, n)] = (piece, A_X, flight); shift(i, j, fl): the flight with its "Pc" replaced by the
    enclosure to use against M = N_j (a lambdabar interval: widen).  Returns the link records."""
    link_rec = []
    for i, j in links:
        cM, AM = set_data(sets[j])
        amin, right, left = math.inf, [], []
        for n, pc in enumerate(grid_pieces(*grids[i])):
            _, AX, fl = images[(i, n)]
            off, G = image_in((cM, AM), fl if shift is None else shift(i, j, fl), AX)
            a_ok, margin, edges = piece_checks(off, G, pc)
            cps = [fl["cospsi_box"], fl["cospsi_thin"]]
            check(f"N{i} => N{j} piece {n} psi branch", all(ball.positive(v) if sets[j]["branch"] == "0" else
                                                             ball.negative(v) for v in cps),
                  f"cos psi = {cps[0]} at the crossing: the image lies on M's branch psi = {sets[j]['branch']} mod 2 pi")
            check(f"N{i} => N{j} piece {n} (a)", a_ok, f"image in M's coordinates: y_u = {off[0]} + ..., y_s ="
                  f" {off[1]} + G ...: stays in |y_s| < 1 (margin 1 - max |y_s| = {margin:.4g})")
            amin = min(amin, margin)
            if -1 in edges:
                left.append(edges[-1])
            if 1 in edges:
                right.append(edges[1])
            # the branch of pbar_psi: where the image lands in M it is M's root
            check(f"N{i} => N{j} piece {n} branch", ball.subset(fl["ppsi_box"], branch[j]),
                  f"pbar_psi of the image {fl['ppsi_box']} inside M's branch box {branch[j]} (unique root there)")
        o = 1 if ball.bounds(right[0])[0] > 1 else -1
        okb = all((ball.bounds(e)[0] > 1) if o == 1 else (ball.bounds(e)[1] < -1) for e in right) and \
            all((ball.bounds(e)[1] < -1) if o == 1 else (ball.bounds(e)[0] > 1) for e in left)
        bmin = min(min(abs(float(ball.bounds(e)[0 if o == 1 else 1])) for e in right),
                   min(abs(float(ball.bounds(e)[1 if o == 1 else 0])) for e in left))
        check(f"N{i} => N{j} (b)", okb, f"the exit edges' images beyond M's exit edges (orientation {o}), "
              f"min |y_u| = {bmin:.4g}")
        link_rec.append({"from": i, "to": j, "orientation": o, "a_margin": amin, "b_min_abs_yu": bmin})
        say(f"N{i} => N{j}: (a) margin {amin:.3g}, (b) min |y_u| {bmin:.3g}")
    return link_rec


def _hull(c, A):
    U = ball.interval(-1, 1)
    return (ball.q(c[0]) + ball.q(A[0][0]) * U + ball.q(A[0][1]) * U,
            ball.q(c[1]) + ball.q(A[1][0]) * U + ball.q(A[1][1]) * U)


def _vertices(c, A):
    return [(c[0] + A[0][0] * a + A[0][1] * b, c[1] + A[1][0] * a + A[1][1] * b) for a, b in
            ((1, 1), (1, -1), (-1, -1), (-1, 1))]


def _disjoint(P1, P2) -> bool:
    """Two convex polygons (exact vertices, in order) are disjoint iff some edge normal separates them strictly."""
    for poly in (P1, P2):
        n = len(poly)
        for i in range(n):
            (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % n]
            nx, ny = y2 - y1, x1 - x2
            a = [nx * x + ny * y for x, y in P1]
            b = [nx * x + ny * y for x, y in P2]
            if max(a) < min(b) or max(b) < min(a):
                return True
    return False


def entropy_root_lower(L: int, digits: int = 12) -> Fraction:
    """A rational rho_lo < rho, the largest root of x^L = x^(L-1) + 1 (f(rho_lo) < 0 for f = x^L - x^(L-1) - 1,
    f(2) > 0, f increasing on [1, 2] beyond its one critical point (L-1)/L < 1): by bisection on [1, 2]."""
    lo, hi = Fraction(1), Fraction(2)
    for _ in range(int(digits * 3.33) + 2):
        mid = (lo + hi) / 2
        if mid**L - mid ** (L - 1) - 1 < 0:
            lo = mid
        else:
            hi = mid
    return lo


# --------------------------------------------------------------------------------------------------------------
# a lambdabar interval: the point certificate's sets, moving with lambdabar
# --------------------------------------------------------------------------------------------------------------
def lambda_motion(p: fields.ExactParams, h, settings: dict, sets: list, DPs: list, dl: float = 1e-6) -> list:
    """The sets' motion v_j = d c_j / d lambdabar (float design; the verifier checks whatever it is): x0 moves along
    Fix(R) with v_0 = ((I - DP_0)^-1 dP/dlambdabar (x0))_theta, (0); along the chain v_{j+1} = DP_j v_j +
    dP/dlambdabar (c_j) (central differences of the float map, step dl), with v_1 = v_0 + alpha e_u^1 and alpha
    (exact linear solve: the recursion is affine in alpha) such that the end stays on Fix(R): v_k's pbar_theta = 0.
    DPs: the float DP of each N_j (j < k) about its centre.  Returns [(v_theta, v_ptheta)] as dyadic Fractions."""
    from dataclasses import replace

    k = len(sets) - 1
    maps = [FloatMap(replace(p, lam=p.lam + Fraction(s * dl)), h, settings.get("branch", "0"),
                     int(settings.get("root", -1))) for s in (1, -1)]
    cs = [np.array([float(x) for x in set_data(sd)[0]]) for sd in sets]
    dlP = [[Fraction(float(x)) for x in (maps[0](c) - maps[1](c)) / (2 * dl)] for c in cs[:k]]
    D = [[[Fraction(float(x)) for x in row] for row in M] for M in DPs]

    def mul(M, v):
        return [M[0][0] * v[0] + M[0][1] * v[1], M[1][0] * v[0] + M[1][1] * v[1]]

    I_D = [[1 - D[0][0][0], -D[0][0][1]], [-D[0][1][0], 1 - D[0][1][1]]]
    det = I_D[0][0] * I_D[1][1] - I_D[0][1] * I_D[1][0]
    v0 = [(I_D[1][1] * dlP[0][0] - I_D[0][1] * dlP[0][1]) / det, Fraction(0)]
    A1 = set_data(sets[1])[1]
    eu = [A1[0][0], A1[1][0]]

    def run(alpha):
        vs = [v0, [v0[0] + alpha * eu[0], v0[1] + alpha * eu[1]]]
        for j in range(1, k):
            w = mul(D[j], vs[-1])
            vs.append([w[0] + dlP[j][0], w[1] + dlP[j][1]])
        return vs

    a, b = run(Fraction(0))[-1][1], run(Fraction(1))[-1][1]
    vs = run(-a / (b - a))
    out = [(dyadic_of(v[0], 60), dyadic_of(v[1], 60)) for v in vs]
    out[0] = (out[0][0], Fraction(0))
    out[-1] = (out[-1][0], Fraction(0))
    return out


def disjoint_moving(P1, P2, dv, w) -> bool:
    """P1 and P2 + s dv are disjoint for every s in [-w, w] (convex polygons, exact): some axis (an edge normal of
    P1 or P2, or the normal of dv) separates P1 from the swept P2 (P2's vertices at s = +-w)."""
    axes = []
    for poly in (P1, P2):
        n = len(poly)
        for i in range(n):
            (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % n]
            axes.append((y2 - y1, x1 - x2))
    if dv[0] or dv[1]:
        axes.append((-dv[1], dv[0]))
    swept = [(x + s * dv[0], y + s * dv[1]) for x, y in P2 for s in (-w, w)]
    for nx, ny in axes:
        a = [nx * x + ny * y for x, y in P1]
        b = [nx * x + ny * y for x, y in swept]
        if max(a) < min(b) or max(b) < min(a):
            return True
    return False


def widen(cert: dict, lam_rad, *, module=gen, progress=None) -> ProofResult:
    """The point certificate's horseshoe for every lambdabar in [lam - lam_rad, lam + lam_rad] (statement 12 over
    an interval): each set moves with lambdabar, N_j(lambdabar) = c_j + v_j (lambdabar - lam) + A_j [-1, 1]^2
    (v_j: lambda_motion), so that it follows its chain; each piece's box is re-flown over the interval with
    lambdabar the fifth state (section_return.Moving), its centre at lam on the certificate's own steps, and the
    covering conditions hold for every lambdabar with P_s(X(s)) in P(c_X) + DP A_X [-1, 1]^2 + (dPds - v_M)
    (s - lam) in M's moving coordinates.  N0 and Nk stay symmetric (v_0, v_k on Fix(R)), the disjointness is
    checked for the swept sets.  Why the sets must move: fixed sets hold for |lambdabar - lam| < ~1e-16 only (the
    chain moves by ~87 per unit lambdabar per return against entry widths of 1.4e-13; measured at Fig 4(a)); moving,
    the limit is the growth of the 5-D box's derivative enclosures with its lambdabar extent |v| lam_rad
    (docs/nonintegrability.md, statement 12).

    Returns a ProofResult whose certificate has settings["lam_rad"] and a "v" per set.  Point certificates of
    period 1 only (lambda_motion follows x0 as a fixed point; a cycle certificate raises ParameterError)."""
    if int(cert.get("settings", {}).get("period", 1)) != 1:
        raise ParameterError("cert", "a certificate around a periodic orbit (period > 1) cannot be widened here")
    say = progress or (lambda s: None)
    w = ball.fraction(lam_rad)
    if w <= 0:
        raise ParameterError("lam_rad", f"must be > 0, got {lam_rad}")
    if cert.get("kind") != KIND or Fraction(cert["settings"].get("lam_rad", "0")) != 0:
        raise ParameterError("cert", "must be a point certificate of kind section_horseshoe")
    return run_checked(int(cert["settings"]["prec"]), lambda check: _widen(cert, w, module, check, say), flights=True)


def _widen(cert, w, module, check, say) -> dict:
    import copy

    from .section_return import Moving

    s = cert["settings"]
    p = fields.ExactParams(**{kk: Fraction(cert["params"][kk]) for kk in fields.PARAMS})
    h = Fraction(cert["level"])
    sets = copy.deepcopy(cert["sets"])
    k = len(sets) - 1
    fl_by = {int(f["set"]): f for f in cert["flights"]}
    DPs = [np.mean([_mid_matrix([[ball.from_json(x) for x in row] for row in r["enclosures"]["DP"]])
                    for r in fl_by[i]["pieces"]], axis=0) for i in range(k)]
    say("the sets' motion (float)")
    vs = lambda_motion(p, h, s, sets, DPs)
    for sd, v in zip(sets, vs):
        sd["v"] = [_q(x) for x in v]
    brs = [sd.get("branch", "0") for sd in sets]
    for name, idx in (("N0", 0), (f"N{k}", k)):
        check(f"{name} moves on Fix(R)", vs[idx][1] == 0, "v's pbar_theta = 0: the set stays symmetric")
    pars0, fld0 = p.balls(), fields.chart_field(p, module)
    parsL = fields.parameter_balls(p, w)
    Lam = parsL[fields.LAM]
    fldL = fields.lam_state_field(p, module)
    if "taylor_model" in (s.get("integrator"), s.get("thin_integrator")):  # Newton's coefficients, as the verifier
        import dataclasses                                                 # (see _prover_field)

        fld0, fldL = (dataclasses.replace(f, series="newton") for f in (fld0, fldL))
    Dl = Lam - ball.q(p.lam)
    prad = Fraction(s["p_rad"])
    branch = {}
    for i, sd in enumerate(sets):
        c, A = set_data(sd)
        th, pt = _hull(c, A)
        th, pt = th + ball.q(vs[i][0]) * Dl, pt + ball.q(vs[i][1]) * Dl
        _, B, ok = periodic.level_newton_section(parsL, h, th, pt, Fraction(sd["p_c"]), prad, module, brs[i])
        check(f"N{i} branch box", ok, "pbar_psi unique in the branch box over the set's hull swept over lambdabar")
        branch[i] = B
    links = [(0, 0), (0, 1)] + [(j, j + 1) for j in range(1, k)]
    grids, images, flights = {}, {}, []
    for i in range(k):
        cN, AN = set_data(sets[i])
        grids[i] = tuple(fl_by[i]["grid"])
        mv = Moving(tuple(parsL), fldL, Lam, p.lam, vs[i])
        recs = []
        for n, (pc, r) in enumerate(zip(grid_pieces(*grids[i]), fl_by[i]["pieces"])):
            check(f"N{i} piece {n} geometry", [Fraction(x) for x in r["piece"]] == list(pc), "the grid's piece")
            say(f"set N{i}: piece {n + 1}/{len(fl_by[i]['pieces'])} over lambdabar")
            cX, AX = piece_geometry(cN, AN, pc)
            t_a, ppc = Fraction(r["t_a"]), Fraction(r["p_c"])
            thin_steps = [[Fraction(x) for x in ph] for ph in r["steps"]["thin"]]
            fl = periodic.piece_return(pars0, h, fld0, cX, AX, ppc, prad, t_a, Fraction(s["lead"]),
                                       t1=Fraction(s["t1"]), order=int(s["order"]), tol=float(s["tol"]),
                                       steps={"thin": thin_steps}, newton=int(s["newton"]), thin_c1=False,
                                       integrator=section_return.integrator(s.get("integrator", "taylor")),
                                       thin_integrator=section_return.integrator(s.get("thin_integrator", "taylor")),
                                       branch=brs[i], moving=mv, module=module)
            check(f"N{i} piece {n} level", fl["level_ok"] and ball.subset(fl["ppsi_hull"], branch[i]),
                  "pbar_psi unique in its Newton box over the moving piece, inside the set's branch box")
            check(f"N{i} piece {n} positive return", ball.positive(fl["gdot_thin"]) and ball.positive(fl["gdot_box"]),
                  f"d(sin psi)/dt = {fl['gdot_box']} > 0 at the crossing")
            recs.append({"piece": r["piece"], "p_c": r["p_c"], "t_a": r["t_a"],
                         "steps": {kk: [[ball.decimal(x) for x in ph] for ph in vv] for kk, vv in fl["steps"].items()},
                         "n_steps": sum(len(ph) for vv in fl["steps"].values() for ph in vv),
                         "enclosures": {"Pc": [stored(v) for v in fl["Pc"]],
                                        "DP": [[stored(v) for v in row] for row in fl["DP"]],
                                        "dPds": [stored(v) for v in fl["dPds"]],
                                        "ppsi_box": stored(fl["ppsi_box"])}})
            images[(i, n)] = (pc, AX, fl)
        flights.append({"set": i, "grid": list(grids[i]), "pieces": recs})

    def shift(i, j, fl):  # P_s(c_X(s)) - c_M(s) = P(c_X) - c_M + (dPds - v_M)(s - lam)
        vM = [ball.q(x) for x in vs[j]]
        return {**fl, "Pc": tuple(fl["Pc"][a] + (fl["dPds"][a] - vM[a]) * Dl for a in range(2))}

    link_rec = _check_links([{**sd, "branch": b} for sd, b in zip(sets, brs)], links, grids, images, branch, check,
                            say, shift)
    for name, idx in (("N0", 0), (f"N{k}", k)):
        c, A = set_data(sets[idx])
        check(f"{name} symmetric", c[1] == 0 and A[0][1] == A[0][0] and A[1][1] == -A[1][0],
              "centre on Fix(R) and A = [a, R a]: R(N)^T = N")
    polys = [_vertices(*set_data(sd)) for sd in sets]
    for j in range(1, k + 1):
        dv = (vs[j][0] - vs[0][0], vs[j][1] - vs[0][1])
        check(f"N0, N{j} disjoint", brs[j] != brs[0] or disjoint_moving(polys[0], polys[j], dv, w),
              "another branch of psi, or a separating axis for every lambdabar (exact)")
    for j in range(1, k):
        dv = (vs[j][0] - vs[0][0], -vs[j][1] - vs[0][1])
        check(f"N0, R(N{j}) disjoint", brs[j] != brs[0] or
              disjoint_moving(polys[0], [(x, -y) for x, y in polys[j]], dv, w),
              "another branch of psi (R keeps it), or a separating axis for every lambdabar (exact)")
    digest = fields.source_digest(module)
    check("field_is_derived", digest == fields.source_digest(gen),
          "the vector field is the derive-generated generated/validated.py (SHA-256 of its source)")
    L = int(cert["loop_length"])
    out = {kk: cert[kk] for kk in ("format", "kind", "params", "level", "field_digest", "links", "loop_length",
                                    "entropy", "hypotheses_symbolic")}
    out["field_digest"] = digest
    out["theorem"] = section_horseshoe_theorem(cert["params"], cert["level"], k, L, cert["entropy"]["rho_lower"],
                                               _q(w))
    out["settings"] = {**s, "lam_rad": _q(w)}
    out["sets"], out["flights"], out["link_margins"] = sets, flights, link_rec
    out["design"] = {**cert["design"], "v": [[float(x) for x in v] for v in vs]}
    return out


def entropy_root_lower_cycle(p: int, L: int, digits: int = 12) -> Fraction:
    """A rational rho_lo < rho, the largest root of x^L = x^(L-p) + 1 (p < L: the blocks "1 0^(p-1)" and
    "1 0^(L-1)"; p = 1 is entropy_root_lower's polynomial): f = x^L - x^(L-p) - 1 has f(1) = -1 < 0, f(2) > 0 and
    f' = x^(L-p-1) (L x^p - (L-p)) > 0 for x >= 1, so one root in (1, 2): bisection, f(rho_lo) < 0 exactly."""
    if not 1 <= p < L:
        raise ValueError("need 1 <= p < L")
    lo, hi = Fraction(1), Fraction(2)
    for _ in range(int(digits * 3.33) + 2):
        mid = (lo + hi) / 2
        if mid**L - mid ** (L - p) - 1 < 0:
            lo = mid
        else:
            hi = mid
    return lo
