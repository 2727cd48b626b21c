"""magnetic-extensible: the paper's rod (the default of magrod): isotropic (B1 = B2), extensible and shearable, in a
uniform field, at the numeric scale of derive/numeric_scale.py (B = C = m3 = 1, eq:nondim_1) with the
non-dimensional parameters (m, mu, gamma, delta, lambdabar) of the paper's figures -- the runtime parameters of
generated/names.py.  H, J and the Casimirs are those the paper's own pipeline derives (derive/numeric_scale.py from
derive/model.py's W and J, eq:hyperelastic, eq:noncanonical_structure, eq:magnetic_casimirs1-3); nothing is typed in
here.  Generated ONCE, with the paper's tree at generated/ top level (derive/build.py: names.py, body.py,
integrals.py, model_report.json): the registry's entry is that tree, not a copy of it.

mu does not enter H or J: it fixes the Casimir level C1 = (mu + 1)/(2 m^4) of the paper's chart (eq:nondim_1);
a body-frame orbit of this model lies on whatever level its start has."""
import sympy as sp

from .. import numeric_scale as ns
from ..model import X, m1, m2, m3, n1, n2, n3, e1, e2, e3, structure_matrix
from ..paper import delta, gamma, lambar, m, mu

lam = sp.Symbol("lam", real=True)  # lambdabar of the paper (runtime name `lam`, generated/names.py PARAMS)
_SUB = {lambar: lam}

NAME = "magnetic-extensible"
TITLE = "the paper's rod: isotropic, extensible, shearable, conducting, in a uniform magnetic field"
SOURCE = "this paper (sec. 2, eq:nondim_1)"
STATE = X
PARAMETERS = {m: ("m = m3/sqrt(B C2)", (0, sp.oo), sp.Rational(17, 10)),
              mu: ("mu = 2 C1 B/m3^2 - 1: the Casimir level of the chart", (-sp.oo, sp.oo), sp.Rational(2, 5)),
              gamma: ("gamma = C2 (1/K - 1/J): extensibility less shear", (-sp.oo, sp.oo), 3),
              delta: ("delta = C2/J: shearability", (0, sp.oo), 3),
              lam: ("lambdabar = lambda B^2/m3^3: current times field strength", (-sp.oo, sp.oo),
                    sp.Rational(27, 200))}
H = ns.body_hamiltonian().subs(_SUB)
J = structure_matrix(ns.LAMBDA_BODY).subs(_SUB)
CASIMIRS = {f"C{i}": c.subs(_SUB) for i, c in enumerate(ns.casimirs_body(), 1)}  # eq:magnetic_casimirs1-3
CANDIDATES = {"I1": (m3, "eq:magnetic_lagrange"),
              "I2": (n1 * m1 + n2 * m2 + n3 * m3 + ns.LAMBDA_BODY.subs(_SUB) * e3, "eq:int2 (Sinden08)")}
SECTION = ns.events_body()["section"]  # e31 n2 - e32 n1 = sin(theta) rho sin(psi): the paper's section
REFERENCE = {m1: 0.2, m2: 0.1, m3: 1.0, n1: 0.1, n2: 0.05, n3: 0.35, e1: 0.3, e2: 0.1, e3: 0.95}
