"""The named structure matrices of the rod models (one place): the Lie-Poisson bracket of se(3)* (the force-free
rod: state (m, n)) and the magnetic bracket of eq:noncanonical_structure (state (m, n, e3); derive/model.py)."""
from __future__ import annotations

import sympy as sp

from ..model import hat, m1, m2, m3, mvec, n1, n2, n3, nvec, structure_matrix, u1, u2, u3, v1, v2, v3

SE3_STATE = [m1, m2, m3, n1, n2, n3]
BENDING = [(u1, m1), (u2, m2), (u3, m3)]
SHEAR = [(v1, n1), (v2, n2), (v3, n3)]
INEXTENSIBLE = {v1: 0, v2: 0, v3: 1}  # v = d3: unshearable and inextensible


def se3_structure():
    """The Lie-Poisson structure of se(3)* in body coordinates (m, n): m' = m x grad_m H + n x grad_n H,
    n' = n x grad_m H (the Kirchhoff rod; eq:noncanonical_structure with the e3 block and lambda removed)."""
    Z = sp.zeros(3, 3)
    return sp.Matrix.vstack(sp.Matrix.hstack(hat(mvec), hat(nvec)), sp.Matrix.hstack(hat(nvec), Z))


magnetic_structure = structure_matrix  # eq:noncanonical_structure (9x9, lambda)

__all__ = ["SE3_STATE", "BENDING", "SHEAR", "INEXTENSIBLE", "se3_structure", "magnetic_structure", "m1", "m2", "m3",
           "n1", "n2", "n3", "u1", "u2", "u3", "v1", "v2", "v3"]
