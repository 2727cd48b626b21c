"""Data for the exact search for polynomial first integrals (issue 20, item 4; magrod/integrability/
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

from .codegen import BallPrinter, function_source, module_source
from .model import B1, B2, C, X, cH, cJ, cK, lam, structure_matrix
from .poisson import first_integrals, hamiltonian_compliance
from .results import DISAGREES, HOLDS, Result

PARAMS = (B1, B2, C, cH, cJ, cK, lam)
PARAM_NAMES = ("B1", "B2", "C", "c_H", "c_J", "c_K", "lam")
NAMES = dict(zip(PARAMS, PARAM_NAMES))


class FractionPrinter(BallPrinter):
    """BallPrinter whose `_Q(p, q)` is fractions.Fraction: the generated arithmetic is exact over Q (the model
    data here are rational functions of the constants: no sqrt, no pi, no transcendental function)."""

    def pow_int(self, src: str, k: int) -> str:
        return src if k == 1 else f"({src} ** {k})"  # exact Fractions: ** is exact

    def p(self, e):
        if e is sp.pi or (isinstance(e, sp.Function)) or (e.is_Pow and not e.exp.is_Integer):
            raise TypeError(f"not a rational function: {e}")
        return super().p(e)


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


def module() -> str:
    pr = FractionPrinter(NAMES)
    pol = polynomials()
    parts, consts = [], {"PARAMETERS": PARAM_NAMES}
    for k, (monos, coefs) in pol.items():
        consts[f"{k}_MONOMIALS"] = tuple(monos)
        parts.append(function_source(k, list(PARAM_NAMES), list(coefs), pr,
                                     f"Coefficients of {k} in the order of {k}_MONOMIALS (exponents of BODY_STATE)."))
    st = structure_terms()
    consts["STRUCTURE_TERMS"] = tuple((i, j, k) for i, j, k, _ in st)
    parts.append(function_source("structure", list(PARAM_NAMES), [c for *_, c in st], pr,
                                 "Coefficients c with J_ij = sum c x_k, in the order of STRUCTURE_TERMS (i, j, k)."))
    return module_source("Exact data of the polynomial first-integral search (issue 20): H, J(x; lambda) and the "
                         "known integrals as monomials with rational coefficients (fractions.Fraction).",
                         "first_integrals.py", parts, consts, lib=None,
                         imports=("from fractions import Fraction as _Q",))
