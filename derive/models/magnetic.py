"""magnetic: the isotropic inextensible, unshearable conducting rod in a uniform field ([Sinden08]: integrable,
with I2 = n.m + B lambda e3.d3, eq:int2).  The bracket is the paper's eq:noncanonical_structure (derive/model.py)."""
import sympy as sp

from .. import paper
from ..model import X, m3
from .algebras import BENDING, INEXTENSIBLE, SHEAR, magnetic_structure, u1, u2, u3

B, C = sp.symbols("B C", positive=True)
lam = sp.Symbol("lam", real=True)  # lambda of the paper (a Python keyword: `lam` in code)

NAME = "magnetic"
TITLE = "isotropic inextensible conducting rod in a uniform magnetic field"
SOURCE = "Sinden08"
STATE = X
PARAMETERS = {B: ("bending stiffness B1 = B2", (0, sp.oo), 1), C: ("torsional stiffness", (0, sp.oo), sp.Rational(3, 4)),
              lam: ("lambda = I Bbar: current times field strength", (-sp.oo, sp.oo), sp.Rational(1, 4))}
W = (B * (u1**2 + u2**2) + C * u3**2) / 2
STRAINS = BENDING + SHEAR
FIXED = INEXTENSIBLE
J = magnetic_structure(lam)
CANDIDATES = {"I1": (m3, "Sinden08 (eq:magnetic_lagrange)"),
              # the printed eq:int2 (derive/paper.py) in this model's symbols: a comparison target, tested
              "I2": (paper.eq_int2().subs({paper.B: B, paper.lam: lam}), "Sinden08 (eq:int2)")}
SECTION = X[0]
REFERENCE = {X[0]: 0.2, X[1]: 0.1, m3: 0.5, X[3]: 0.3, X[4]: 0.1, X[5]: 0.9, X[6]: 0.6, X[7]: 0.0, X[8]: 0.8}
