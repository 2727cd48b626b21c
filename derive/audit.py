"""Audit of the authors' Fortran (djps/homoclinic-orbits) against the derived equations, term by term.
The transcription is a comparison target in derive/paper.py (djps_fortran_rhs); here its right-hand side is
compared with x' = J(lambda) grad H of derive/poisson.py under the parameter map (their names -> ours):

    force x1..x3 = m^2 n (their force is scaled by m^2: n3 = 1 on the straight rod), moment x4..x6 = m,
    u = ((1 + rho) m1, m2, (1 + nu) m3):  B1 = 1/(1 + rho), B2 = 1, C = 1/(1 + nu),
    v = (eps (1 + gamma_F) n1, eps n2, 1 + eps (1 + sigma_F) n3) in their n-equation:
        c_H = m^2 eps (1 + gamma_F), c_J = m^2 eps, c_K = m^2 eps (1 + sigma_F)   (paper: delta = eps, gamma = eps sigma_F
        for gamma_F = 0, i.e. sigma_F = gamma/delta),
    lambda = lambda_F/m^2,  e3 (body) = (2(q1 q3 - q2 q4), 2(q1 q4 + q2 q3), q3^2 + q4^2 - q1^2 - q2^2),
    derivatives: d(x1..x3)/dt = m^2 n',  d(x4..x6)/dt = m'  (their xT factor is the time scaling to [0, 1])."""
from __future__ import annotations

import sympy as sp

from .model import B1, B2, C, X, cH, cJ, cK, lam
from .paper import djps_fortran_rhs
from .poisson import equations_of_motion, hamiltonian_compliance
from .results import DISAGREES, HOLDS, Result, fmt


def fortran_differences():
    """[their F(k) - ours(k)] for k = 1..6 under the parameter map (module docstring), factored."""
    s, E, F = djps_fortran_rhs()
    x1, x2, x3, x4, x5, x6 = s["x"]
    mm, eF, gF, sF = s["m"], s["epsilon"], s["gamma"], s["sigma"]
    eom = equations_of_motion(hamiltonian_compliance())
    sub = {B1: 1 / (1 + s["rho"]), B2: 1, C: 1 / (1 + s["nu"]), cH: mm**2 * eF * (1 + gF), cJ: mm**2 * eF,
           cK: mm**2 * eF * (1 + sF), lam: s["lam"] / mm**2}
    state = dict(zip(X, [x4, x5, x6, x1 / mm**2, x2 / mm**2, x3 / mm**2, *E]))
    ours = [e.subs(sub).subs(state, simultaneous=True) for e in eom]
    mine = [mm**2 * ours[3], mm**2 * ours[4], mm**2 * ours[5], ours[0], ours[1], ours[2]]
    return [sp.factor(sp.expand(a - b)) for a, b in zip(F, mine)], (gF, sF)


def derive_all():
    diffs, (gF, sF) = fortran_differences()
    force_ok = all(d == 0 for d in diffs[:3])
    moment_at_equal = all(sp.simplify(d.subs(sF, gF)) == 0 for d in diffs[3:])
    return [Result(
        "fortran_djps_equations", "eq:magnetic_moment, eq:magnetic_force (the authors' shooting code)",
        "djps/homoclinic-orbits newton.f term by term: the force equations F(1)-F(3) equal the derived n' = n x u + "
        "lambda e3 x v (not the printed d3 + v); the moment equations F(4)-F(6) use v with gamma_F and sigma_F "
        "interchanged (c_H <-> c_K in m' = m x u + n x v), so they equal the derived ones only if gamma_F = sigma_F",
        DISAGREES if force_ok and not all(d == 0 for d in diffs[3:]) and moment_at_equal else
        (HOLDS if all(d == 0 for d in diffs) else DISAGREES),
        "symbolic: transcribed F minus derived J grad H under the parameter map of derive/audit.py, factored",
        {"F(k) - derived (k = 1..6)": [fmt(d) for d in diffs],
         "force equations equal": force_ok, "moment equations equal when gamma_F = sigma_F": moment_at_equal,
         "note": "monodromy.f (the linearisation about the straight rod) has (1 + eps sigma_F) and (1 + eps (sigma_F - "
                 "gamma_F)), i.e. the derived form; the committed shooting.f sets xgamma = xsigma = xepsilon = xlambda "
                 "= 0, where the difference vanishes"})]
