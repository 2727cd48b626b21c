"""The Euler-angle chart of a model that has the paper's: the `magnetic` rod (parameters B, C, lam) is the paper's
rod at gamma = delta = 0 after a scaling, so its section in the chart is the paper's reduced section
(`poincare_section(mr.System("magnetic"), formulation="reduced")`).

The scaling m = m3 m~, n = (m3^2/B) n~, s = (B/m3) s~ maps the rod with B = C to the numeric scale of
derive/numeric_scale.py (B = C = m3 = 1, lambda~ = lambda B^2/m3^3); there C2~ = e3.n~ = 1/m^2,
lambda~ = lambdabar/m^4 and 2 C1~ = (mu + 1)/m^4.  C != B adds the uniform rotation m3 (1/C - 1/B) about d3, i.e.
phi' only: (theta, psi, pbar_theta, pbar_psi) are those of the B = C rod.
"""
from __future__ import annotations

import numpy as np

from ..core import systems
from ..core.errors import ParameterError


def magnetic_to_paper(names, x, pars) -> tuple:
    """The `magnetic` model's state x (parameters B, C, lam; `names` its generated names module) as the paper's
    rod at gamma = delta = 0: (RodParams, chart coordinates (theta, psi, phi, pbar_theta, pbar_psi), arclength
    scale c).  ParameterError("x0") where the chart does not reach (m3 <= 0, |e3| != 1, e3.n <= 0)."""
    from ..core.params import RodParams

    names = getattr(names, "names", names)  # a ModelCode or its names module
    B, lam = (pars[names.PARAMS.index(k)] for k in ("B", "lam"))
    i = {k: names.STATE.index(k) for k in names.STATE}
    m3 = x[i["m3"]]
    mv = np.array([x[i["m1"]], x[i["m2"]], m3])
    nv = np.array([x[i["n1"]], x[i["n2"]], x[i["n3"]]])
    ev = np.array([x[i["e31"]], x[i["e32"]], x[i["e33"]]])
    if not m3 > 0:
        raise ParameterError("x0", f"the chart needs m3 > 0 (p_phi = m3 is the unit of the scale), got {m3:g}")
    if abs(ev @ ev - 1.0) > 1e-12:
        raise ParameterError("x0", f"the chart needs |e3| = 1 (the field direction), got {np.sqrt(ev @ ev):.15g}")
    nt = nv * B / m3**2
    C2 = float(ev @ nt)
    if not C2 > 0:
        raise ParameterError("x0", f"the chart needs e3.n > 0 (m = m3/sqrt(B e3.n)), got e3.n = {ev @ nv:g}")
    m = C2 ** -0.5
    lt = lam * B**2 / m3**3
    C1 = 0.5 * float(nt @ nt) + lt * float((mv / m3) @ ev)
    rp = RodParams(m=float(m), mu=float(2 * C1 * m**4 - 1), gamma=0.0, delta=0.0, lam=float(lt * m**4))
    xs = np.concatenate([mv / m3, nt, ev])
    q = systems.body_to_euler(xs, rp.array())
    return rp, np.asarray(q, dtype=float), B / m3


def magnetic_chart_start(system, starts=None):
    """(RodParams, start keywords) of the paper's chart for the `magnetic` model's reference state (or the first
    of `starts`); None for every other model (whose reduced formulation `ModelCode.require_s1` refuses)."""
    code = system.code
    if code.name != "magnetic" or code.origin != "registry":
        return None
    x0 = np.array(code.names.REFERENCE if starts is None else np.atleast_2d(starts)[0], dtype=float)
    rp, q, _ = magnetic_to_paper(code.names, x0, system.array())
    ci = {k: systems.chart_index(k) for k in ("theta", "psi", "ptheta", "ppsi")}
    return rp, {"theta0": float(q[ci["theta"]]), "ptheta0": float(q[ci["ptheta"]]), "psi0": float(q[ci["psi"]]),
                "p_psi0": float(q[ci["ppsi"]])}
