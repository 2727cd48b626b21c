"""A gyrostat rod not in the registry: an anisotropic inextensible rod with a linear gyrostatic term K u1 in W
(a user's model file, compiled into the model cache; tests/test_engine_models.py)."""
import sympy as sp
m1, m2, m3, n1, n2, n3 = sp.symbols("m1 m2 m3 n1 n2 n3", real=True)
u1, u2, u3 = sp.symbols("u1 u2 u3", real=True)
v1, v2, v3 = sp.symbols("v1 v2 v3", real=True)
A, B, C = sp.symbols("A B C", positive=True)
K = sp.Symbol("K", real=True)

def hat(a):
    return sp.Matrix([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])

m, n = sp.Matrix([m1, m2, m3]), sp.Matrix([n1, n2, n3])
NAME = "gyro-rod"
STATE = [m1, m2, m3, n1, n2, n3]
PARAMETERS = {A: ("bending stiffness about d1", (0, sp.oo), 1), B: ("bending stiffness about d2", (0, sp.oo), 2),
              C: ("torsional stiffness", (0, sp.oo), sp.Rational(3, 2)),
              K: ("gyrostatic moment about d1", (-sp.oo, sp.oo), sp.Rational(3, 10))}
J = sp.Matrix.vstack(sp.Matrix.hstack(hat(m), hat(n)), sp.Matrix.hstack(hat(n), sp.zeros(3, 3)))
W = (A * u1**2 + B * u2**2 + C * u3**2) / 2 + K * u1
STRAINS = [(u1, m1), (u2, m2), (u3, m3), (v1, n1), (v2, n2), (v3, n3)]
FIXED = {v1: 0, v2: 0, v3: 1}
CANDIDATES = {"I1": (m3, "Kehrbaum97b")}
