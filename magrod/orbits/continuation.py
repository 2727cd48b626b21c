"""Pseudo-arclength continuation (Keller 1977; e.g. Kuznetsov, Elements of Applied Bifurcation Theory, sec. 10.2)
of solution branches of F(u) = 0, F: R^{n+1} -> R^n, with fold detection -- a small layer on the Newton +
variational-Jacobian shooting maps magrod already has (no maintained Python continuation library exists).

Algorithm.  At a point u_k with unit tangent t_k (the null vector of the n x (n+1) Jacobian F_u, oriented so
that t_k . t_{k-1} > 0): predictor u* = u_k + ds t_k; corrector Newton on
    F(u) = 0,  t_k . (u - u*) = 0          (the bordered (n+1) x (n+1) system [F_u; t_k^T]),
converged when max|F| <= tol.  Step control: ds halves on failure (down to ds_min), grows by 1.5 after a quick
(<= 3 Newton steps) convergence (up to ds_max).  All arclength geometry is in scaled variables u / scale, so that
unknowns of different size (T ~ 100, lambdabar ~ 1e-3) count alike.  A fold of the parameter u[par] is a sign
change of t[par] between consecutive points; it is located by regula falsi (Illinois variant) on t[par] = 0 along
the chord between the two points, each iterate corrected onto the branch (so the fold comes out the same from
either side: tests/test_continuation.py crosses a real fold of 2-pulse orbits forward and back).

Problems (each a function returning F(u), F_u(u)):
  mu2lam_problem    symmetric N-pulse orbits of the straight rod on mu = 2 lambdabar (codimension one), u = (T,
                    lambdabar, q) with q = m, gamma or delta: a curve in the (lambdabar, q) plane
  periodic_problem  symmetric homoclinic orbits to the periodic saddle (mu > 2 lambdabar), u = (T, angle, q),
                    q = lam, mu or m
Costs: one variational integration (+ 2 per free parameter for the launch-point difference) per Newton step.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..core.errors import ParameterError
from ..generated import scalars
from ..generated.names import PARAMS
from ..core.params import RodParams


@dataclass
class Branch:
    """Continuation output.  u (npts, n+1) points, tangents (npts, n+1) (unscaled), residuals (npts,), newton
    iterations (npts,), folds: list of dicts {index (the point before the fold), u (located fold), residual},
    success/message (stopped early and why)."""

    u: np.ndarray
    tangents: np.ndarray
    residuals: np.ndarray
    iterations: np.ndarray
    folds: list = field(default_factory=list)
    success: bool = True
    message: str = ""
    names: tuple = ()


def _tangent(J, prev=None):
    # null vector of the n x (n+1) Jacobian (smallest right singular vector), oriented along prev
    _, _, Vt = np.linalg.svd(J)
    t = Vt[-1]
    if prev is not None and t @ prev < 0:
        t = -t
    elif prev is None and t[-1] < 0:
        t = -t
    return t / np.linalg.norm(t)


def correct(F, u_pred, t, *, scale, tol, max_iter=12, start=None):
    """Newton on (F(u) = 0, t . (u - u_pred)/scale = 0) in scaled variables, from `start` (default u_pred).
    Returns (u, |F|, iterations, J at the solution) or raises RuntimeError."""
    vp = np.asarray(u_pred, float) / scale
    v = vp.copy() if start is None else np.asarray(start, float) / scale
    for it in range(max_iter + 1):
        r, J = F(v * scale)
        res = float(np.max(np.abs(r)))
        if not np.isfinite(res):
            break
        Js = J * scale  # d F / d v
        if res <= tol and it > 0:
            return v * scale, res, it, Js
        A = np.vstack([Js, t])
        b = -np.r_[r, t @ (v - vp)]
        try:
            dv = np.linalg.solve(A, b)
        except np.linalg.LinAlgError:
            break
        v = v + dv
    raise RuntimeError(f"corrector did not converge (last residual {res:.2e})")


def pseudo_arclength(F, u0, *, scale=None, ds=0.05, steps=50, ds_min=1e-6, ds_max=0.5, tol=1e-10, par=-1,
                     direction=1, bounds=None, names=(), locate_folds=True, progress=None) -> Branch:
    """Continue F(u) = 0 from u0 (an approximate solution; corrected first, with t along +-u[par]).

    scale: per-component scale of u (default |u0| or 1); ds, ds_min, ds_max: scaled arclength steps; steps:
    number of points after the first; par: index of the continuation parameter (fold detection, direction
    sign); bounds: {index: (lo, hi)} stop when left; progress: optional callable(n_new_points); returns a Branch (success False if the step size fell
    below ds_min)."""
    u0 = np.asarray(u0, float)
    scale = np.asarray(scale if scale is not None else np.where(u0 != 0, np.abs(u0), 1.0), float)
    e = np.zeros(u0.size)
    e[par] = 1.0
    # first point: Newton with u[par] fixed
    u, res, it, Js = correct(F, u0, e * direction, scale=scale, tol=tol)
    t = _tangent(Js)
    if t[par] * direction < 0:
        t = -t
    U, Tg, R, I = [u], [t * scale / np.linalg.norm(t * scale)], [res], [it]
    folds = []
    msg, ok = f"{steps} steps done", True
    h = ds
    for k in range(steps):
        while True:
            try:
                u_new, res, it, Js = correct(F, (u / scale + h * t) * scale, t, scale=scale, tol=tol)
                break
            except (RuntimeError, ParameterError, np.linalg.LinAlgError) as exc:
                h *= 0.5
                if h < ds_min:
                    return Branch(np.array(U), np.array(Tg), np.array(R), np.array(I), folds, False,
                                  f"step size below ds_min at point {len(U)}: {exc}", tuple(names))
        t_new = _tangent(Js, t)
        if t_new[par] * t[par] < 0:
            fold = {"index": len(U) - 1, "u": None, "residual": None}
            if locate_folds:
                try:
                    fold.update(_locate_fold(F, u, u_new, t, t_new, scale, par, tol))
                except (RuntimeError, ParameterError, np.linalg.LinAlgError) as exc:
                    fold["message"] = str(exc)
            if fold["u"] is None:  # secant estimate
                w = t[par] / (t[par] - t_new[par])
                fold["u"] = (1 - w) * u + w * u_new
            folds.append(fold)
        u, t = u_new, t_new
        U.append(u)
        Tg.append(t * scale / np.linalg.norm(t * scale))
        R.append(res)
        I.append(it)
        if progress is not None:
            progress(1)
        if it <= 3:
            h = min(ds_max, 1.5 * h)
        if bounds and any(not (lo <= u[i] <= hi) for i, (lo, hi) in bounds.items()):
            msg = f"left the bounds after {k + 1} steps"
            break
    return Branch(np.array(U), np.array(Tg), np.array(R), np.array(I), folds, ok, msg, tuple(names))


def _locate_fold(F, ua, ub, ta, tb, scale, par, tol, max_iter=20):
    """Fold point: F(u) = 0 and t(u)[par] = 0, by regula falsi (Illinois variant) on the arclength s along the
    chord between ua and ub, each iterate corrected onto the branch in the hyperplane perpendicular to the chord.
    Stops when |t[par]| <= 1e-12 or the bracket in s is below 1e-12.  The corrector accepts 4 tol there: the
    residual's noise floor is reached at the fold, where the (T, angle) block of the Jacobian is singular."""
    va, vb = ua / scale, ub / scale
    ga, gb = ta[par], tb[par]
    chord = (vb - va) / np.linalg.norm(vb - va)
    sa, sb = 0.0, float(np.linalg.norm(vb - va))
    side = 0
    u = res = None
    for _ in range(max_iter):
        s_ = (sa * gb - sb * ga) / (gb - ga)
        u, res, _, Js = correct(F, (va + s_ * chord) * scale, chord, scale=scale, tol=4 * tol)
        g = _tangent(Js, ta)[par]
        if abs(g) <= 1e-12:
            break
        if np.sign(g) == np.sign(ga):
            sa, ga = s_, g
            if side == -1:
                gb *= 0.5
            side = -1
        else:
            sb, gb = s_, g
            if side == 1:
                ga *= 0.5
            side = 1
        if abs(sb - sa) <= 1e-12:
            break
    return {"u": u, "residual": res}


