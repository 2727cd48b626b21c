"""The structure the proofs use, checked on the generated chart field as exact identities (part of the verifier's
trust base).

Each verified theorem uses two structural facts of the reduced chart field f of Hbar (eq:full_ham_nondim) in
x = (theta, psi, pbar_theta, pbar_psi):

- **reversibility** under R = diag(1, -1, -1, 1): f(R x) = -R f(x), and Hbar(R x) = Hbar(x).  The homoclinic
  theorem takes W^s(q*) = R(W^u(q*)); the section fixed point's orbit is R-symmetric and DP(x0) = R A^-1 R A;
  the horseshoe's chain N0 => ... => Nk closes through back-coverings R(Nk) <= ... <= R(N0) on the same level;
- **Hamiltonian form** f = J grad Hbar with the canonical J (pairs (theta, pbar_theta) and (psi, pbar_psi)): the
  return map to {sin psi = 0} on Hbar = h preserves dtheta ^ dpbar_theta, so det DP = 1 (statement 11's
  hyperbolicity from |tr DP| > 2 alone) and the level's pbar_psi is solved from Hbar itself;

and the variational equations that give every C^1 enclosure use the generated chart_jacobian, which must be Df.

They are checked here, at run time, on the source whose SHA-256 the certificate records (`fields.source`), not
read from the derivation's report: every function of the generated module is evaluated in the field of rational
functions Q(t_theta, t_psi, pbar_theta, r, m, mu, gamma, delta, lambdabar) with python-flint's exact multivariate
polynomials (`fmpq_mpoly`, numerator and denominator reduced by their gcd), where

    sin = 2 t / (1 + t^2),  cos = (1 - t^2) / (1 + t^2)  (theta and psi enter only through sin and cos),
    pbar_psi = (mu - r^2) / (2 lambdabar), so that the field's one radical sqrt(mu - 2 lambdabar pbar_psi) = r,

and derivatives by forward mode (dual numbers a + b eps over that field; the rules of + - * /, sin, cos, sqrt).
An identity holds when each component's difference is the zero rational function: a proof for every parameter
value, every state of the chart's domain (sin theta != 0, mu - 2 lambdabar pbar_psi > 0; lambdabar = 0 and
angle = pi by continuity), not a check at sample points.  SymPy is not used: the numerics never import it, and the
exact polynomial arithmetic of FLINT is small and already the verifier's arithmetic library.

Anything the exact evaluation cannot represent (another radical, an angle used other than through sin and cos, a
division by zero) makes every identity fail with that reason: the check says what it could not cover.

Cost: ~0.1 s for the four identities; the result is remembered per source digest in the process (it depends on
the field's source only, not on the certificate).
"""
from __future__ import annotations

import hashlib
from fractions import Fraction

import flint

#: the reversor the verifier's checks use (Fix(R) = {psi = pbar_theta = 0}), in the chart state's order
REVERSOR = (1, -1, -1, 1)
CHART_STATE = ("theta", "psi", "ptheta", "ppsi")
#: the variables of the rational-function field: the half-angle tangents, pbar_theta, the radical, the parameters
_STATE_VARS = ("t_theta", "t_psi", "ptheta", "r")

#: the identities' names, as the verifier's checks are named
REVERSIBLE = "reversibility f(R x) = -R f(x)"
LEVEL_SYMMETRIC = "reversibility Hbar(R x) = Hbar(x)"
HAMILTONIAN = "Hamiltonian form f = J grad Hbar"
VARIATIONAL = "variational field chart_jacobian = Df"
NAMES = (REVERSIBLE, LEVEL_SYMMETRIC, HAMILTONIAN, VARIATIONAL)
#: the horseshoe's fifth structural fact (its returns at psi = 2 pi are points of Sigma): psi_periodic()
PSI_PERIODIC = "2 pi-periodic in psi"

_REMEMBERED: dict = {}

# --- the lift to the body frame (the homoclinic theorem's flights run in body variables) --------------------------
BODY_STATE = ("m1", "m2", "m3", "n1", "n2", "n3", "e31", "e32", "e33")
#: the body events and their chart forms (rho = r/m^2, r = sqrt(mu - 2 lambdabar pbar_psi)): what the homoclinic
#: verifier reads at a body crossing as sin(theta) pbar_theta, sin(theta) rho sin(psi), ... of the chart
EVENT_FORMS = ("g = sin(theta) pbar_theta", "Gs = sin(theta) rho sin(psi)", "Gc = sin(theta) rho cos(psi)",
               "s2 = sin(theta)^2", "rad = r^2", "e33 = cos(theta)")
