"""Ball-arithmetic vector fields for the validated (computer-assisted) integrator of magrod.proof.

What is generated (generated/validated.py, python-flint source printed by codegen.BallPrinter):
  * the reduced chart field f(x) of Hbar, x = (theta, psi, pbar_theta, pbar_psi)  (Hamilton's equations, the same
    SymPy expressions as generated/reduced.py), its Jacobian Df (4 x 4, by sp.diff) and Hbar itself;
  * the singularity-free body-frame field (quadratic in (m, n, e3)) and its Jacobian (9 x 9), for the
    containment tests against the closed-form lambdabar = 0 homoclinic orbit;
  * the chart reversor R = diag(1, -1, -1, 1) (derive/symmetry.py: reversor_reduced), as data.
Every function takes the state and the parameters as two sequences and returns a list; common subexpressions are
hoisted (sp.cse), so one call costs one evaluation of each distinct subexpression.  The same source evaluates
`arb` balls and `arb_series` power series: magrod.proof.taylor gets the Taylor coefficients of a solution by
Picard iteration on arb_series (Arb's rigorous series arithmetic for sin, cos, sqrt, division), so no Taylor
recurrence is written by hand anywhere.  Rationals are exact (`_Q(p, q)`); BallPrinter refuses rounded numbers.
"""
from __future__ import annotations

import sympy as sp

from . import numeric_scale as ns
from . import reduction
from .codegen import BallPrinter, module_source
from .model import X, phi, psi, theta
from .paper import delta, gamma, lambar, m, mu, pps, pth
from .results import DISAGREES, HOLDS, Result, fmt

PAR_NAMES = {m: "m", mu: "mu", gamma: "gamma", delta: "delta", lambar: "lam"}
PAR_ARGS = ["m", "mu", "gamma", "delta", "lam"]
CHART_SYMS = [theta, psi, pth, pps]
CHART_ARGS = ["theta", "psi", "ptheta", "ppsi"]
BODY_ARGS = ["m1", "m2", "m3", "n1", "n2", "n3", "e31", "e32", "e33"]
# f(R x) = -R f(x) for this R is proved symbolically in derive/symmetry.py (report entry reversor_reduced)
CHART_REVERSOR = (1, -1, -1, 1)


class ProductPrinter(BallPrinter):
    """BallPrinter with integer powers written as products: python-flint's `x ** k` on an arb ball that contains
    0 returns nan (it goes through the real power x^y = exp(y log x)), e.g. sin(psi)^2 at psi = 0 +- r."""

    def p(self, e):
        if e.is_Pow and e.exp.is_Integer and e.exp != 0:
            k = int(e.exp)
            prod = " * ".join([f"({self.p(e.base)})"] * abs(k))
            return f"({prod})" if k > 0 else f"(_Q(1, 1) / ({prod}))"
        if e.is_Pow and e.exp.is_Rational and e.exp.q == 2:
            k = int(e.exp.p)
            inner = f"(({self.p(e.base)}).sqrt())"
            prod = " * ".join([inner] * abs(k))
            return f"({prod})" if k > 0 else f"(_Q(1, 1) / ({prod}))"
        return super().p(e)


def cse_function_source(name: str, state_args: list[str], state_syms, exprs, doc: str) -> str:
    """def name(x, p): unpack, hoist common subexpressions (sp.cse), return a list of balls / series."""
    reps, red = sp.cse(list(exprs), symbols=sp.numbered_symbols("_c"), order="canonical")
    names = {**dict(zip(state_syms, state_args)), **PAR_NAMES}
    for s, _ in reps:
        names[s] = str(s)
    pr = ProductPrinter(names)
    lines = [f"def {name}(x, p):", f'    """{doc}"""',
             f"    {', '.join(state_args)}, = x",
             f"    {', '.join(PAR_ARGS)}, = p"]
    for s, e in reps:
        lines.append(f"    {s} = {pr(e)}")
    lines.append("    return [")
    lines.extend(f"        {pr(e)}," for e in red)
    lines.append("    ]")
    return "\n".join(lines) + "\n"