def point_at(F, u_guess, index: int, value: float, *, scale=None, tol=1e-10):
    """The branch point with u[index] = value (Newton with that component fixed), from a nearby guess."""
    u = np.asarray(u_guess, float).copy()
    u[index] = value
    scale = np.asarray(scale if scale is not None else np.where(u != 0, np.abs(u), 1.0), float)
    e = np.zeros(u.size)
    e[index] = 1.0
    return correct(F, u, e, scale=scale, tol=tol)[:2]


# --- problems --------------------------------------------------------------------------------------------------
MU2LAM_FREE = ("m", "gamma", "delta")


def mu2lam_problem(base: RodParams, second: str = "m", *, eps: float = 1e-9, precision: str = "long double"):
    """F(T, lam, q) = (pbar_theta, sin psi)(x(T)) for the straight rod's unstable manifold on mu = 2 lam, q =
    `second` (m, gamma or delta); Jacobian from the variational equations (as magrod.orbits.shooting.shoot).  Returns
    (F, params_of(u))."""
    from ..core import systems
    from .periodic_homoclinic import _fix, _propagate
    from .equilibrium import straight_rod

    if second not in MU2LAM_FREE:
        raise ParameterError("second", f"must be one of {MU2LAM_FREE}, got {second!r}")
    ip = {n: systems.par_index(n) for n in ("mu", "lam", second)}

    def params_of(u):
        kw = base.as_dict()
        kw["lam"], kw[second] = float(u[1]), float(u[2])
        kw["mu"] = scalars.straight_rod_mu(**kw)  # stay on mu = 2 lam, where the straight rod is the saddle
        return RodParams(**kw)

    def launch(p):
        return straight_rod(p).launch_point(eps)

    def F(u):
        p = params_of(u)
        pars = p.array()
        ft = systems.PRECISIONS[precision]
        x0 = straight_rod(p).launch_point(eps, fp_type=ft)
        x, Phi, Psi = _propagate(x0, pars, u[0], precision)
        fc, fg = _fix()
        r = fc(x, [])
        G = fg(x, []).reshape(2, 9)
        f = systems.body_functions()["rhs"](x, pars)
        cols = [G @ f]
        for name in ("lam", second):
            v = getattr(p, name)
            hh = 1e-6 * max(1.0, abs(v))
            up, um = np.array(u, float), np.array(u, float)
            j = 1 if name == "lam" else 2
            up[j] += hh
            um[j] -= hh
            dx0 = (launch(params_of(up)) - launch(params_of(um))) / (2 * hh)
            # d pars/d name with mu kept on the straight rod's level (generated straight_rod_mu_gradient)
            dpar = np.zeros(len(PARAMS))
            dpar[ip[name]] = 1.0
            dpar[ip["mu"]] = scalars.straight_rod_mu_gradient(**params_of(u).as_dict())[ip[name]]
            cols.append(G @ (Phi @ dx0 + Psi @ dpar))
        return r, np.column_stack(cols)

    return F, params_of


