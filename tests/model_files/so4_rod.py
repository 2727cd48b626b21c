"""A rod on the Lie-Poisson algebra so(4)* (deformed by kappa): {m_i, m_j} = e_ijk m_k, {m_i, n_j} = e_ijk n_k,
{n_i, n_j} = kappa e_ijk m_k.  kappa = 0 is e(3)* (the Kirchhoff rod's bracket), kappa > 0 so(4)*, kappa < 0
so(3,1)*: one family, every kappa legal.  Its Casimirs are m.n and kappa |m|^2 + |n|^2 (at kappa = 0: |n|^2).
A user's model file written from scratch, outside the registry (tests/test_models_defects.py)."""
import sympy as sp

m1, m2, m3, n1, n2, n3 = sp.symbols("m1 m2 m3 n1 n2 n3", real=True)
A, C = sp.symbols("A C", positive=True)
kappa = sp.Symbol("kappa", real=True)


def hat(a):
    return sp.Matrix([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])


m, n = sp.Matrix([m1, m2, m3]), sp.Matrix([n1, n2, n3])
NAME = "so4-rod"
TITLE = "Lagrange rod on so(4)*"
SOURCE = "a user's rod (tests)"
STATE = [m1, m2, m3, n1, n2, n3]
PARAMETERS = {A: ("bending stiffness", (0, sp.oo), 1), C: ("torsional stiffness", (0, sp.oo), 2),
              kappa: ("curvature of the algebra", (-sp.oo, sp.oo), 1)}
J = sp.Matrix.vstack(sp.Matrix.hstack(hat(m), hat(n)), sp.Matrix.hstack(hat(n), kappa * hat(m)))
H = (m1**2 + m2**2) / (2 * A) + m3**2 / (2 * C) + n3
REFERENCE = {m1: 0.3, m2: 0.2, m3: 0.5, n1: 0.1, n2: -0.2, n3: 0.9}