LIFT_INTERTWINES = "lift X intertwines the flows"
BODY_EQUIVARIANT = "body field commutes with the rotation about d3"
EVENTS_ON_CHART = "body events are rotation-invariant chart forms"
BODY_DERIVATIVES = "body_jacobian, body_events_gradient, lift_jacobian are derivatives"
LIFT_NAMES = (LIFT_INTERTWINES, BODY_EQUIVARIANT, EVENTS_ON_CHART, BODY_DERIVATIVES)


class _NotExact(Exception):
    """The field cannot be evaluated in the exact rational-function field (named reason)."""


def check(source: str, params: tuple) -> list:
    """The four identities on the generated module's `source` (its text, as digested), with parameter names
    `params` (the module's PARAMS, which must include mu and lam): [(name, holds, how)], in NAMES' order."""
    return [r for r in _remembered(source, params) if r[0] in NAMES]


def psi_periodic(source: str, params: tuple) -> tuple:
    """(holds, how) of PSI_PERIODIC: the chart field (chart_rhs, chart_jacobian, chart_hamiltonian) evaluated in the
    exact rational-function field with psi known only through sin psi and cos psi (an _Angle: any other use of the
    angle -- arithmetic, a comparison, a conversion -- is not representable and fails), so each is a rational
    function of (sin psi, cos psi) and hence 2 pi-periodic in psi: a proof, not a scan of the source text."""
    return next((h, how) for n, h, how in _remembered(source, params) if n == PSI_PERIODIC)


def _remembered(source: str, params: tuple) -> list:
    key = hashlib.sha256(f"{params}\n{source}".encode()).hexdigest()
    if key not in _REMEMBERED:
        _REMEMBERED[key] = _check(source, tuple(params))
    return list(_REMEMBERED[key])


def _check(source: str, params: tuple) -> list:
    how = {
        REVERSIBLE: f"chart_rhs(R x) + R chart_rhs(x) is the zero rational function, R = diag{REVERSOR} "
                    "(W^s = R(W^u); Fix(R)-symmetric orbits; the horseshoe's back-coverings)",
        LEVEL_SYMMETRIC: "chart_hamiltonian(R x) - chart_hamiltonian(x) is the zero rational function (R maps the "
                         "level Hbar = h to itself)",
        HAMILTONIAN: "chart_rhs - J grad chart_hamiltonian is the zero rational function, J canonical on (theta, "
                     "psi; pbar_theta, pbar_psi) (the section map is area-preserving: det DP = 1)",
        VARIATIONAL: "every entry of chart_jacobian - D chart_rhs (forward mode) is the zero rational function (the "
                     "C^1 enclosures solve V' = Df V with chart_jacobian)",
        PSI_PERIODIC: "chart_rhs, chart_jacobian and chart_hamiltonian evaluate exactly with psi known only through "
                      "sin psi and cos psi: rational functions of them, so 2 pi-periodic in psi (the horseshoe's "
                      "return at psi = 2 pi is a point of Sigma)",
    }
    exact = "exact identity in Q(t_theta, t_psi, pbar_theta, r, parameters), sin = 2t/(1+t^2), cos = " \
            "(1-t^2)/(1+t^2), pbar_psi = (mu - r^2)/(2 lambdabar)"
    try:
        got = _identities(source, params)
    except _NotExact as err:
        return [(n, False, f"{how[n]}; the generated field is not evaluable exactly: {err}") for n in (*NAMES,
                                                                                                        PSI_PERIODIC)]
    out = []
    for n in (*NAMES, PSI_PERIODIC):
        bad = got[n]
        out.append((n, not bad, f"{how[n]}; {exact}" + (f"; nonzero in component(s) {bad}" if bad else "")))
    return out


