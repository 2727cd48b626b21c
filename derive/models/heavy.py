"""Why the heavy rod is not in the registry ([Gottlieb99]: gravity destroys integrability).

The heavy rod's body-frame equations (isotropic, inextensible; e3 = the body components of the vertical, rho g
the weight per length):
    m' = m x u + n x d3,   n' = n x u - rho g e3,   e3' = e3 x u,   u = (m1/B, m2/B, m3/C),
i.e. the field of the Kirchhoff rod on (m, n, e3) plus the constant-in-x term (0, -rho g e3, 0).  Every structure
matrix of the registry on (m, n, e3) -- the magnetic bracket eq:noncanonical_structure at any lambda, including
lambda = 0 (the semidirect product se(3) x R^3) -- has the Casimir e3.n (found by the ansatz in
derive/models/pipeline.py).  A Casimir is conserved by *every* Hamiltonian flow of its bracket, whatever H; along
the heavy rod's flow d(e3.n)/ds = -rho g |e3|^2 != 0.  Hence the heavy rod's field is not J grad G for any
function G and any of these brackets: gravity breaks the Lie-Poisson structure (the force is not a conserved
space vector: the weight makes n grow linearly along the rod, n_space(s) = n0 - rho g s e3).  The rod is
Hamiltonian again only on a larger phase space (the height z = r.e3 as a coordinate, with explicit dependence
on it), which is not of the registry's form (state, W, a Lie-Poisson J)."""
from __future__ import annotations

import sympy as sp

from ..model import X, evec, mvec, nvec, structure_matrix
from ..results import HOLDS, Result, fmt
from . import magnetic
from .pipeline import casimirs, gradient
from .spec import load_module

rho_g = sp.Symbol("rho_g", positive=True)


def heavy_field(model):
    """The heavy rod's body-frame vector field: the Kirchhoff rod on (m, n, e3) plus (0, -rho g e3, 0)."""
    u = sp.Matrix([sp.diff(model.H, x) for x in mvec])
    d3 = sp.Matrix([0, 0, 1])
    return sp.Matrix.vstack(mvec.cross(u) + nvec.cross(d3), nvec.cross(u) - rho_g * evec, evec.cross(u))


def derive_results():
    base = load_module(magnetic)
    lam0 = next(p for p in base.params if str(p) == "lam")
    out = {}
    for label, lam_value in (("lambda = 0 (se(3) x R^3)", 0), ("lambda generic (eq:noncanonical_structure)", lam0)):
        m = load_module(magnetic)
        m.J = structure_matrix(lam_value)
        f = heavy_field(m)
        changes = {}
        for c in casimirs(m):
            rate = sp.factor(sp.expand((gradient(c, X).T * f)[0, 0]))
            changes[fmt(c)] = fmt(rate)
        out[label] = changes
    broken = all(any(v != "0" for v in ch.values()) for ch in out.values())
    return [Result("heavy_rod", "Gottlieb99", "The heavy rod is not a Lie-Poisson system of the registry's brackets: "
                   "its flow changes a Casimir", HOLDS if broken else "disagrees",
                   "symbolic: the derivative of each Casimir found along the heavy rod's field, expanded and factored",
                   {"d/ds Casimir along the heavy rod": out,
                    "reason": "e3.n is a Casimir of every bracket here, so every Hamiltonian flow conserves it; "
                              "gravity gives d(e3.n)/ds = -rho g |e3|^2 != 0",
                    "registered": False})]
