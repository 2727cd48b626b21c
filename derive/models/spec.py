"""What a rod model is, for the pipeline: the data entered once per model, and the checks that make a model file
acceptable.

A model is a Python module (one per model in derive/models/, or the user's own file, see docs/models.md) that
defines, with SymPy:

  NAME        short name (lower case, digits, '-' or '_')
  TITLE       one line
  SOURCE      where it comes from (reference keys of the paper's bibliography, e.g. "Kehrbaum97b")
  STATE       list of real Symbols, the body-frame state x
  PARAMETERS  {Symbol: (meaning, (low, high), default)}: every constant of W/H and J, with its admissible open
              range (sp.oo allowed) and a default value inside it
  J           the structure matrix J(x; parameters), a square SymPy Matrix (x' = J grad H)
  and either
  H           the Hamiltonian, a polynomial in STATE
  or
  W           the strain energy, a polynomial of degree <= 2 in the strains, with
  STRAINS     [(strain Symbol, conjugate state Symbol)] (e.g. (u1, m1): m1 = dW/du1) and optionally
  FIXED       {strain Symbol: value} for constrained strains (inextensible, unshearable: v = d3)
  optional:
  CANDIDATES  {name: (polynomial, reference)}: integrals claimed in the literature, tested (never assumed)
  SECTION     the Poincare section function (default: STATE[0]), crossed upwards
  REFERENCE   {state Symbol: number}: a state near which default initial conditions are drawn (default: a
              seeded generic state with components in [0.1, 0.9])
  CASIMIRS    {"C1": polynomial, ...}: the Casimirs in the model's own normalisation and order (e.g. the printed
              ones); checked (J grad C = 0, and they span the Casimirs the pipeline finds), never assumed

Every check below raises ModelError(check, text) naming the check that failed; `load_file` runs all of them
before anything is written.
"""
from __future__ import annotations

import importlib.util
import keyword
import re
import sys
from dataclasses import dataclass, field

import sympy as sp

NAME_RE = re.compile(r"^[a-z][a-z0-9_-]{0,39}$")
# identifiers the generated modules use themselves: a symbol may not be called like one of them
RESERVED = {"hy", "pars", "system", "rhs", "hamiltonian", "casimirs", "candidates", "section", "constraints",
            "constraint_gradients", "math", "np", "xs", "STATE", "PARAMS", "_E", "_Q", "Fraction"}


class ModelError(ValueError):
    """A model file failed one of the pipeline's checks; `check` names it (import, missing, name clash, skew,
    jacobi, W polynomial, W convex, parameters, state, candidates)."""

    def __init__(self, check: str, text: str):
        self.check = check
        super().__init__(f"{check}: {text}")


def sym(value, check: str = "expression"):
    """A model's value as SymPy, never parsed from a string: sympify(strict=True) converts numbers and SymPy
    objects only (a string in a model file would be evaluated a second time, as code; ModelError names the check)."""
    try:
        return sp.sympify(value, strict=True)
    except (sp.SympifyError, TypeError):
        raise ModelError(check, f"{str(value)[:60]!r} must be a SymPy expression or a number, not a string") from None


@dataclass
class Model:
    name: str
    title: str
    source: str
    state: list
    parameters: dict  # {Symbol: (meaning, (lo, hi), default)}
    J: sp.Matrix
    H: sp.Expr
    W: sp.Expr | None = None
    strains: list = field(default_factory=list)
    fixed: dict = field(default_factory=dict)
    candidates: dict = field(default_factory=dict)
    section: sp.Expr | None = None
    reference: dict = field(default_factory=dict)
    notes: str = ""
    casimirs: dict = field(default_factory=dict)  # {"C1": expr, ...} as the model names them (optional)
    helpers: list = field(default_factory=list)  # files of the user's own modules the model file imported

    def fingerprint(self) -> str:
        """The evaluated model as text (srepr of every expression, the data in a fixed order): equal for two files
        that define the same model, different when an expression changed, wherever it was computed."""
        params = [(sp.srepr(p), v[0], sp.srepr(sym(v[1][0])), sp.srepr(sym(v[1][1])), sp.srepr(sym(v[2])))
                  for p, v in self.parameters.items()]
        parts = [self.name, self.title, self.source, self.notes, [sp.srepr(x) for x in self.state], params,
                 sp.srepr(self.J), sp.srepr(self.H), sp.srepr(self.W) if self.W is not None else "",
                 [(sp.srepr(s), sp.srepr(x)) for s, x in self.strains],
                 sorted((sp.srepr(k), sp.srepr(sym(v))) for k, v in self.fixed.items()),
                 [(k, sp.srepr(sym(e)), str(r)) for k, (e, r) in self.candidates.items()],
                 sp.srepr(self.section), [(sp.srepr(k), repr(v)) for k, v in self.reference.items()],
                 [(k, sp.srepr(v)) for k, v in self.casimirs.items()]]
        return repr(parts)

    @property
    def params(self) -> list:
        return list(self.parameters)

    @property
    def ident(self) -> str:
        """The Python identifier of the model (the package name under generated/models/)."""
        return self.name.replace("-", "_")


