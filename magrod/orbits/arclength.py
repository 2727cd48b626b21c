"""Pseudo-arclength continuation of F(u) = 0, F: R^{n+1} -> R^n, with fold detection (Keller 1977; Kuznetsov,
Elements of Applied Bifurcation Theory, sec. 10.2): the algorithm of magrod.orbits.continuation's docstring, on
any problem, for every model (the paper's shooting problems and magrod.orbits.reversible's both call it).  Its own
module so that the engines below the face import it without importing the face functions."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..core.errors import ParameterError
from ..core.params import RodParams
from ..core.results import Result, jsonable
from ..core.tolerances import CONTINUATION_TOL
from .shooting import newton


@dataclass(repr=False)
class Branch(Result):
    """Continuation output.  u (npts, n+1) points, tangents (npts, n+1) (unit in scaled variables), residuals
    (npts,), Newton iterations (npts,), folds: list of dicts {index (the point before the fold), u (located
    fold), residual}, success/message (stopped early and why), names of the components of u; for branches of
    orbits (`continue_branch`) also the kind of saddle, the continuation parameter, pulses and the start orbit's
    parameters.  `.plot()` draws T against the parameter, folds marked."""

    u: np.ndarray  # the branch points, shape (npts, n+1)
    tangents: np.ndarray  # unit tangents in scaled variables, shape (npts, n+1)
    residuals: np.ndarray  # max|F| at each point, shape (npts,)
    iterations: np.ndarray  # Newton iterations of each point, shape (npts,)
    folds: list = field(default_factory=list)
    success: bool = True
    message: str = ""
    names: tuple = ()  # names of the components of u
    kind: str = ""  # the kind of saddle the orbits are homoclinic to (orbit branches; empty for a bare problem)
    parameter: str = ""
    pulses: int = 0  # pulses of the continued orbit (0 for a bare problem)
    start: RodParams | None = None  # the start orbit's parameters (orbit branches)
    system: object = None  # what was studied (the System at the start)

    _repr_fields = ("names", "points", "fold_values", "max_residual")

    @property
    def points(self) -> int:
        """The number of branch points."""
        return int(len(self.u))

    @property
    def max_residual(self) -> float:
        """The largest residual max|F| over the branch."""
        return float(np.max(self.residuals)) if len(self.residuals) else math.nan

    @property
    def accuracy(self) -> dict:
        """The accuracy achieved: the largest corrector residual max|F| over the branch's points."""
        return {"max_residual": self.max_residual, "points": int(len(self.residuals))}

    @property
    def fold_values(self) -> list:
        """The continuation parameter (last component of u) at each located fold."""
        return [float(f["u"][-1]) for f in self.folds if f.get("u") is not None]

    def to_dict(self) -> dict:
        d = {k: jsonable(getattr(self, k)) for k in ("success", "message", "names", "kind", "parameter", "pulses",
                                                      "u", "tangents", "residuals", "iterations")}
        d.update({"folds": fold_summary(self), "start": self.start.to_dict() if self.start else None,
                  "system": self.system.to_dict() if self.system is not None else None})
        return d


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
    """Newton on (F(u) = 0, t . (u - u_pred)/scale = 0) in scaled variables, from `start` (default u_pred), with
    the one damped Newton (magrod.orbits.shooting.newton; at least one step, convergence on max|F|).
    Returns (u, |F|, iterations, J at the solution) or raises RuntimeError."""
    vp = np.asarray(u_pred, float) / scale
    v0 = vp.copy() if start is None else np.asarray(start, float) / scale

    @dataclass
    class Bordered:  # F and the arclength condition, and the scaled Jacobian d F / d v
        r: np.ndarray
        J: np.ndarray
        F: np.ndarray
        Js: np.ndarray

    def evaluate(v):
        r, J = F(v * scale)
        Js = J * scale  # d F / d v
        return Bordered(np.r_[r, t @ (v - vp)], np.vstack([Js, t]), np.asarray(r), Js)

    def solve(rb, A, v):
        return np.linalg.solve(A, -rb)

    run = newton(evaluate, v0, tol=tol, max_evaluations=max_iter + 1, solve=solve, min_steps=1,
                 measure=lambda ev: np.max(np.abs(ev.F)))
    if run.outcome == "rejected":
        raise run.error
    if run.outcome != "converged":
        raise RuntimeError(f"corrector did not converge (last residual {run.residual:.2e})")
    return run.z * scale, run.residual, run.iterations, run.evaluation.Js


def pseudo_arclength(F, u0, *, scale=None, ds=0.05, steps=50, ds_min=1e-6, ds_max=0.5, tol=CONTINUATION_TOL, par=-1,
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


def point_at(F, u_guess, index: int, value: float, *, scale=None, tol=CONTINUATION_TOL):
    """The branch point with u[index] = value (Newton with that component fixed), from a nearby guess."""
    u = np.asarray(u_guess, float).copy()
    u[index] = value
    scale = np.asarray(scale if scale is not None else np.where(u != 0, np.abs(u), 1.0), float)
    e = np.zeros(u.size)
    e[index] = 1.0
    return correct(F, u, e, scale=scale, tol=tol)[:2]


def fold_summary(branch: Branch) -> list[dict]:
    """The branch's folds as plain data: per fold its index on the branch, the unknowns there by name (when the
    fold was located) and the residual of the located point."""
    return [{"index": f["index"], **({n: float(v) for n, v in zip(branch.names, f["u"])} if f["u"] is not None
                                     else {}), "residual": f.get("residual")} for f in branch.folds]
