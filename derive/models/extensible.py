"""extensible: the isotropic, extensible and shearable rod without a field ([Stump00]: still integrable):
W = (B (u1^2 + u2^2) + C u3^2 + S (v1^2 + v2^2) + K (v3 - 1)^2) / 2 on se(3)* (eq:hyperelastic with B1 = B2 and
equal shear stiffnesses H = J =: S)."""
import sympy as sp

from .algebras import BENDING, SE3_STATE, SHEAR, m3, se3_structure, u1, u2, u3, v1, v2, v3

B, C, S, K = sp.symbols("B C S K", positive=True)

NAME = "extensible"
TITLE = "isotropic extensible, shearable rod"
SOURCE = "Stump00"
STATE = SE3_STATE
PARAMETERS = {B: ("bending stiffness B1 = B2", (0, sp.oo), 1), C: ("torsional stiffness", (0, sp.oo), sp.Rational(3, 4)),
              S: ("shear stiffness H = J", (0, sp.oo), 8), K: ("extensional stiffness", (0, sp.oo), 5)}
W = (B * (u1**2 + u2**2) + C * u3**2 + S * (v1**2 + v2**2) + K * (v3 - 1) ** 2) / 2
STRAINS = BENDING + SHEAR
J = se3_structure()
CANDIDATES = {"I1": (m3, "Stump00 (m.d3 survives extensibility and shear)")}
SECTION = SE3_STATE[0]
REFERENCE = {SE3_STATE[0]: 0.2, SE3_STATE[1]: 0.1, m3: 0.5, SE3_STATE[3]: 0.3, SE3_STATE[4]: 0.1, SE3_STATE[5]: 0.9}
