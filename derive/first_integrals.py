"""Data for the exact search for polynomial first integrals (magrod/integrability/
first_integrals.py, `magrod check --integrals`).

The search solves {F, H} = grad F . J(x; lambda) grad H = 0 for polynomials F in the 9 body variables
x = (m, n, e3).  It needs, as exact rational data in the model constants (B1, B2, C, c_H, c_J, c_K, lambda):
  * H in compliance form (derive/poisson.py hamiltonian_compliance: the Legendre transform of eq:hyperelastic),
  * the structure matrix J(x; lambda) of eq:noncanonical_structure (entries linear in x),
  * the known integrals: the Casimirs C1, C2, C3 (eq:magnetic_casimirs1-3, found by derive/poisson.py), I1 = B1 m3
    (eq:magnetic_lagrange, a first integral iff B1 = B2) and I2 = n.m + B1 lambda e33 (eq:int2).
They are written as monomial lists plus functions returning the coefficients, printed with exact rationals
(fractions.Fraction), so the runtime evaluates them at rational parameter values without SymPy and without
rounding.  Entered nowhere else: the runtime reads only this generated module."""
from __future__ import annotations

import sympy as sp

from .model import B1, B2, C, X, cH, cJ, cK, lam, structure_matrix
from .poisson import first_integrals, hamiltonian_compliance
from .results import DISAGREES, HOLDS, Result

PARAMS = (B1, B2, C, cH, cJ, cK, lam)
PARAM_NAMES = ("B1", "B2", "C", "c_H", "c_J", "c_K", "lam")
NAMES = dict(zip(PARAMS, PARAM_NAMES))


def _poly(expr):
    """(monomials, coefficients) of expr as a polynomial in X with coefficients rational in PARAMS."""
    P = sp.Poly(sp.expand(expr), *X)
    terms = sorted(P.terms(), key=lambda mc: mc[0])
    return [tuple(int(k) for k in mono) for mono, _ in terms], [sp.factor(c) for _, c in terms]


def polynomials() -> dict:
    """{name: (monomials, coefficients)} for H, C1, C2, C3, I1, I2 (general regime: B1, B2, c_H, c_J free)."""
    fi = first_integrals({})
    out = {"H": _poly(hamiltonian_compliance())}
    for k in ("C1", "C2", "C3", "I1", "I2"):
        out[k] = _poly(fi[k])
    return out


def structure_terms():
    """[(i, j, k, coefficient)] with J_ij = sum_k coefficient * x_k (J is linear in x; coefficients in lambda)."""
    Jm = structure_matrix()
    out = []
    for i in range(9):
        for j in range(9):
            e = sp.expand(Jm[i, j])
            if e == 0:
                continue
            P = sp.Poly(e, *X)
            for mono, c in sorted(P.terms()):
                if sum(mono) != 1:
                    raise AssertionError(f"J[{i},{j}] is not linear in x: {e}")
                out.append((i, j, list(mono).index(1), c))
    return out


def derive_all():
    """Report entry: the data are exact, J is linear and skew, and H, C1-C3 are what derive/poisson.py derived."""
    st = structure_terms()
    skew = all(sp.simplify(structure_matrix()[i, j] + structure_matrix()[j, i]) == 0 for i in range(9)
               for j in range(9))
    pol = polynomials()
    deg = {k: max(sum(mn) for mn in v[0]) for k, v in pol.items()}
    ok = skew and deg == {"H": 2, "C1": 2, "C2": 2, "C3": 2, "I1": 1, "I2": 2}
    return [Result("first_integral_data", "eq:magnetic_ham, eq:noncanonical_structure, eq:magnetic_casimirs1-3, "
                   "eq:magnetic_lagrange, eq:int2",
                   "Exact data for the polynomial first-integral search: H (compliance form), J(x; lambda) linear "
                   "and skew, C1-C3, I1, I2 as monomial lists with rational coefficients",
                   HOLDS if ok else DISAGREES,
                   "symbolic: J entries expanded (all linear in x), J + J^T = 0; degrees of the polynomials",
                   {"structure terms": len(st), "degrees": deg,
                    "terms": {k: len(v[0]) for k, v in pol.items()}})]


def model():
    """The rod of this search as a model of the pipeline (derive/models/spec.py Model): anisotropic, extensible and
    shearable (compliance form), in a field -- the family that the registered models specialise.  Its data module is
    written by the one generator of every model's search data (derive/models/pipeline.py first_integrals_module).
    lambda is named `lam` in the generated code (a Python keyword otherwise)."""
    from .models.spec import Model

    lam_s = sp.Symbol("lam", real=True)
    ren = {lam: lam_s}
    params = [p.subs(ren) for p in PARAMS]
    meaning = ("bending stiffness B1", "bending stiffness B2", "torsional stiffness", "shear compliance 1/H",
               "shear compliance 1/J", "extensional compliance 1/K", "lambda = I Bbar: current times field strength")
    ranges = [(0, sp.oo)] * 6 + [(-sp.oo, sp.oo)]
    parameters = {p: (mn, rg, 1) for p, mn, rg in zip(params, meaning, ranges)}
    fi = first_integrals({})
    cas = {k: sp.expand(fi[k].subs(ren)) for k in ("C1", "C2", "C3")}
    cands = {"I1": (fi["I1"], "eq:magnetic_lagrange"), "I2": (sp.expand(fi["I2"].subs(ren)), "eq:int2")}
    return Model("paper-family", "the paper's rod family: anisotropic, extensible, shearable, in a field (compliance "
                 "form)", "this paper (sec. 2)",
                 list(X), parameters, structure_matrix().subs(ren), sp.expand(hamiltonian_compliance().subs(ren)),
                 candidates=cands, casimirs=cas)


def module() -> str:
    """generated/first_integrals.py: model()'s search data, by the generator of every model's (pipeline)."""
    from .models import pipeline

    m = model()
    fs = {"H": m.H, **m.casimirs, **{k: e for k, (e, _) in m.candidates.items()}}
    return pipeline.first_integrals_module(m, fs)