def legendre(W, strains, fixed):
    """H = sum x s - W with x = dW/ds solved for the free strains s (W quadratic in them: a linear system with a
    unique solution iff the Hessian is regular; convexity is checked separately) and the fixed strains
    substituted (their conjugate state variables then enter H linearly: the reaction of the constraint)."""
    free = [(s, x) for s, x in strains if s not in fixed]
    Wf = W.subs(fixed)
    eqs = [x - sp.diff(Wf, s) for s, x in free]
    sol = sp.solve(eqs, [s for s, _ in free], dict=True) if free else [{}]
    if len(sol) != 1:
        raise ModelError("W convex", "the constitutive law x = dW/ds has no unique inverse")
    sol = sol[0]
    Hm = sum(x * s for s, x in strains) - W
    return sp.expand(Hm.subs(fixed).subs(sol))


def _check_W(W, strains, fixed, parameters):
    free = [s for s, _ in strains if s not in fixed]
    try:
        P = sp.Poly(sp.expand(W), *[s for s, _ in strains])
    except sp.PolynomialError:
        raise ModelError("W polynomial", f"W is not a polynomial in the strains {[str(s) for s, _ in strains]}: "
                                         f"{W}") from None
    if P.total_degree() > 2:
        raise ModelError("W polynomial", f"W has degree {P.total_degree()} in the strains; the Legendre transform "
                                         "to a polynomial H needs degree <= 2 (linear elasticity)")
    extra = sorted(str(x) for c in P.coeffs() for x in c.free_symbols - set(parameters))
    if extra:
        raise ModelError("parameters", f"missing parameters: {', '.join(dict.fromkeys(extra))} appear in W but not "
                                       "in PARAMETERS (or are state variables inside W's coefficients)")
    Hess = sp.hessian(W.subs(fixed), free) if free else sp.zeros(0, 0)
    defaults = {p: v[2] for p, v in parameters.items()}
    for k in range(1, len(free) + 1):
        minor = sp.factor(Hess[:k, :k].det())
        pos = minor.is_positive
        val = minor.subs(defaults)
        if pos is False or (val.is_number and not val > 0):
            raise ModelError("W convex", f"W is not strictly convex in the free strains: the leading minor of order "
                                         f"{k} of its Hessian is {minor} (at the defaults {val})")
    return Hess


def jacobi_failures(Jm, X, limit=None):
    """Index triples (i, j, k) whose cyclic sum  sum_l J_il d_l J_jk + cyclic  does not expand to 0."""
    import itertools

    n = len(X)
    dJ = [[[sp.diff(Jm[j, k], X[l]) for l in range(n)] for k in range(n)] for j in range(n)]
    bad = []
    for i, j, k in itertools.combinations(range(n), 3):
        r = sp.expand(sum(Jm[i, l] * dJ[j][k][l] + Jm[j, l] * dJ[k][i][l] + Jm[k, l] * dJ[i][j][l]
                          for l in range(n)))
        if r != 0:
            bad.append(((i, j, k), r))
            if limit and len(bad) >= limit:
                break
    return bad