def _identities(source: str, params: tuple) -> dict:
    """{name: [the components where the difference is not zero]}."""
    if not {"mu", "lam"} <= set(params):
        raise _NotExact(f"the parameters {params} lack mu or lam (the radical's parametrisation)")
    F, v, pars, R2, ppsi, ns = _exact_setting(source, params, _STATE_VARS)
    zero, one = F.const(0), F.const(1)
    try:
        for name in ("chart_rhs", "chart_jacobian", "chart_hamiltonian", "CHART_STATE"):
            if name not in ns:
                raise _NotExact(f"the module has no {name}")
        if REVERSOR[3] != 1:
            raise _NotExact("a reversor that changes pbar_psi (the radical's parametrisation keeps it)")
        if tuple(ns["CHART_STATE"]) != CHART_STATE:
            raise _NotExact(f"the chart state is {ns['CHART_STATE']}, not {CHART_STATE}")

        def point(j=None, reflect=False):
            """x (R x if reflect) with tangent e_j (no tangent for j None)."""
            d = [None] * 4 if j is None else [one if i == j else zero for i in range(4)]
            sg = REVERSOR if reflect else (1, 1, 1, 1)
            th, ps = _Angle(v["t_theta"], sg[0], d[0]), _Angle(v["t_psi"], sg[1], d[1])
            pt = sg[2] * v["ptheta"]
            return [th, ps] + [x if dx is None else _Dual(x, dx) for x, dx in ((pt, d[2]), (ppsi, d[3]))]

        f = ns["chart_rhs"](point(), pars)
        fR = ns["chart_rhs"](point(reflect=True), pars)
        H = ns["chart_hamiltonian"](point(), pars)[0]
        HR = ns["chart_hamiltonian"](point(reflect=True), pars)[0]
        dH = [_part(ns["chart_hamiltonian"](point(j), pars)[0], F) for j in range(4)]
        cols = [[_part(c, F) for c in ns["chart_rhs"](point(j), pars)] for j in range(4)]
        Jm = ns["chart_jacobian"](point(), pars)
        Jg = [dH[2], dH[3], -dH[0], -dH[1]]
        return {
            REVERSIBLE: [CHART_STATE[i] for i in range(4) if not F.zero(fR[i] + REVERSOR[i] * f[i])],
            LEVEL_SYMMETRIC: [] if F.zero(HR - H) else ["Hbar"],
            HAMILTONIAN: [CHART_STATE[i] for i in range(4) if not F.zero(f[i] - Jg[i])],
            VARIATIONAL: [f"[{i}, {j}]" for i in range(4) for j in range(4) if not F.zero(Jm[4 * i + j] - cols[j][i])],
            PSI_PERIODIC: [],  # evaluated at all: psi entered only through sin and cos (_Angle)
        }
    except (TypeError, ZeroDivisionError, AttributeError, ValueError, IndexError) as err:
        raise _NotExact(f"{type(err).__name__}: {str(err)[:120]}") from None


def _exact_setting(source: str, params: tuple, variables: tuple):
    """The field Q(variables, params) with the radical sqrt(mu - 2 lambdabar pbar_psi) = r, its generators by name,
    the parameters, r^2, pbar_psi = (mu - r^2)/(2 lambdabar), and the generated module executed over it."""
    F = _Field(variables + params)
    v = dict(zip(F.names, F.gens))
    R2 = v["r"] * v["r"]
    F.radicand, F.root = R2, v["r"]
    return F, v, [v[k] for k in params], R2, (v["mu"] - R2) / (2 * v["lam"]), _namespace(source, F)


def _part(x, F):
    """The eps part: the derivative (0 for a value that does not depend on the state, e.g. a constant component)."""
    return x.b if isinstance(x, _Dual) else F.const(0)


def _namespace(source: str, F) -> dict:
    """The generated module executed afresh (its own source, the one digested), with its exact constants _Q(p, q)
    as elements of F instead of Arb balls."""
    ns: dict = {"__name__": "magrod.generated.validated_exact"}
    exec(compile(source, "<generated/validated.py, exact>", "exec"), ns)  # noqa: S102 - the package's own source
    ns["_Q"] = lambda p, q: F.const(Fraction(p, q))
    return ns


class _Field:
    """Q(names) with elements _RF (numerator, denominator: fmpq_mpoly, reduced by their gcd, monic denominator)."""

    def __init__(self, names):
        self.names = tuple(names)
        self.ctx = flint.fmpq_mpoly_ctx.get(self.names, "lex")
        self.gens = [_RF(self, g) for g in self.ctx.gens()]
        self.radicand = self.root = None

    def poly(self, c: Fraction):
        return self.ctx.from_dict({(0,) * len(self.names): flint.fmpq(c.numerator, c.denominator)})

    def const(self, c) -> "_RF":
        return _RF(self, self.poly(Fraction(c)))

    def zero(self, x) -> bool:
        if isinstance(x, _Dual):
            raise TypeError("a value with a tangent where a plain value was expected")
        return _RF.of(self, x).n.is_zero()