def body_events():
    """Polynomials in (m, n, e3) that the proof evaluates at the section (each = its chart form, lift_checks):
    g = e32 m1 - e31 m2 = sin(theta) pbar_theta (the section Sigma), Gs = e31 n2 - e32 n1 = sin(theta) rho sin(psi),
    Gc = (e31^2 + e32^2) n3 - e33 (e31 n1 + e32 n2) = sin(theta) rho cos(psi), s2 = e31^2 + e32^2 = sin(theta)^2,
    rad = mu - 2 lambdabar m.e3 = mu - 2 lambdabar pbar_psi, e33 = cos(theta)."""
    m1, m2, m3, n1, n2, n3, e1, e2, e3 = X
    return {"g": e2 * m1 - e1 * m2, "Gs": e1 * n2 - e2 * n1, "Gc": (e1**2 + e2**2) * n3 - e3 * (e1 * n1 + e2 * n2),
            "s2": e1**2 + e2**2, "rad": mu - 2 * lambar * (m1 * e1 + m2 * e2 + m3 * e3), "e33": e3}


def chart_forms():
    rho = sp.sqrt(reduction.RHO2_BAR) / m**2
    return {"g": sp.sin(theta) * pth, "Gs": sp.sin(theta) * rho * sp.sin(psi), "Gc": sp.sin(theta) * rho * sp.cos(psi),
            "s2": sp.sin(theta) ** 2, "rad": reduction.RHO2_BAR, "e33": sp.cos(theta)}


def lift_checks(chart_rhs):
    """The lift X(theta, psi, phi, pbar_theta, pbar_psi) (numeric_scale.euler_to_body, p_phi = 1) intertwines the
    flows: f_body(X(q)) = DX(q) (f_chart(q), Omega(q)), Omega = phi' = (1 - pbar_psi cos theta)/sin^2 theta (solved
    from the e31, e32 components, then all 9 checked); so a body solution from X(q0, 0) is X(q(t), phi(t)) with q(t)
    the chart solution, as long as the chart is defined (sin(theta) > 0, radicand > 0).  Also every body event equals its chart
    form.  Returns (ok, details); all by trig normal forms (reduction.trig_normal_form)."""
    Xq = [sp.sympify(e) for e in ns.euler_to_body()]
    fb = ns.body_rhs()
    sub = dict(zip(X, Xq))
    q4 = CHART_SYMS
    D = [sp.expand(fb[i].subs(sub, simultaneous=True) - sum(sp.diff(Xq[i], q) * chart_rhs[j] for j, q in enumerate(q4)))
         for i in range(9)]
    dphi = [sp.diff(e, phi) for e in Xq]
    e31, e32 = X.index(X[6]), X.index(X[7])
    Om = (D[e31] * sp.sin(phi) + D[e32] * sp.cos(phi)) / sp.sin(theta)
    res = [reduction.trig_normal_form(sp.sin(theta) * D[i] - sp.sin(theta) * Om * dphi[i], reduction.RHO2_BAR)
           for i in range(9)]
    cf = chart_forms()
    ev = {k: reduction.trig_normal_form(sp.expand(e.subs(sub, simultaneous=True) - cf[k]), reduction.RHO2_BAR)
          for k, e in body_events().items()}
    omega = (1 - pps * sp.cos(theta)) / sp.sin(theta) ** 2
    om_res = reduction.trig_normal_form(sp.expand(Om * sp.sin(theta) ** 3 - omega * sp.sin(theta) ** 3), reduction.RHO2_BAR)
    ok = all(r == 0 for r in res) and all(v == 0 for v in ev.values()) and om_res == 0
    return ok, {"Omega = phi'": fmt(omega), "Omega residual": fmt(om_res), "intertwining residuals": [fmt(r) for r in res],
                "event residuals": {k: fmt(v) for k, v in ev.items()}}


def jacobian(f, xs):
    return [sp.diff(fi, xj) for fi in f for xj in xs]


def hamilton_check(Hbar, rhs) -> bool:
    """The chart field is Hamilton's equations of Hbar in the canonical pairs (theta, pbar_theta), (psi, pbar_psi)."""
    ham = [sp.diff(Hbar, pth), sp.diff(Hbar, pps), -sp.diff(Hbar, theta), -sp.diff(Hbar, psi)]
    return all(sp.expand(a - b) == 0 for a, b in zip(ham, rhs))


