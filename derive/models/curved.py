"""curved: the isotropic inextensible rod with intrinsic curvature uhat = (k1, 0, k3) (bending in the d1 direction
and pre-twist): W = (B ((u1 - k1)^2 + u2^2) + C (u3 - k3)^2) / 2 ([Champneys97a; Leung04]: intrinsic curvature
destroys integrability).  With k1 = 0 (pure pre-twist) m3 is again an integral."""
import sympy as sp

from .algebras import BENDING, INEXTENSIBLE, SE3_STATE, SHEAR, m3, se3_structure, u1, u2, u3

B, C = sp.symbols("B C", positive=True)
k1, k3 = sp.symbols("k1 k3", real=True)

NAME = "curved"
TITLE = "isotropic inextensible rod with intrinsic curvature (k1, 0, k3)"
SOURCE = "Champneys97a, Leung04"
STATE = SE3_STATE
PARAMETERS = {B: ("bending stiffness B1 = B2", (0, sp.oo), 1), C: ("torsional stiffness", (0, sp.oo), sp.Rational(3, 4)),
              k1: ("intrinsic curvature about d1 (uhat1)", (-sp.oo, sp.oo), sp.Rational(1, 2)),
              k3: ("intrinsic twist (uhat3)", (-sp.oo, sp.oo), sp.Rational(1, 5))}
W = (B * ((u1 - k1) ** 2 + u2**2) + C * (u3 - k3) ** 2) / 2
STRAINS = BENDING + SHEAR
FIXED = INEXTENSIBLE
J = se3_structure()
CANDIDATES = {"I1": (m3, "Kehrbaum97b (integral of the straight isotropic rod)")}
SECTION = SE3_STATE[1]  # m2 = 0 (m1 carries the curvature offset)
REFERENCE = {SE3_STATE[0]: 0.2, SE3_STATE[1]: 0.1, m3: 0.5, SE3_STATE[3]: 0.3, SE3_STATE[4]: 0.1, SE3_STATE[5]: 0.9}