class _RF:
    __slots__ = ("F", "n", "d")

    def __init__(self, F, n, d=None):
        if d is None:
            d = F.poly(Fraction(1))
        if d.is_zero():
            raise ZeroDivisionError("a denominator is the zero rational function")
        g = n.gcd(d)
        if not g.is_one():
            n, d = n / g, d / g
        lc = d.leading_coefficient()
        if lc != 1:
            n, d = n / lc, d / lc
        self.F, self.n, self.d = F, n, d

    @staticmethod
    def of(F, o):
        if isinstance(o, _RF):
            return o
        if isinstance(o, (int, Fraction)) and not isinstance(o, bool):
            return F.const(o)
        raise TypeError(f"{type(o).__name__} in exact arithmetic (only rational constants)")

    def __add__(self, o):
        if isinstance(o, (_Dual, _Angle)):
            return NotImplemented
        o = _RF.of(self.F, o)
        if self.d == o.d:
            return _RF(self.F, self.n + o.n, self.d)
        return _RF(self.F, self.n * o.d + o.n * self.d, self.d * o.d)

    __radd__ = __add__

    def __neg__(self):
        return _RF(self.F, -self.n, self.d)

    def __sub__(self, o):
        if isinstance(o, (_Dual, _Angle)):
            return NotImplemented
        return self + (-_RF.of(self.F, o))

    def __rsub__(self, o):
        return _RF.of(self.F, o) - self

    def __mul__(self, o):
        if isinstance(o, (_Dual, _Angle)):
            return NotImplemented
        o = _RF.of(self.F, o)
        return _RF(self.F, self.n * o.n, self.d * o.d)

    __rmul__ = __mul__

    def __truediv__(self, o):
        if isinstance(o, (_Dual, _Angle)):
            return NotImplemented
        o = _RF.of(self.F, o)
        if o.n.is_zero():
            raise ZeroDivisionError("division by the zero rational function")
        return _RF(self.F, self.n * o.d, self.d * o.n)

    def __rtruediv__(self, o):
        return _RF.of(self.F, o) / self

    def sqrt(self):
        # the chart field's one radical: sqrt(mu - 2 lambdabar pbar_psi) = r (r > 0 on the chart's domain)
        if self.F.radicand is not None and (self - self.F.radicand).n.is_zero():
            return self.F.root
        raise TypeError("a square root of other than mu - 2 lambdabar pbar_psi")


class _Dual:
    """a + b eps (eps^2 = 0) over _RF: the exact derivative rules."""

    __slots__ = ("a", "b")

    def __init__(self, a, b):
        self.a, self.b = a, b

    @staticmethod
    def _d(o, like):
        return o if isinstance(o, _Dual) else _Dual(_RF.of(like.a.F, o), like.a.F.const(0))

    def __add__(self, o):
        o = self._d(o, self)
        return _Dual(self.a + o.a, self.b + o.b)

    __radd__ = __add__

    def __sub__(self, o):
        o = self._d(o, self)
        return _Dual(self.a - o.a, self.b - o.b)

    def __rsub__(self, o):
        return self._d(o, self) - self

    def __neg__(self):
        return _Dual(-self.a, -self.b)

    def __mul__(self, o):
        o = self._d(o, self)
        return _Dual(self.a * o.a, self.a * o.b + self.b * o.a)

    __rmul__ = __mul__

    def __truediv__(self, o):
        o = self._d(o, self)
        return _Dual(self.a / o.a, (self.b * o.a - self.a * o.b) / (o.a * o.a))

    def __rtruediv__(self, o):
        return self._d(o, self) / self

    def sqrt(self):
        s = self.a.sqrt()
        return _Dual(s, self.b / (2 * s))