def module(chart: dict, body: dict) -> str:
    """generated/validated.py from the reduced module's {"Hbar", "rhs"} and the body module's {"H", "rhs"}."""
    f, H = list(chart["rhs"]), chart["Hbar"]
    fb = list(body["rhs"])
    lift0 = [sp.expand(sp.sympify(e).subs(phi, 0)) for e in ns.euler_to_body()]
    ev = body_events()
    parts = [
        cse_function_source("chart_rhs", CHART_ARGS, CHART_SYMS, f,
                            "Hamilton's equations of Hbar: (theta', psi', pbar_theta', pbar_psi') (eq:full_ham_nondim)."),
        cse_function_source("chart_jacobian", CHART_ARGS, CHART_SYMS, jacobian(f, CHART_SYMS),
                            "Df of chart_rhs, row-major (4 x 4): entry [4 i + j] = d f_i / d x_j (sp.diff)."),
        cse_function_source("chart_hamiltonian", CHART_ARGS, CHART_SYMS, [H],
                            "[Hbar(theta, psi, pbar_theta, pbar_psi)] (eq:full_ham_nondim, derived)."),
        cse_function_source("body_rhs", BODY_ARGS, X, fb,
                            "x' = J(x; lambda) grad H in (m, n, e3), lambda = lambdabar/m^4 (numeric scale)."),
        cse_function_source("body_jacobian", BODY_ARGS, X, jacobian(fb, X),
                            "Df of body_rhs, row-major (9 x 9) (sp.diff)."),
        cse_function_source("body_hamiltonian", BODY_ARGS, X, [body["H"]],
                            "[H(m, n)] of eq:magnetic_ham at the numeric scale."),
        cse_function_source("lift", CHART_ARGS, CHART_SYMS, lift0,
                            "X(theta, psi, phi = 0, pbar_theta, pbar_psi): the body state (m, n, e3) of a chart state "
                            "(numeric_scale.euler_to_body, p_phi = 1)."),
        cse_function_source("lift_jacobian", CHART_ARGS, CHART_SYMS, jacobian(lift0, CHART_SYMS),
                            "dX/d(theta, psi, pbar_theta, pbar_psi) at phi = 0, row-major (9 x 4)."),
        cse_function_source("body_events", BODY_ARGS, X, list(ev.values()),
                            "[" + ", ".join(ev) + "]: " + body_events.__doc__.split(":", 1)[1].strip().replace("\n", " ")),
        cse_function_source("body_events_gradient", BODY_ARGS, X, jacobian(list(ev.values()), X),
                            "Gradients of body_events, row-major (6 x 9)."),
    ]
    consts = {"CHART_STATE": tuple(CHART_ARGS), "BODY_STATE": tuple(BODY_ARGS), "PARAMS": tuple(PAR_ARGS),
              "CHART_REVERSOR": CHART_REVERSOR, "BODY_EVENTS": tuple(ev)}
    return module_source("Ball-arithmetic (python-flint arb / arb_series) vector fields and Jacobians of the reduced "
                         "chart and the body frame, for the validated integrator of magrod.proof (issue 21).",
                         "validated.py", parts, consts, lib="arb")


def derive_all(chart: dict, body: dict) -> list[Result]:
    ok = hamilton_check(chart["Hbar"], chart["rhs"])
    lift_ok, lift_details = lift_checks(chart["rhs"])
    return [Result("chart_body_lift", "eq:canonical_moment, eq:canonical_force, eq:full_ham_nondim",
                   "The lift X(q, phi) intertwines the flows at the numeric scale: f_body(X(q)) = DX(q) (f_chart(q), "
                   "Omega(q)), Omega = (1 - pbar_psi cos theta)/sin^2 theta; and the body polynomials g, Gs, Gc, s2, rad, "
                   "e33 equal sin(theta) pbar_theta, sin(theta) rho sin(psi), sin(theta) rho cos(psi), sin^2(theta), "
                   "the radicand and cos(theta) on the chart",
                   HOLDS if lift_ok else DISAGREES,
                   "symbolic: trig normal form (mod sin^2 + cos^2 = 1, rho^2 = radicand) of sin(theta) (f_body(X) - DX "
                   "(f_chart, Omega)) and of each event minus its chart form is 0", lift_details),
            Result("validated_fields", "eq:full_ham_nondim, eq:noncanonical_structure",
                   "Ball-arithmetic chart and body fields for the computer-assisted proof: the chart field is "
                   "Hamilton's equations of Hbar, Jacobians by differentiation, the reversor R = diag(1, -1, -1, 1)",
                   HOLDS if ok else DISAGREES,
                   "symbolic: expanded difference between the printed field and d Hbar is 0; sp.diff; reversibility "
                   "is report entry reversor_reduced",
                   {"chart_reversor": list(CHART_REVERSOR), "printer": "codegen.BallPrinter (exact rationals)"})]
