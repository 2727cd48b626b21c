"""The rod's vector fields as ball-evaluable `Field`s (generated/validated.py), and the exact parameters.

Parameters enter the proof as exact rationals (`Fraction`): the CLI string "0.04" is the rational 1/25, not the
binary double 0.04000000000000000083; the certificate records them as "p/q".  `source_digest` is the SHA-256 of
the generated module, recorded in a certificate so that the verifier re-checks against the same field.
"""
from __future__ import annotations

import hashlib
import inspect
from dataclasses import dataclass
from fractions import Fraction

from ..generated import validated as gen
from . import ball
from .taylor import Field

PARAMS = gen.PARAMS
CHART_STATE = gen.CHART_STATE
REVERSOR = gen.CHART_REVERSOR
THETA, PSI, PTHETA, PPSI = (CHART_STATE.index(k) for k in ("theta", "psi", "ptheta", "ppsi"))


@dataclass(frozen=True)
class ExactParams:
    """(m, mu, gamma, delta, lam) as exact rationals."""

    m: Fraction
    mu: Fraction
    gamma: Fraction
    delta: Fraction
    lam: Fraction

    @classmethod
    def from_values(cls, **kw) -> "ExactParams":
        return cls(**{k: ball.fraction(str(kw[k]) if isinstance(kw[k], float) else kw[k]) for k in PARAMS})

    def balls(self) -> tuple:
        return tuple(ball.q(getattr(self, k)) for k in PARAMS)

    def floats(self) -> list[float]:
        return [float(getattr(self, k)) for k in PARAMS]

    def as_json(self) -> dict:
        return {k: f"{getattr(self, k).numerator}/{getattr(self, k).denominator}" for k in PARAMS}

    def centre(self) -> "ExactParams":
        """The parameters at the point (an interval's centre lambdabar; itself for a point)."""
        return ExactParams(self.m, self.mu, self.gamma, self.delta, self.lam)


@dataclass(frozen=True)
class IntervalParams(ExactParams):
    """ExactParams whose lambdabar is the interval [lam - lam_rad, lam + lam_rad] in every ball evaluation: every
    field, Jacobian, lift and event evaluated with `balls()` encloses its value for every lambdabar of the interval
    at once (Arb's inclusion property), so a proof run with them holds for each lambdabar of it.  `floats()` and
    `as_json()` are the centre's (the float search aims at the centre; the certificate records lam_rad apart).

    Examples
    --------
    >>> from fractions import Fraction
    >>> p = IntervalParams(Fraction(17, 10), Fraction(1, 25), Fraction(1), Fraction(1), Fraction(1, 100),
    ...                    lam_rad=Fraction(1, 10**6))
    >>> lo, hi = ball.bounds(p.balls()[4])  # exact rationals, rounded outward
    >>> lo <= Fraction(1, 100) - Fraction(1, 10**6) and Fraction(1, 100) + Fraction(1, 10**6) <= hi
    True
    """

    lam_rad: Fraction = Fraction(0)

    def balls(self) -> tuple:
        return _with_lam_interval(ExactParams.balls(self), self.lam, self.lam_rad)


def chart_field(p: ExactParams, module=gen) -> Field:
    """The reduced chart field of Hbar (4-D) at exact parameters; `module` may be a (mutated) copy of the
    generated module (controls)."""
    return Field(module.chart_rhs, module.chart_jacobian, len(CHART_STATE), p.balls(), "chart")


def body_field(p: ExactParams, module=gen) -> Field:
    return Field(module.body_rhs, module.body_jacobian, len(gen.BODY_STATE), p.balls(), "body")


BODY_EVENTS = gen.BODY_EVENTS
EV = {k: i for i, k in enumerate(BODY_EVENTS)}
E33 = gen.BODY_STATE.index("e33")


def lift(p: ExactParams, q, module=gen) -> list:
    """X(q, phi = 0): body state of the chart state q (balls)."""
    return list(module.lift(list(q), p.balls()))


def lift_jacobian(p: ExactParams, q, module=gen):
    """dX/dq (9 x 4 arb_mat) at phi = 0 over the chart box q."""
    from flint import arb_mat

    return arb_mat(len(gen.BODY_STATE), len(CHART_STATE), list(module.lift_jacobian(list(q), p.balls())))