class _Angle:
    """An angle known only through sin and cos (half-angle tangent t; sign -1: the reflected angle); with a tangent
    dt its sin and cos are duals.  Any other use (arithmetic on the angle) is a TypeError: not covered."""

    __slots__ = ("s", "c", "dt")

    def __init__(self, t, sign, dt=None):
        q = 1 + t * t
        self.s, self.c, self.dt = sign * (2 * t) / q, (1 - t * t) / q, dt

    def sin(self):
        return self.s if self.dt is None else _Dual(self.s, self.c * self.dt)

    def cos(self):
        return self.c if self.dt is None else _Dual(self.c, -self.s * self.dt)

    def _other_use(self, *_):
        raise TypeError("an angle used other than through sin and cos")

    # a comparison or a truth test would otherwise answer silently (object identity): not covered, so refused
    __eq__ = __ne__ = __lt__ = __le__ = __gt__ = __ge__ = __bool__ = __float__ = __int__ = __index__ = _other_use
    __hash__ = None


# --------------------------------------------------------------------------------------------------------------
# the lift to the body frame
# --------------------------------------------------------------------------------------------------------------
def lift_check(source: str, params: tuple) -> list:
    """The facts the homoclinic verifier's body-frame flights rest on, as exact identities on the generated module's
    `source`: [(name, holds, how)] in LIFT_NAMES' order.  With G the generator of the rotation about d3 (each of
    m, n, e3: (v1, v2, v3) -> (v2, -v1, 0)) and Omega(q) = (1 - pbar_psi cos theta)/sin^2 theta:

    1. f_body(X(q)) = DX(q) f_chart(q) + Omega(q) G X(q)   (X = lift, the body state of q at phi = 0);
    2. Df_body(x) G x = G f_body(x)                        (the body field commutes with exp(phi G));
    3. grad e(x) . G x = 0 and e(X(q)) = its chart form    (each body event, EVENT_FORMS);
    4. body_jacobian = D body_rhs, body_events_gradient = D body_events, lift_jacobian = D lift (forward mode).

    Then Y(t) = exp(phi(t) G) X(q(t)), with q the chart solution and phi' = Omega(q), solves the body system (1, 2),
    so the body solution from X(q0) is Y (uniqueness), and its events are the chart's quantities at q(t) (3), while
    sin(theta) != 0 and the radicand > 0 (the verifier's guards).  Replaces the derivation's report entry
    chart_body_lift as what the verifier relies on.  Remembered per source digest, like check()."""
    key = "lift:" + hashlib.sha256(f"{params}\n{source}".encode()).hexdigest()
    if key not in _REMEMBERED:
        _REMEMBERED[key] = _lift_check(source, tuple(params))
    return list(_REMEMBERED[key])


def _lift_check(source: str, params: tuple) -> list:
    how = {
        LIFT_INTERTWINES: "body_rhs(lift(q)) - D lift(q) chart_rhs(q) - Omega(q) G lift(q) is the zero rational "
                          "function, Omega = (1 - pbar_psi cos theta)/sin^2 theta, G v = (v2, -v1, 0) on m, n, e3 "
                          "(a body solution from lift(q0) is exp(phi G) lift(q(t)), phi' = Omega)",
        BODY_EQUIVARIANT: "D body_rhs(x) G x - G body_rhs(x) is the zero polynomial (exp(phi G) maps body solutions "
                          "to body solutions)",
        EVENTS_ON_CHART: "grad e . G x = 0 and e(lift(q)) - chart form = 0 for " + "; ".join(EVENT_FORMS),
        BODY_DERIVATIVES: "every entry of body_jacobian - D body_rhs, body_events_gradient - D body_events and "
                          "lift_jacobian - D lift (forward mode) is the zero rational function",
    }
    exact = "exact identity in Q(t_theta, t_psi, pbar_theta, r, m1 .. e33, parameters)"
    try:
        got = _lift_identities(source, params)
    except _NotExact as err:
        return [(n, False, f"{how[n]}; the generated module is not evaluable exactly: {err}") for n in LIFT_NAMES]
    return [(n, not got[n], f"{how[n]}; {exact}" + (f"; nonzero in {got[n]}" if got[n] else "")) for n in LIFT_NAMES]


