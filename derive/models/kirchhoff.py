"""kirchhoff: the isotropic, inextensible, unshearable rod without a field (paper sec. 1; [Kehrbaum97b]).

W = (B (u1^2 + u2^2) + C u3^2) / 2 with v = d3 on se(3)*; completely integrable: H, m3 = m.d3 and the Casimirs
n.n, m.n (the Kirchhoff kinetic analogue of the Lagrange top)."""
import sympy as sp

from .algebras import BENDING, INEXTENSIBLE, SE3_STATE, SHEAR, m3, n3, se3_structure, u1, u2, u3

B, C = sp.symbols("B C", positive=True)

NAME = "kirchhoff"
TITLE = "isotropic, inextensible Kirchhoff rod"
SOURCE = "Kehrbaum97b"
STATE = SE3_STATE
PARAMETERS = {B: ("bending stiffness B1 = B2", (0, sp.oo), 1), C: ("torsional stiffness", (0, sp.oo), sp.Rational(3, 4))}
W = (B * (u1**2 + u2**2) + C * u3**2) / 2
STRAINS = BENDING + SHEAR
FIXED = INEXTENSIBLE
J = se3_structure()
CANDIDATES = {"I1": (m3, "Kehrbaum97b (m.d3, the Lagrange-top integral)")}
SECTION = SE3_STATE[0]  # m1 = 0
REFERENCE = {SE3_STATE[0]: 0.2, SE3_STATE[1]: 0.1, m3: 0.5, SE3_STATE[3]: 0.3, SE3_STATE[4]: 0.1, n3: 0.9}
