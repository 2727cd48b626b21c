"""The model, entered once (paper sec. 2).  Everything else in derive/ is derived from this module.

Inputs, and only these, are typed in from the paper:
  * the body-frame state (m, n, e3) in R^9                               (sec. 2.3)
  * the linearly elastic strain energy W(u, v)                            eq:hyperelastic
  * the structure matrix J(m, n, e3; lambda)                              eq:noncanonical_structure
  * the Euler-angle chart of SO(3), built from elementary rotations       (sec. 4, matrix R)

The Hamiltonian is *not* typed in: it is the Legendre transform of W (compared with eq:magnetic_ham in
derive/poisson.py).
"""
from __future__ import annotations

import sympy as sp

# --- state ---------------------------------------------------------------------------------------
m1, m2, m3 = sp.symbols("m1 m2 m3", real=True)
n1, n2, n3 = sp.symbols("n1 n2 n3", real=True)
e1, e2, e3 = sp.symbols("e31 e32 e33", real=True)  # body components of the field direction e_3
mvec = sp.Matrix([m1, m2, m3])
nvec = sp.Matrix([n1, n2, n3])
evec = sp.Matrix([e1, e2, e3])
X = [m1, m2, m3, n1, n2, n3, e1, e2, e3]  # ordering of the 9-D state everywhere in magrod

# --- constants -------------------------------------------------------------------------------------
# Stiffnesses (eq:hyperelastic).  The shear stiffness called H in the paper is `Hs` here so that it
# cannot be confused with the Hamiltonian.
B1, B2, C = sp.symbols("B1 B2 C", positive=True)
Hs, J, K = sp.symbols("H J K", positive=True)
lam = sp.symbols("lambda", real=True)  # lambda = I * Bbar (current times field strength)
B = sp.symbols("B", positive=True)  # isotropic bending stiffness B1 = B2 =: B
# Compliances 1/H, 1/J, 1/K: the inextensible/unshearable rod is the limit of zero compliance.
cH, cJ, cK = sp.symbols("c_H c_J c_K", nonnegative=True)

# --- strains ---------------------------------------------------------------------------------------
u1, u2, u3, v1, v2, v3 = sp.symbols("u1 u2 u3 v1 v2 v3", real=True)
uvec = sp.Matrix([u1, u2, u3])
vvec = sp.Matrix([v1, v2, v3])
d3 = sp.Matrix([0, 0, 1])  # body components of d_3


def strain_energy():
    """eq:hyperelastic -- the linearly elastic strain energy density W(u, v)."""
    return (B1 * u1**2 + B2 * u2**2 + C * u3**2 + Hs * v1**2 + J * v2**2 + K * (v3 - 1) ** 2) / 2


def hat(a):
    """eq:isomorphism -- hat map R^3 -> so(3), hat(a) b = a x b."""
    return sp.Matrix([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])


def structure_matrix(lam_=lam):
    """eq:noncanonical_structure -- J(m, n, e3; lambda), 9x9, skew."""
    Z = sp.zeros(3, 3)
    top = sp.Matrix.hstack(hat(mvec), hat(nvec), hat(evec))
    mid = sp.Matrix.hstack(hat(nvec), lam_ * hat(evec), Z)
    bot = sp.Matrix.hstack(hat(evec), Z, Z)
    return sp.Matrix.vstack(top, mid, bot)


def gradient(f, xs=X):
    return sp.Matrix([sp.diff(f, x) for x in xs])


def bracket(f, g, lam_=lam):
    """{f, g} = grad f . J grad g, i.e. eq:magnetic_bracket written with the structure matrix."""
    return (gradient(f).T * structure_matrix(lam_) * gradient(g))[0, 0]


# --- Euler-angle chart -----------------------------------------------------------------------------
theta, psi, phi = sp.symbols("theta psi phi", real=True)
p_theta, p_psi, p_phi = sp.symbols("p_theta p_psi p_phi", real=True)


def _frame_rot_z(a):
    # passive rotation about the 3-axis: components in a frame turned by angle a
    return sp.Matrix([[sp.cos(a), sp.sin(a), 0], [-sp.sin(a), sp.cos(a), 0], [0, 0, 1]])


def _frame_rot_y(a):
    return sp.Matrix([[sp.cos(a), 0, -sp.sin(a)], [0, 1, 0], [sp.sin(a), 0, sp.cos(a)]])


def euler_rotation(th=theta, ps=psi, ph=phi):
    """R(theta, psi, phi) = R_z(phi) R_y(theta) R_z(psi): maps space components to body components.

    Row i holds the space components of director d_i, so (row 3) d_3 makes angle theta with the field
    direction e_3 and has azimuth psi about it; phi is the twist about d_3.  Compared with the matrix R
    printed in sec. 4 in derive/reduction.py.
    """
    return _frame_rot_z(ph) * _frame_rot_y(th) * _frame_rot_z(ps)