def _lift_identities(source: str, params: tuple) -> dict:
    if not {"mu", "lam", "m"} <= set(params):
        raise _NotExact(f"the parameters {params} lack m, mu or lam")
    F, v, pars, R2, ppsi, ns = _exact_setting(source, params, _STATE_VARS + BODY_STATE)
    nb = len(BODY_STATE)  # m, n, e3: three vectors of three
    zero, one = F.const(0), F.const(1)
    try:
        for name in ("chart_rhs", "lift", "lift_jacobian", "body_rhs", "body_jacobian", "body_events",
                     "body_events_gradient", "BODY_STATE", "BODY_EVENTS"):
            if name not in ns:
                raise _NotExact(f"the module has no {name}")
        if tuple(ns["BODY_STATE"]) != BODY_STATE:
            raise _NotExact(f"the body state is {ns['BODY_STATE']}, not {BODY_STATE}")
        if tuple(ns["BODY_EVENTS"]) != tuple(f.split(" = ")[0] for f in EVENT_FORMS):
            raise _NotExact(f"the body events are {ns['BODY_EVENTS']}")

        def chart(d=None):
            """q, with tangent d (a list of 4 values, or None)."""
            d = d or [None] * 4
            th, ps = _Angle(v["t_theta"], 1, d[0]), _Angle(v["t_psi"], 1, d[1])
            return [th, ps] + [x if dx is None else _Dual(x, dx) for x, dx in ((v["ptheta"], d[2]), (ppsi, d[3]))]

        def G(x):
            return [w for i in range(0, nb, 3) for w in (x[i + 1], -x[i], zero)]

        def plain(x):
            return x.a if isinstance(x, _Dual) else x

        def tangent(x):
            return _part(x, F)

        fc = ns["chart_rhs"](chart(), pars)
        X = [plain(c) for c in ns["lift"](chart(), pars)]
        DXf = [tangent(c) for c in ns["lift"](chart(fc), pars)]
        ang = _Angle(v["t_theta"], 1)
        omega = (1 - ppsi * ang.c) / (ang.s * ang.s)
        fbX = ns["body_rhs"](X, pars)
        GX = G(X)
        inter = [BODY_STATE[i] for i in range(nb) if not F.zero(fbX[i] - DXf[i] - omega * GX[i])]

        xb = [v[k] for k in BODY_STATE]
        fb = ns["body_rhs"](xb, pars)
        Gx = G(xb)
        dfGx = [tangent(c) for c in ns["body_rhs"]([_Dual(a, b) for a, b in zip(xb, Gx)], pars)]
        Gfb = G(fb)
        equi = [BODY_STATE[i] for i in range(nb) if not F.zero(dfGx[i] - Gfb[i])]

        evG = [tangent(c) for c in ns["body_events"]([_Dual(a, b) for a, b in zip(xb, Gx)], pars)]
        evX = ns["body_events"](X, pars)
        rho = v["r"] / (v["m"] * v["m"])
        ps = _Angle(v["t_psi"], 1)
        forms = [ang.s * v["ptheta"], ang.s * rho * ps.s, ang.s * rho * ps.c, ang.s * ang.s, R2, ang.c]
        names = list(ns["BODY_EVENTS"])
        events = ([f"{names[k]} not invariant" for k in range(len(names)) if not F.zero(evG[k])]
                  + [f"{names[k]} on the chart" for k in range(len(names)) if not F.zero(evX[k] - forms[k])])

        units = [[one if i == j else zero for i in range(nb)] for j in range(nb)]
        Jb = ns["body_jacobian"](xb, pars)
        colb = [[tangent(c) for c in ns["body_rhs"]([_Dual(a, b) for a, b in zip(xb, u)], pars)] for u in units]
        Eg = ns["body_events_gradient"](xb, pars)
        cole = [[tangent(c) for c in ns["body_events"]([_Dual(a, b) for a, b in zip(xb, u)], pars)] for u in units]
        JX = ns["lift_jacobian"](chart(), pars)
        colX = [[tangent(c) for c in ns["lift"](chart([one if i == j else zero for i in range(4)]), pars)]
                for j in range(4)]
        ders = ([f"body_jacobian[{i}, {j}]" for i in range(nb) for j in range(nb) if not F.zero(Jb[nb * i + j] - colb[j][i])]
                + [f"body_events_gradient[{k}, {j}]" for k in range(len(names)) for j in range(nb)
                   if not F.zero(Eg[nb * k + j] - cole[j][k])]
                + [f"lift_jacobian[{i}, {j}]" for i in range(nb) for j in range(4) if not F.zero(JX[4 * i + j] - colX[j][i])])
        return {LIFT_INTERTWINES: inter, BODY_EQUIVARIANT: equi, EVENTS_ON_CHART: events, BODY_DERIVATIVES: ders}
    except (TypeError, ZeroDivisionError, AttributeError, ValueError, IndexError) as err:
        raise _NotExact(f"{type(err).__name__}: {str(err)[:120]}") from None