def body_events(p: ExactParams, x, module=gen) -> dict:
    """{g, Gs, Gc, s2, rad, e33} of body_events (derive/validated.py: their chart forms) on the body box x."""
    return dict(zip(BODY_EVENTS, module.body_events(list(x), p.balls())))


def body_event_gradient(p: ExactParams, x, name: str, module=gen) -> list:
    k, n = EV[name], len(gen.BODY_STATE)
    g = module.body_events_gradient(list(x), p.balls())
    return list(g[n * k: n * (k + 1)])


def hamiltonian(p: ExactParams, x, module=gen):
    return module.chart_hamiltonian(list(x), p.balls())[0]


def source(module=gen) -> str:
    """The text of the generated field module (the installed generated/validated.py, or a control's SOURCE)."""
    return inspect.getsource(gen) if module is gen else module.SOURCE


def source_digest(module=gen) -> str:
    """SHA-256 of the vector-field source the proof ran on."""
    return hashlib.sha256(source(module).encode()).hexdigest()


def mutated_module(term: int = 0, function: str = "chart_rhs"):
    """A copy of generated/validated.py with the sign of one term flipped: the `term`-th ' + ' inside `function`
    becomes ' - ' (a control: the mutated field is neither the derived one nor, in general, reversible or
    Hamiltonian; `magrod prove` must fail on it).  Returns a module-like namespace with the mutated source."""
    import types

    src = inspect.getsource(gen)
    start = src.index(f"def {function}(")
    end = src.find("\ndef ", start + 1)
    end = len(src) if end < 0 else end
    body = src[start:end]
    pos = -1
    for _ in range(term + 1):
        pos = body.find(" + ", pos + 1)
        if pos < 0:
            raise ValueError(f"{function} has fewer than {term + 1} ' + ' terms")
    body = body[:pos] + " - " + body[pos + 3:]
    new = src[:start] + body + src[end:]
    mod = types.ModuleType("magrod.generated.validated_mutated")
    exec(compile(new, "<mutated generated/validated.py>", "exec"), mod.__dict__)  # noqa: S102 - our own source
    mod.SOURCE = new
    return mod


# --------------------------------------------------------------------------------------------------------------
# lambdabar as a state variable (a statement for every lambdabar of an interval)
# --------------------------------------------------------------------------------------------------------------
class _Dual:
    """a + b eps (eps^2 = 0) over balls or power series: forward-mode derivative of the generated field in one
    parameter.  Only the operations the generated chart code uses (+ - * /, unary -, sin, cos, sqrt); each is the
    exact derivative rule, evaluated in ball arithmetic, so the eps part encloses the exact partial derivative."""

    __slots__ = ("a", "b")

    def __init__(self, a, b):
        self.a, self.b = a, b

    @staticmethod
    def _d(x):
        return x if isinstance(x, _Dual) else _Dual(x, 0 * x if not isinstance(x, (int, Fraction)) else 0)

    def __add__(self, o):
        o = self._d(o)
        return _Dual(self.a + o.a, self.b + o.b)

    __radd__ = __add__

    def __sub__(self, o):
        o = self._d(o)
        return _Dual(self.a - o.a, self.b - o.b)

    def __rsub__(self, o):
        return self._d(o) - self

    def __neg__(self):
        return _Dual(-self.a, -self.b)

    def __mul__(self, o):
        o = self._d(o)
        return _Dual(self.a * o.a, self.a * o.b + self.b * o.a)

    __rmul__ = __mul__

    def __truediv__(self, o):
        o = self._d(o)
        return _Dual(self.a / o.a, (self.b * o.a - self.a * o.b) / (o.a * o.a))

    def __rtruediv__(self, o):
        return self._d(o) / self

    def sin(self):
        return _Dual(self.a.sin(), self.a.cos() * self.b)

    def cos(self):
        return _Dual(self.a.cos(), -(self.a.sin()) * self.b)

    def sqrt(self):
        s = self.a.sqrt()
        return _Dual(s, self.b / (2 * s))


LAM = gen.PARAMS.index("lam")


def parameter_balls(p: ExactParams, lam_rad: Fraction = Fraction(0)) -> tuple:
    """The parameters as balls in generated/validated.py's order; lambdabar widened to [lam - lam_rad, lam + lam_rad]
    (every enclosure computed with it holds for every lambdabar of the interval)."""
    return _with_lam_interval(p.balls(), p.lam, lam_rad)