PERIODIC_FREE = ("lam", "mu", "m", "gamma", "delta")


def periodic_problem(base: RodParams, free: str, pulses: int, *, eps: float | None = None, precision: str = "auto"):
    """F(T, angle, q) for symmetric homoclinic orbits to the periodic saddle (magrod.orbits.periodic_homoclinic), q =
    `free`.  Returns (F, params_of(u))."""
    from . import periodic_homoclinic as hp

    if free not in PERIODIC_FREE:
        raise ParameterError("free", f"must be one of {PERIODIC_FREE}, got {free!r}")
    prec = hp._precision(pulses, precision)
    eps = eps if eps is not None else (hp.DEFAULT_EPS if prec == "double" else hp.EXTENDED_EPS)

    def params_of(u):
        kw = base.as_dict()
        kw[free] = float(u[2])
        return RodParams(**kw)

    def F(u):
        r, J, *_ = hp.residual_and_jacobian(params_of(u), u[0], u[1], eps=eps, precision=prec, free=(free,))
        return r, J

    return F, params_of


def fold_summary(branch: Branch) -> list[dict]:
    return [{"index": f["index"], **({n: float(v) for n, v in zip(branch.names, f["u"])} if f["u"] is not None
                                     else {}), "residual": f.get("residual")} for f in branch.folds]


def wrap_angle(a: float) -> float:
    return math.remainder(a, 2 * math.pi) % (2 * math.pi)
