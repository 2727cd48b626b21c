"""The rod's 3-D shape from a body-frame solution: directors and centreline (paper sec. 2, eq:hyperelastic).

Scale (derive/numeric_scale.py): B = C = m3 = 1, so t = s is arclength in units of B/m3 and the compliances
are 1/H = 1/J = delta m^2, 1/K = (gamma + delta) m^2.  Strains from the constitutive law: u = dH/dm = m and
v = dH/dn = (delta m^2 n1, delta m^2 n2, 1 + (gamma + delta) m^2 n3) -- the extensible, shearable v, not d3.

The frame D = [d1 d2 d3] (columns = space components of the directors) obeys D' = D hat(u) and the
centreline r' = D v; both are integrated by heyoka together with the 9-D state (21 equations), so the frame is
as accurate as the state (orthonormality drift ~1e-14 over the orbits of Figs 6-7).  The space frame is fixed by
e3 (the field) = z: the third row of D is e3's body components, D(0)^T z = e3_body(0)."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..core import systems
from ..core.errors import ParameterError
from ..core.deprecation import renamed_keywords
from ..core.results import Result

N = systems.dim("body")
E3 = slice(systems.state_index("body", "e31"), systems.state_index("body", "e33") + 1)  # body components of e3


def initial_frame(e_body) -> np.ndarray:
    """A rotation D0 with third row e_body (so D0^T z = e_body): the space z-axis is the field direction."""
    e = np.asarray(e_body, float) / np.linalg.norm(e_body)
    a = np.array([1.0, 0.0, 0.0]) if abs(e[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    r1 = a - (a @ e) * e
    r1 /= np.linalg.norm(r1)
    r2 = np.cross(e, r1)
    return np.vstack([r1, r2, e])


def reconstruct(x0, pars, s_grid, D0=None, r0=(0.0, 0.0, 0.0)) -> dict:
    """Integrate state, frame and centreline from s_grid[0] (state x0 there) over s_grid
    (systems.rod_frame_integrator: the body system + D' = D hat(u) + r' = D v).

    Returns s (N,), x (N, 9), D (N, 3, 3), r (N, 3), and the checks: orthonormality max|D^T D - I|, max|det D - 1|,
    field consistency max|D^T z - e3_body| (the body e3 integrated by the state equations)."""
    s_grid = np.asarray(s_grid, float)
    if s_grid.ndim != 1 or s_grid.size < 2 or np.any(np.diff(s_grid) <= 0):
        raise ParameterError("s_grid", "must be an increasing 1-D array with at least 2 points")
    x0 = np.asarray(x0, float)
    D0 = initial_frame(x0[E3]) if D0 is None else np.asarray(D0, float)
    ta = systems.rod_frame_integrator()
    systems.reset(ta, np.concatenate([x0, D0.ravel(), np.asarray(r0, float)]), float(s_grid[0]),
                  np.asarray(pars, float))
    out = ta.propagate_grid(s_grid)[-1]
    x, D, r = out[:, :N], out[:, N:N + 9].reshape(-1, 3, 3), out[:, N + 9:N + 12]
    eye = np.eye(3)
    ortho = float(np.max(np.abs(np.einsum("nki,nkj->nij", D, D) - eye)))
    det = float(np.max(np.abs(np.linalg.det(D) - 1)))
    field = float(np.max(np.abs(D[:, 2, :] - x[:, E3])))
    return {"s": s_grid, "x": x, "D": D, "r": r, "orthonormality": ortho, "det": det, "field_consistency": field}


def from_orbit(d: dict, n: int = 3001) -> dict:
    """Rod of a symmetric orbit (arrays x0, T, pars, t, tau, x as written by `magrod multipulse`): integrated from
    the launch point over the plotted window |tau| <= 1 (theta >= shooting.THETA_CUT at its ends; outside, the
    rod is straight to that order).  Also reports the max deviation of the integrated states from the stored
    symmetric orbit in the window (the forward integration past the symmetric point drifts off it like
    residual * exp(a s) only as it nears the saddle)."""
    x0, T, pars, t, tau, X = d["x0"], float(d["T"]), d["pars"], d["t"], d["tau"], d["x"]
    win = np.abs(tau) <= 1.0
    s_a = float(t[win][0])
    # integrate from the launch point; grid starts at 0 so that the state there is x0
    # the stored orbit's own samples in the window (no interpolation in the comparison), thinned to ~n points
    idx = np.flatnonzero(win)[:: max(1, int(np.count_nonzero(win) // n))]
    grid = np.concatenate([[0.0], t[idx]]) if t[idx][0] > 0 else t[idx]
    rod = reconstruct(x0, pars, grid)
    keep = rod["s"] >= s_a
    for k in ("s", "x", "D", "r"):
        rod[k] = rod[k][keep]
    rod["r"] = rod["r"] - rod["r"][0]
    dev = np.max(np.abs(rod["x"] - X[idx]), axis=1)
    rod["deviation_from_symmetric_orbit"] = float(np.max(dev))
    rod["deviation_first_half"] = float(np.max(dev[rod["s"] <= T]))
    rod["pars"] = pars
    rod["T"] = T
    return rod


def reconstruct_model(system, x0, s_grid, D0=None, r0=(0.0, 0.0, 0.0)) -> dict:
    """`reconstruct` for any model: state, director frame D' = D hat(u) and centreline r' = D v integrated together,
    u = dH/dm, v = dH/dn by hy.diff of the model's H (model_field.frame_integrator).  The space z-axis is the
    field e3 where the model has one (D0^T z = e3_body), else the force n (constant in space: the balance n' = 0
    of a rod without distributed load), else d3.

    Returns the keys of `reconstruct`; field_consistency is max|D^T z - e3_body| with a field, else the drift of
    the force in space max|D n_body - D0 n_body(0)| (both zero exactly: numerical evidence of the frame's accuracy)."""
    from . import model_field

    s_grid = np.asarray(s_grid, float)
    if s_grid.ndim != 1 or s_grid.size < 2 or np.any(np.diff(s_grid) <= 0):
        raise ParameterError("s_grid", "must be an increasing 1-D array with at least 2 points")
    mf = model_field.field(system)
    x0 = np.asarray(x0, float)
    idx = model_field.strain_indices(system)
    nb = list(idx[3:])
    e3 = [mf.index(k) for k in ("e31", "e32", "e33")] if mf.has("e31", "e32", "e33") else None
    if D0 is None:
        axis = x0[e3] if e3 else (x0[nb] if np.linalg.norm(x0[nb]) > 0 else np.array([0.0, 0.0, 1.0]))
        D0 = initial_frame(axis)
    D0 = np.asarray(D0, float)
    ta = model_field.frame_integrator(system)
    ta.time = float(s_grid[0])
    ta.state[:] = np.concatenate([x0, D0.ravel(), np.asarray(r0, float)])
    ta.pars[:] = system.array()
    out = np.array(ta.propagate_grid(s_grid)[-1])
    n = mf.dim
    x, D, r = out[:, :n], out[:, n:n + 9].reshape(-1, 3, 3), out[:, n + 9:n + 12]
    eye = np.eye(3)
    ortho = float(np.max(np.abs(np.einsum("nki,nkj->nij", D, D) - eye)))
    det = float(np.max(np.abs(np.linalg.det(D) - 1)))
    if e3:
        consistency = float(np.max(np.abs(D[:, 2, :] - x[:, e3])))
    else:
        f_space = np.einsum("nij,nj->ni", D, x[:, nb])
        consistency = float(np.max(np.abs(f_space - f_space[0])))
    return {"s": s_grid, "x": x, "D": D, "r": r, "orthonormality": ortho, "det": det,
            "field_consistency": consistency}


def _model_shape(system, orbit, n: int):
    """(dict of `reconstruct_model`, deviation, deviation of the first half, T) of a symmetric orbit or an equilibrium
    (a uniform helix over 4 pitches of its curvature, or length 20 for a straight rod)."""
    from .equilibria import Equilibrium
    from .reversible import SymmetricOrbit

    if isinstance(orbit, SymmetricOrbit):
        smp = orbit.sample(2 * n + 1)
        t, X = smp["t"], smp["x"]
        # the window where the rod is not straight to the launch distance: |x - x*| >= 1e3 delta
        far = np.max(np.abs(X - orbit.equilibrium.x), axis=1) >= 1e3 * orbit.launch_distance
        win = np.flatnonzero(far)
        lo, hi = (int(win[0]), int(win[-1])) if win.size >= 2 else (0, t.size - 1)
        idx = np.arange(lo, hi + 1)[:: max(1, (hi - lo + 1) // n)]
        grid = np.concatenate([[0.0], t[idx]]) if t[idx][0] > 0 else t[idx]
        rod = reconstruct_model(system, orbit.x0, grid)
        keep = rod["s"] >= t[lo]
        for k in ("s", "x", "D", "r"):
            rod[k] = rod[k][keep]
        rod["r"] = rod["r"] - rod["r"][0]
        dev = np.max(np.abs(rod["x"] - X[idx]), axis=1)
        return rod, float(np.max(dev)), float(np.max(dev[rod["s"] <= orbit.T])), float(orbit.T)
    if isinstance(orbit, Equilibrium):
        from . import model_field

        pars = system.array()
        g = np.asarray(model_field.field(system).grad_H(orbit.x, pars), float)
        idx = model_field.strain_indices(system)
        k = float(np.linalg.norm(g[list(idx[:3])]))
        length = 8 * np.pi / k if k > 1e-12 else 20.0
        rod = reconstruct_model(system, orbit.x, np.linspace(0.0, length, n))
        dev = float(np.max(np.abs(rod["x"] - orbit.x)))
        return rod, dev, dev, length / 2
    raise ParameterError("orbit", "must be a converged orbit (a symmetric homoclinic orbit or MultipulseOrbit), an "
                                  "equilibrium, an orbit file's arrays or its path")


@dataclass(repr=False)
class RodShape(Result):
    """The 3-D rod of an orbit: arclength s (n,), centreline r (n, 3) (z along the field, r[0] = 0), director
    frames D (n, 3, 3) (columns d1, d2, d3 in space components), body states x (n, N); checks: orthonormality
    max|D^T D - I|, det max|det D - 1|, field_consistency max|D^T z - e3_body|, deviation_from_symmetric_orbit
    (max over the window of |x - the stored symmetric orbit|) and over its first half; pars, T.  `.plot()` draws
    the rod as a tube."""

    success: bool
    message: str
    s: np.ndarray  # arclength, shape (n,)
    r: np.ndarray  # centreline, shape (n, 3), z along the field, r[0] = 0
    D: np.ndarray  # director frames, shape (n, 3, 3): columns d1, d2, d3 in space components
    x: np.ndarray  # body states along the rod, shape (n, N)
    orthonormality: float  # max|D^T D - I| over the rod
    det: float  # max|det D - 1| over the rod
    field_consistency: float  # max|D^T z - e3_body|: the frame against the body state
    deviation_from_symmetric_orbit: float  # max over the window of |x - the stored symmetric orbit|
    deviation_first_half: float  # the same over the first half of the window
    pars: np.ndarray  # the parameter values of the model
    T: float  # the orbit's half-time
    system: object = None

    _repr_fields = ("length", "end_to_end", "orthonormality", "field_consistency", "deviation_first_half")
    # to_xarray(): one sample dimension, named axes, and CF attributes (the scale of derive/numeric_scale.py)
    _xarray_dims = {"s": ("sample",), "r": ("sample", "space"), "D": ("sample", "space", "director"),
                    "x": ("sample", "body_state")}
    _cf = {"s": ("B/m3", "arclength s of the rod"), "r": ("B/m3", "centreline r(s) in space components"),
           "D": ("1", "frame: columns d1, d2, d3 in space components"),
           "x": ("1 (B = C = m3 = 1)", "body state (m, n, e3) along the rod, generated/names.py BODY_STATE")}

    @property
    def accuracy(self) -> dict:
        """The accuracy achieved by the frame integration: orthonormality and determinant of the director frame,
        consistency of the integrated frame with the body-frame field, and the symmetric orbit's reversal
        deviations (rod.py module docstring)."""
        return {"orthonormality": self.orthonormality, "det": self.det, "field_consistency": self.field_consistency,
                "deviation_from_symmetric_orbit": self.deviation_from_symmetric_orbit,
                "deviation_first_half": self.deviation_first_half}

    @property
    def length(self) -> float:
        """Arclength of the window (units B/m3)."""
        return float(self.s[-1] - self.s[0])

    @property
    def end_to_end(self) -> float:
        """|r(end) - r(start)| (longer than `length` for a stretched rod: the centreline's |r'| = |v| > 1)."""
        return float(np.linalg.norm(self.r[-1] - self.r[0]))


@renamed_keywords(params="system")
def rod_shape(system=None, orbit=None, n: int = 3001) -> RodShape:
    """The rod's 3-D shape (directors and centreline) of an orbit of any model.

    Parameters
    ----------
    system : System, or what converts to one (magrod.core.system.as_system)
        The model and its parameters.  A result passed here (the old spelling ``rod_shape(orbit)``) stands for
        itself and its system.
    orbit : SymmetricOrbit, MultipulseOrbit, Equilibrium, dict or path
        A converged symmetric homoclinic orbit (any model), an equilibrium (its uniform helix), a paper's-rod
        orbit (multipulse_orbits), the arrays of an orbit file (magrod.core.io.load_orbit_file), or its path.
    n : int
        About this many samples along the plotted window (>= 2).

    Returns
    -------
    RodShape
        Arclength, centreline, director frames, body states and the frame checks; `.system`; `.plot()` (a 3-D
        tube).

    Raises
    ------
    ParameterError
        "orbit" if not a converged orbit, "from" if the file is not a magrod orbit file, "n" if n < 2, "model" if
        the model has no body moments and forces (m, n) to integrate the frame from.

    Examples
    --------
    >>> import magrod as mr
    >>> from magrod.orbits.multipulse import multipulse_orbits
    >>> from magrod.orbits.rod import rod_shape
    >>> p = mr.RodParams(m=1.7, mu=0.002, gamma=1, delta=1, lam=0.001)
    >>> found = multipulse_orbits(p, max_pulses=2, samples=41)
    >>> rod = rod_shape(p, found[0], n=501)
    >>> rod.orthonormality < 1e-12 and rod.field_consistency < 1e-12
    True

    Notes
    -----
    Method: the body system, D' = D hat(u) and r' = D v (u = dH/dm, v = dH/dn of the model's H by hy.diff: the
    paper's rod's extensible, shearable constitutive law, or any model's) integrated together by heyoka from the
    launch point over the plotted window (paper's rod: ``|tau| <= 1``, from_orbit; other models: where the orbit is
    1e3 launch distances away from the saddle), so the frame is as accurate as the state (orthonormality drift
    ~1e-14).  The space frame has z along the field (or the force).  Cost: one integration of n + 12 equations
    (~10 ms).  Reference: paper sec. 2, eq:hyperelastic.
    """
    from ..core.errors import require_positive_int
    from ..core.system import System, as_system

    if orbit is None or isinstance(orbit, int) and not isinstance(orbit, bool):
        # the old call rod_shape(orbit[, n]): the orbit first, its system from it
        if isinstance(orbit, int):
            n = orbit
        orbit, system = system, getattr(system, "system", None)
    if system is None and hasattr(orbit, "system"):
        system = orbit.system
    n = require_positive_int("n", n)
    if n < 2:
        raise ParameterError("n", f"must be >= 2, got {n}")
    if system is not None and not isinstance(system, System):
        system = as_system(system)[0]
    if system is not None and not system.is_paper:
        if not getattr(orbit, "success", False):
            raise ParameterError("orbit", "must be a converged orbit of the model (a symmetric homoclinic orbit or "
                                          "an equilibrium)")
        if getattr(orbit, "system", system) != system:
            raise ParameterError("system", f"the orbit was computed for {orbit.system!r}, not {system!r}")
        rod, dev, dev1, T = _model_shape(system, orbit, n)
        return RodShape(True, f"rod of the model {system.model!r} reconstructed from the orbit (state + frame + "
                              "centreline integrated together)", rod["s"], rod["r"], rod["D"], rod["x"],
                        rod["orthonormality"], rod["det"], rod["field_consistency"], dev, dev1, system.array(), T,
                        system=system)
    if isinstance(orbit, (str, Path)):
        from ..core.io import load_orbit_file

        d = load_orbit_file(orbit)
    elif isinstance(orbit, dict):
        d = orbit
    else:
        from .equilibria import Equilibrium
        from .reversible import SymmetricOrbit

        if isinstance(orbit, (SymmetricOrbit, Equilibrium)) and getattr(orbit, "success", False):
            rod, dev, dev1, T = _model_shape(orbit.system, orbit, n)
            return RodShape(True, "rod reconstructed from the orbit (state + frame + centreline integrated "
                                  "together)", rod["s"], rod["r"], rod["D"], rod["x"], rod["orthonormality"],
                            rod["det"], rod["field_consistency"], dev, dev1, orbit.system.array(), T,
                            system=orbit.system)
        if not getattr(orbit, "success", False) or not hasattr(orbit, "sample"):
            raise ParameterError("orbit", "must be a converged MultipulseOrbit, an orbit file's arrays or its path")
        orb = orbit.sample()
        d = {"x0": orbit.x0, "T": orbit.T, "pars": orbit.params.array(), "t": orb["t"], "tau": orb["tau"],
             "x": orb["x"]}
    rod = from_orbit(d, n)
    if system is None:
        from ..core.system import System as _S

        system = _S._make(models_default(), _paper_names(), tuple(float(v) for v in rod["pars"]), _double())
    return RodShape(True, "rod reconstructed from the orbit (state + frame + centreline integrated together)",
                    rod["s"], rod["r"], rod["D"], rod["x"], rod["orthonormality"], rod["det"],
                    rod["field_consistency"], rod["deviation_from_symmetric_orbit"], rod["deviation_first_half"],
                    np.asarray(rod["pars"], float), float(rod["T"]), system=system)


def models_default() -> str:
    from ..core.system import PAPER_MODEL

    return PAPER_MODEL


def _paper_names() -> tuple:
    from ..core.system import _paper_names as names

    return names()


def _double():
    from ..core.precision import Precision

    return Precision.DOUBLE