def build_model(ns: dict, origin: str) -> Model:
    """A Model from the namespace of a model module, every check of the module docstring applied."""
    for key in ("NAME", "STATE", "PARAMETERS", "J"):
        if key not in ns:
            raise ModelError("missing", f"{origin} defines no {key}")
    if "H" not in ns and "W" not in ns:
        raise ModelError("missing", f"{origin} defines neither H nor W")
    name = ns["NAME"]
    if not isinstance(name, str) or not NAME_RE.match(name):
        raise ModelError("name clash", f"NAME must match {NAME_RE.pattern}, got {name!r}")
    X = list(ns["STATE"])
    if not X or not all(isinstance(x, sp.Symbol) for x in X) or len(set(X)) != len(X):
        raise ModelError("state", "STATE must be a non-empty list of distinct SymPy Symbols")
    parameters = ns["PARAMETERS"]
    if not isinstance(parameters, dict) or not all(isinstance(p, sp.Symbol) for p in parameters):
        raise ModelError("parameters", "PARAMETERS must be a dict {Symbol: (meaning, (low, high), default)}")
    for p, v in parameters.items():
        if not (isinstance(v, tuple) and len(v) == 3 and isinstance(v[0], str) and len(v[1]) == 2):
            raise ModelError("parameters", f"PARAMETERS[{p}] must be (meaning, (low, high), default)")
        lo, hi = (sym(b, "parameters") for b in v[1])
        d = sym(v[2], "parameters")
        if not (d.is_number and d.is_real and lo < d < hi):
            raise ModelError("parameters", f"the default {v[2]} of {p} is not inside its range ({lo}, {hi})")
    names = [str(s) for s in X + list(parameters)]
    for s in names:
        if not s.isidentifier() or keyword.iskeyword(s) or s in RESERVED:
            raise ModelError("name clash", f"{s!r} cannot name a variable of the generated code (a Python keyword "
                                           "or a name the generated modules use)")
    dup = sorted({s for s in names if names.count(s) > 1})
    if dup:
        raise ModelError("name clash", f"{', '.join(dup)} names both a state variable and a parameter (or two)")
    Jm = ns["J"]
    if not isinstance(Jm, sp.MatrixBase) or Jm.shape != (len(X), len(X)):
        raise ModelError("skew", f"J must be a {len(X)}x{len(X)} SymPy Matrix")
    Jm = sp.Matrix(Jm)
    strains, fixed, W = list(ns.get("STRAINS", [])), dict(ns.get("FIXED", {})), ns.get("W")
    if W is not None:
        if not strains:
            raise ModelError("missing", "W is given but STRAINS (the strain/state pairs) is not")
        for s, x in strains:
            if x not in X:
                raise ModelError("state", f"the conjugate {x} of strain {s} is not in STATE")
        _check_W(sym(W, "W polynomial"), strains, fixed, parameters)
        H = legendre(sym(W, "W polynomial"), strains, fixed)
        if "H" in ns:
            raise ModelError("missing", "give W or H, not both (H is derived from W by the Legendre transform)")
    else:
        H = sp.expand(sym(ns["H"], "missing"))
    cands = dict(ns.get("CANDIDATES", {}))
    given = dict(ns.get("CASIMIRS", {}))
    for k in given:
        if not (isinstance(k, str) and re.match(r"^C[1-9][0-9]?$", k)):
            raise ModelError("casimirs", f"CASIMIRS names must be C1, C2, ..., got {k!r}")
    given = {k: sp.expand(sym(v, "casimirs")) for k, v in sorted(given.items(), key=lambda kv: int(kv[0][1:]))}
    section = sym(ns.get("SECTION", X[0]), "state")
    exprs = [H, section, *Jm] + [c[0] for c in cands.values()] + list(given.values())
    syms = set().union(*(sym(e).free_symbols for e in exprs))
    by_name: dict = {}
    for s in syms | set(X) | set(parameters):
        by_name.setdefault(str(s), set()).add(s)
    clash = sorted(k for k, v in by_name.items() if len(v) > 1)
    if clash:
        raise ModelError("name clash", f"different symbols share the name {', '.join(clash)} (e.g. declared with "
                                       "different assumptions)")
    missing = sorted(str(s) for s in syms - set(X) - set(parameters))
    if missing:
        raise ModelError("parameters", f"missing parameters: {', '.join(missing)} appear in H, J, W or the "
                                       "candidates but not in PARAMETERS")
    try:
        sp.Poly(H, *X)
    except sp.PolynomialError:
        raise ModelError("W polynomial", f"H is not a polynomial in the state: {H}") from None
    if sp.expand(Jm + Jm.T) != sp.zeros(*Jm.shape):
        i, j = next((i, j) for i in range(len(X)) for j in range(len(X)) if sp.expand(Jm[i, j] + Jm[j, i]) != 0)
        raise ModelError("skew", f"J is not skew: J[{i},{j}] + J[{j},{i}] = {sp.expand(Jm[i, j] + Jm[j, i])}")
    for (i, j), e in zip(((i, j) for i in range(len(X)) for j in range(len(X))), Jm):
        try:
            if sp.Poly(e, *X).total_degree() > 1:
                raise ModelError("jacobi", f"J[{i},{j}] = {e} is not affine in the state (the pipeline needs a "
                                           "Lie-Poisson or constant structure)")
        except sp.PolynomialError:
            raise ModelError("jacobi", f"J[{i},{j}] = {e} is not polynomial in the state") from None
    bad = jacobi_failures(Jm, X, limit=1)
    if bad:
        (i, j, k), r = bad[0]
        raise ModelError("jacobi", f"the Jacobi identity fails for ({X[i]}, {X[j]}, {X[k]}): cyclic sum {r}")
    for k, (e, _ref) in cands.items():
        if not isinstance(k, str) or not k.isidentifier():
            raise ModelError("candidates", f"candidate name {k!r} is not an identifier")
        try:
            sp.Poly(sym(e, "candidates"), *X)
        except sp.PolynomialError:
            raise ModelError("candidates", f"candidate {k} is not a polynomial in the state") from None
    ref = {sp.Symbol(str(k)) if not isinstance(k, sp.Symbol) else k: v for k, v in dict(ns.get("REFERENCE", {})).items()}
    if not ref:  # a generic (seeded, non-zero) state: the origin is usually a singular point of the level sets
        import random

        rng = random.Random(0)
        ref = {x: round(rng.uniform(0.1, 0.9), 3) for x in X}
    return Model(name, str(ns.get("TITLE", name)), str(ns.get("SOURCE", origin)), X, parameters, Jm, H,
                 sym(W) if W is not None else None, strains, fixed, cands, section,
                 {x: float(ref.get(x, 0.0)) for x in X}, str(ns.get("NOTES", "")), given)


