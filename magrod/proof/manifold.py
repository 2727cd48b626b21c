"""A rigorous local unstable manifold of the saddle-focus by cone conditions, and its boundary circle with C^1
bounds.

Coordinates.  y = (u, s) = V^{-1} (x - xhat), V = [Re v_u, Im v_u, Re v_s, Im v_s] an exact (rational) approximate
eigenbasis; in it the linearisation is close to diag(alpha I + beta J, -alpha I + beta' J) (J the 2 x 2 rotation
generator), whose symmetric parts are +-alpha I.  Euclidean norms |u|, |s| in these coordinates.

Block.  B = {|u| <= r_B, |s| <= rho}.  Over (an interval box containing) B, interval bounds of DG = V^{-1} Df V:
  m_u  <= lambda_min(sym G_uu),   M_s >= lambda_max(sym G_ss),   c_us >= ||G_us||,  c_su >= ||G_su||,
  N_uu >= ||G_uu||,  N_ss >= ||G_ss||,
and of the saddle in these coordinates, |u*| <= U, |s*| <= S (from the Krawczyk box).  Conditions, all strict:
  (C1) m_u r_B > N_uu U + c_us (rho + S)          outflow:  u . u' > 0 on |u| = r_B
  (C2) -M_s rho > c_su (r_B + U) + N_ss S         inflow:   s . s' < 0 on |s| = rho
  (C3) L (m_u - M_s) > c_su + L^2 c_us            cone {|ds| <= L |du|} is forward invariant for differences
  (C4) M_s + c_su / L < 0 and m_u - c_us L > 0     outside the cone |ds| grows backwards; inside |du| shrinks
  (C5) U < r_B and S < rho                        the saddle is inside B
(for two solutions y1, y2 in the convex B, (y1 - y2)' = M (y1 - y2) with M in the interval hull of DG(B), and
y' = M (y - y*) for one solution, so the same bounds control differences and the flow itself).

Theorem used (Wazewski's principle + cone conditions; P. Zgliczynski, J. Differential Equations 246 (2009)
1774-1819, and the classical Hadamard-Perron argument): W = {y in B : phi_t(y) in B for all t <= 0} is the graph
{(u, w(u)) : |u| <= r_B} of a function w with Lip(w) <= L, and W is contained in W^u(y*).  Sketch: for each u0
the disk {u0} x {|s| <= rho} has boundary in the (strict, by C2) exit set of the backward flow; if no point of it
stayed in B for all t <= 0 the exit map would retract the disk onto its boundary circle (impossible), so there is
one; two points of W with |ds| > L |du| would separate exponentially backwards (C3, C4), contradicting
boundedness, so w is L-Lipschitz; inside the cone |du| -> 0 backwards, so every point of W tends to y*.
Because w(u*) = s*, also |w(u)| <= S + L (|u| + U).  W is a piece of the analytic manifold W^u, so w is analytic in
|u| < r_B and ||Dw|| <= L there.

Boundary circle.  r < r_B (so the circle is interior): gamma(phi) = xhat + V (r e(phi), w(r e(phi))),
e(phi) = (cos phi, sin phi), is a point of W^u for every phi, with
  gamma(phi)  in xhat + V_u r e(phi) + V_s D(rho_eff),       rho_eff = min(rho, S + L (r + U)),
  gamma'(phi) in V_u r e'(phi) + V_s D(L r).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction

from flint import arb, arb_mat

from . import ball


def _sq(x):
    return x * x


def _abs_up(x) -> arb:
    """An exact upper bound of |x| over the ball x."""
    return ball.q(max(abs(v) for v in ball.bounds(x)))


def _sym_eig_bounds(M):
    """(lower bound of lambda_min, upper bound of lambda_max) of the symmetric part of a 2 x 2 interval matrix."""
    a, d = M[0][0], M[1][1]
    b = (M[0][1] + M[1][0]) * ball.q(Fraction(1, 2))
    mean = (a + d) * ball.q(Fraction(1, 2))
    half = (a - d) * ball.q(Fraction(1, 2))
    # an upper bound of the radius sqrt(half^2 + b^2) from exact upper bounds of |half|, |b| (a ball that
    # contains 0 squares to a ball with a negative part, whose square root is nan)
    rad = (_sq(_abs_up(half)) + _sq(_abs_up(b))).sqrt()
    lo = mean - rad
    hi = mean + rad
    return ball.bounds(lo)[0], ball.bounds(hi)[1]


def _norm_bound(M) -> Fraction:
    """Upper bound of the spectral norm of a 2 x 2 interval matrix (Frobenius norm of the entrywise maxima)."""
    s = sum(_sq(ball.q(max(abs(v) for v in ball.bounds(e)))) for row in M for e in row)
    return ball.bounds(s.sqrt())[1]


def _block(G, rows, cols):
    return [[G[i, j] for j in cols] for i in rows]


def _vec_norm_bound(xs) -> Fraction:
    s = sum(_sq(ball.q(max(abs(v) for v in ball.bounds(x)))) for x in xs)
    return ball.bounds(s.sqrt())[1]


@dataclass
class LocalManifold:
    """Validated local unstable manifold: the data (xhat, V, r_B, rho, L, r) and the bounds and checks."""

    xhat: list
    V: arb_mat
    Vinv: arb_mat
    r_block: Fraction
    rho: Fraction
    L: Fraction
    r: Fraction
    bounds: dict = field(default_factory=dict)
    checks: dict = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return bool(self.checks) and all(self.checks.values())

    @property
    def rho_eff(self) -> Fraction:
        b = self.bounds
        return min(self.rho, b["S"] + self.L * (self.r + b["U"]))

    def circle_arc(self, phi_lo, phi_hi):
        """(point box, tangent box) of gamma on [phi_lo, phi_hi] in the coordinates y (x = xhat + V y): the y-box
        (r cos Phi, r sin Phi, +-rho_eff, +-rho_eff) and the tangent (-r sin Phi, r cos Phi, +-L r, +-L r).
        (Tangents stay in y: DPhi V is multiplied by them, so the small stable part is not blown up by |DPhi|.)"""
        Phi = ball.interval(phi_lo, phi_hi)
        rq = ball.q(self.r)
        re = ball.q(self.rho_eff)
        ybox = [rq * Phi.cos(), rq * Phi.sin(), ball.interval(-self.rho_eff, self.rho_eff),
                ball.interval(-self.rho_eff, self.rho_eff)]
        lr = self.L * self.r
        dy = [-rq * Phi.sin(), rq * Phi.cos(), ball.interval(-lr, lr), ball.interval(-lr, lr)]
        del re
        return ybox, dy


def validate(fld, xhat: list, V: arb_mat, saddle_box: list, r_block, rho, L, r) -> LocalManifold:
    """Check (C1)-(C5) of the module docstring for the block (r_block, rho) and slope L; r < r_block is the
    radius of the boundary circle.  All inputs exact."""
    r_block, rho, L, r = (ball.fraction(v) for v in (r_block, rho, L, r))
    Vinv = V.inv()
    # the block as an interval box in y, then in x
    ybox = [ball.interval(-r_block, r_block)] * 2 + [ball.interval(-rho, rho)] * 2
    xbox = ball.column(ball.vec(xhat) + V * ball.vec(ybox))
    G = Vinv * fld.df(xbox) * V
    Guu, Gus = _block(G, (0, 1), (0, 1)), _block(G, (0, 1), (2, 3))
    Gsu, Gss = _block(G, (2, 3), (0, 1)), _block(G, (2, 3), (2, 3))
    m_u, _ = _sym_eig_bounds(Guu)
    _, M_s = _sym_eig_bounds(Gss)
    c_us, c_su = _norm_bound(Gus), _norm_bound(Gsu)
    N_uu, N_ss = _norm_bound(Guu), _norm_bound(Gss)
    ystar = ball.column(Vinv * ball.vec([x - xh for x, xh in zip(saddle_box, xhat)]))
    U, S = _vec_norm_bound(ystar[:2]), _vec_norm_bound(ystar[2:])
    checks = {
        "C1_outflow": m_u * r_block > N_uu * U + c_us * (rho + S),
        "C2_inflow": -M_s * rho > c_su * (r_block + U) + N_ss * S,
        "C3_cone": L * (m_u - M_s) > c_su + L * L * c_us,
        "C4_growth": (M_s + c_su / L < 0) and (m_u - c_us * L > 0),
        "C5_saddle_inside": U < r_block and S < rho,
        "circle_inside_block": 0 < r < r_block,
    }
    bounds = {"m_u": m_u, "M_s": M_s, "c_us": c_us, "c_su": c_su, "N_uu": N_uu, "N_ss": N_ss, "U": U, "S": S}
    return LocalManifold(list(xhat), V, Vinv, r_block, rho, L, r, bounds, checks)


def choose(fld, xhat, V, saddle_box, r, *, margin=Fraction("1.125")) -> LocalManifold:
    """Smallest admissible rho and L for the circle radius r (non-rigorous search; `validate` decides)."""
    r = ball.fraction(r)
    rb = r * margin
    rho = r * r
    L = Fraction(1, 1)
    for _ in range(8):
        man = validate(fld, xhat, V, saddle_box, rb, rho, L, r)
        b = man.bounds
        if not (b["m_u"] > 0 > b["M_s"]) or b["m_u"] == b["M_s"]:
            return man  # not hyperbolic on the block: no rho, L can help
        # (C2): rho > c_su (rb + U)/|M_s|; (C3), (C4): L > c_su/(m_u - M_s), L > c_su/|M_s|
        rho_new = Fraction(3, 2) * b["c_su"] * (rb + b["U"]) / (-b["M_s"]) + 2 * b["S"]
        L_new = Fraction(3, 2) * b["c_su"] / min(b["m_u"] - b["M_s"], -b["M_s"])
        rho_new = _round_up(rho_new)
        L_new = _round_up(L_new)
        if man.ok and rho_new >= rho and L_new >= L:
            return man
        rho, L = rho_new, L_new
    return validate(fld, xhat, V, saddle_box, rb, rho, L, r)


def _round_up(x: Fraction) -> Fraction:
    """A short decimal >= x (4 significant digits): certificate numbers stay readable."""
    if x <= 0:
        return Fraction(0)
    y = Fraction(f"{float(x) * 1.001:.3e}")
    while y < x:
        y = Fraction(f"{float(y) * 1.01:.3e}")
    return y
