"""magnetic-extensible: the paper's rod (the default of magrod): isotropic (B1 = B2 =: B, shear H = J =: S),
extensible and shearable, in a uniform field.  W and J are those of derive/model.py (entered once there,
eq:hyperelastic, eq:noncanonical_structure); only the isotropy substitution is made here.  The paper's own
pipeline (generated/ at the top level) is unchanged; this entry puts the same model through the generic one."""
import sympy as sp

from .. import model as paper_model
from ..model import X, e3, m3, mvec, nvec

B, S = sp.symbols("B S", positive=True)
lam = sp.Symbol("lam", real=True)  # lambda of the paper (a Python keyword: `lam` in code)

NAME = "magnetic-extensible"
TITLE = "the paper's rod: isotropic, extensible, shearable, conducting, in a uniform magnetic field"
SOURCE = "this paper (sec. 2)"
STATE = X
PARAMETERS = {B: ("bending stiffness B1 = B2", (0, sp.oo), 1),
              paper_model.C: ("torsional stiffness", (0, sp.oo), sp.Rational(3, 4)),
              S: ("shear stiffness H = J", (0, sp.oo), 8), paper_model.K: ("extensional stiffness", (0, sp.oo), 5),
              lam: ("lambda = I Bbar: current times field strength", (-sp.oo, sp.oo), sp.Rational(1, 4))}
W = paper_model.strain_energy().subs({paper_model.B1: B, paper_model.B2: B, paper_model.Hs: S, paper_model.J: S})
STRAINS = [(paper_model.u1, X[0]), (paper_model.u2, X[1]), (paper_model.u3, X[2]),
           (paper_model.v1, X[3]), (paper_model.v2, X[4]), (paper_model.v3, X[5])]
J = paper_model.structure_matrix(lam)
CANDIDATES = {"I1": (m3, "eq:magnetic_lagrange"), "I2": (nvec.dot(mvec) + B * lam * e3, "eq:int2 (Sinden08)")}
SECTION = X[0]
REFERENCE = {X[0]: 0.2, X[1]: 0.1, m3: 0.5, X[3]: 0.3, X[4]: 0.1, X[5]: 0.9, X[6]: 0.6, X[7]: 0.0, X[8]: 0.8}