def _with_lam_interval(balls, lam: Fraction, lam_rad) -> tuple:
    """The parameter balls with lambdabar's replaced by [lam - lam_rad, lam + lam_rad] (unchanged for lam_rad 0)."""
    out = list(balls)
    if lam_rad:
        out[gen.PARAMS.index("lam")] = ball.interval(lam - lam_rad, lam + lam_rad)
    return tuple(out)


def lam_state_field(p: ExactParams, module=gen):
    """The chart field with lambdabar as a fifth state variable (lambdabar' = 0): x = (theta, psi, pbar_theta,
    pbar_psi, lambdabar).  Its Jacobian's last column, d f / d lambdabar, by forward-mode differentiation (_Dual) of
    the generated chart_rhs; the other columns are the generated chart_jacobian.  A Lohner set of this field carries
    the lambdabar-interval in its linear part (C r0), as it does the initial box, instead of wrapping it into the
    remainder at every step."""
    return _lam_state(module.chart_rhs, module.chart_jacobian, len(CHART_STATE), p, "chart+lambdabar")


def body_lam_state_field(p: ExactParams, module=gen):
    """The body field with lambdabar as a tenth state variable (lambdabar' = 0), as lam_state_field is for the chart:
    x = (m, n, e3, lambdabar); the flights of statement 5 on a lambdabar interval."""
    return _lam_state(module.body_rhs, module.body_jacobian, len(gen.BODY_STATE), p, "body+lambdabar")


def _pars_with(p: ExactParams, lam) -> list:
    """p's parameter balls with lambdabar's slot holding `lam` (a ball, a series or a _Dual)."""
    q = list(ExactParams.balls(p))
    q[LAM] = lam
    return q


def _lam_state(rhs_of, jacobian_of, n, p, name):
    from .taylor import Field

    def rhs(x, _p):
        f = rhs_of(list(x[:n]), _pars_with(p, x[n]))
        return list(f) + [0 * x[n]]

    def jacobian(x, _p):
        J = list(jacobian_of(list(x[:n]), _pars_with(p, x[n])))
        dl = rhs_of([_Dual(v, 0 * v) for v in x[:n]], _pars_with(p, _Dual(x[n], 0 * x[n] + 1)))
        z = 0 * x[n]
        out = []
        for i in range(n):
            out += J[n * i: n * (i + 1)] + [dl[i].b if isinstance(dl[i], _Dual) else z]
        return out + [z] * (n + 1)

    return Field(rhs, jacobian, n + 1, tuple(ExactParams.balls(p)), name)


def lam_state_events(p: ExactParams, x, module=gen) -> dict:
    """body_events on a state of body_lam_state_field (lambdabar its last entry, in the parameters' slot)."""
    n = len(gen.BODY_STATE)
    return dict(zip(BODY_EVENTS, module.body_events(list(x[:n]), _pars_with(p, x[n]))))


def lam_state_event_gradient(p: ExactParams, x, name: str, module=gen) -> list:
    """The gradient of body event `name` in the ten variables (m, n, e3, lambdabar): the generated gradient and
    d/d lambdabar by forward-mode differentiation (_Dual)."""
    k, n = EV[name], len(gen.BODY_STATE)
    g = module.body_events_gradient(list(x[:n]), _pars_with(p, x[n]))
    d = module.body_events([_Dual(v, 0 * v) for v in x[:n]], _pars_with(p, _Dual(x[n], 0 * x[n] + 1)))[k]
    return list(g[n * k: n * (k + 1)]) + [d.b if isinstance(d, _Dual) else 0 * x[n]]


def lift_lam_derivative(p: ExactParams, q, module=gen) -> list:
    """d X / d lambdabar of the lift X(q) (9 balls) over the chart box q and p's lambdabar (an interval for
    IntervalParams), by forward-mode differentiation (_Dual): the lift depends on lambdabar through the radicand
    mu - 2 lambdabar pbar_psi."""
    lam = p.balls()[LAM]
    pars = list(p.balls())
    pars[LAM] = _Dual(lam, 0 * lam + 1)
    out = module.lift(list(q), pars)
    return [v.b if isinstance(v, _Dual) else 0 * lam for v in out]