def load_file(path) -> Model:
    """Run a user's model file (code the user runs on purpose, like a setup.py) and check it.  Nothing is written.
    Any exception while importing it is the 'import' check."""
    spec = importlib.util.spec_from_file_location("magrod_user_model", str(path))
    if spec is None or spec.loader is None:
        raise ModelError("import", f"{path} is not a Python file")
    mod = importlib.util.module_from_spec(spec)
    before = set(sys.modules)
    try:
        spec.loader.exec_module(mod)
    except Exception as exc:  # the user's code: every failure is 'does not import'
        raise ModelError("import", f"{path} does not import: {type(exc).__name__}: {exc}") from None
    finally:
        sys.modules.pop("magrod_user_model", None)
        helpers = _user_modules(set(sys.modules) - before)
    model = build_model(vars(mod), str(path))
    model.helpers = helpers
    return model


def _user_modules(names) -> list:
    """The files of the user's own modules among the newly imported `names` (not installed packages, not the
    standard library), removed from sys.modules: the next load of the model file imports them afresh, so an edited
    helper counts."""
    import os
    import sysconfig

    installed = {os.path.realpath(p) for p in (sys.prefix, sys.base_prefix, sys.exec_prefix,
                                               *sysconfig.get_paths().values()) if p}
    out = []
    for name in sorted(names):
        f = getattr(sys.modules.get(name), "__file__", None)
        if not f or name.split(".")[0] == "magrod":
            continue
        real = os.path.realpath(f)
        if any(real.startswith(p + os.sep) for p in installed):
            continue
        out.append(real)
        sys.modules.pop(name, None)
    return out


def load_module(mod) -> Model:
    return build_model(vars(mod), mod.__name__)
