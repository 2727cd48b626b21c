"""anisotropic: the inextensible rod with unequal bending stiffnesses B1 != B2 and a free torsional stiffness C
([Mielke88]: anisotropy destroys integrability).  The Kirchhoff kinetic analogue of a heavy top with the centre of
mass on the third principal axis (moments B1, B2, C)."""
import sympy as sp

from .algebras import BENDING, INEXTENSIBLE, SE3_STATE, SHEAR, m3, se3_structure, u1, u2, u3

B1, B2, C = sp.symbols("B1 B2 C", positive=True)

NAME = "anisotropic"
TITLE = "anisotropic inextensible rod (B1 != B2, C free)"
SOURCE = "Mielke88"
STATE = SE3_STATE
PARAMETERS = {B1: ("bending stiffness about d1", (0, sp.oo), 1), B2: ("bending stiffness about d2", (0, sp.oo), 2),
              C: ("torsional stiffness", (0, sp.oo), sp.Rational(3, 2))}
W = (B1 * u1**2 + B2 * u2**2 + C * u3**2) / 2
STRAINS = BENDING + SHEAR
FIXED = INEXTENSIBLE
J = se3_structure()
CANDIDATES = {"I1": (m3, "Kehrbaum97b (integral of the isotropic rod only)")}
SECTION = SE3_STATE[0]
REFERENCE = {SE3_STATE[0]: 0.2, SE3_STATE[1]: 0.1, m3: 0.5, SE3_STATE[3]: 0.3, SE3_STATE[4]: 0.1, SE3_STATE[5]: 0.9}
