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


@dataclass(repr=False)
class RodShape(Result):
    """The 3-D rod of an orbit: arclength s (n,), centreline r (n, 3) (z along the field, r[0] = 0), director
    frames D (n, 3, 3) (columns d1, d2, d3 in space components), body states x (n, N); checks: orthonormality
    max|D^T D - I|, det max|det D - 1|, field_consistency max|D^T z - e3_body|, deviation_from_symmetric_orbit
    (max over the window of |x - the stored symmetric orbit|) and over its first half; pars, T.  `.plot()` draws
    the rod as a tube."""

    success: bool
    message: str
    s: np.ndarray
    r: np.ndarray
    D: np.ndarray
    x: np.ndarray
    orthonormality: float
    det: float
    field_consistency: float
    deviation_from_symmetric_orbit: float
    deviation_first_half: float
    pars: np.ndarray
    T: float

    _repr_fields = ("length", "end_to_end", "orthonormality", "field_consistency", "deviation_first_half")

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


def rod_shape(orbit, n: int = 3001) -> RodShape:
    """The rod's 3-D shape (directors and extensible centreline) of a symmetric homoclinic orbit.

    Parameters
    ----------
    orbit : MultipulseOrbit, dict or path
        A converged orbit (multipulse_orbits), the arrays of an orbit file (magrod.core.io.load_orbit_file), or
        the path of an orbit file written by magrod.
    n : int
        About this many samples along the plotted window (>= 2).

    Returns
    -------
    RodShape
        Arclength, centreline, director frames, body states and the frame checks; `.plot()` (a 3-D tube).

    Raises
    ------
    ParameterError
        "orbit" if not a converged orbit, "from" if the file is not a magrod orbit file, "n" if n < 2.

    Examples
    --------
    >>> import magrod as mr
    >>> from magrod.orbits.multipulse import multipulse_orbits
    >>> from magrod.orbits.rod import rod_shape
    >>> found = multipulse_orbits(mr.RodParams(m=1.7, mu=0.002, gamma=1, delta=1, lam=0.001), max_pulses=2,
    ...                           samples=41)
    >>> rod = rod_shape(found[0], n=501)
    >>> rod.orthonormality < 1e-12 and rod.field_consistency < 1e-12
    True

    Notes
    -----
    Method: the body system, D' = D hat(u) and r' = D v (u = dH/dm, v = dH/dn: the extensible, shearable
    constitutive law) integrated together by heyoka from the launch point over the plotted window |tau| <= 1
    (from_orbit), so the frame is as accurate as the state (orthonormality drift ~1e-14).  The space frame has z
    along the field.  Cost: one integration of 21 equations (~10 ms).  Reference: paper sec. 2, eq:hyperelastic.
    """
    from ..core.errors import require_positive_int

    n = require_positive_int("n", n)
    if n < 2:
        raise ParameterError("n", f"must be >= 2, got {n}")
    if isinstance(orbit, (str, Path)):
        from ..core.io import load_orbit_file

        d = load_orbit_file(orbit)
    elif isinstance(orbit, dict):
        d = orbit
    else:
        if not getattr(orbit, "success", False) or not hasattr(orbit, "sample"):
            raise ParameterError("orbit", "must be a converged MultipulseOrbit, an orbit file's arrays or its path")
        orb = orbit.sample()
        d = {"x0": orbit.x0, "T": orbit.T, "pars": orbit.params.array(), "t": orb["t"], "tau": orb["tau"],
             "x": orb["x"]}
    rod = from_orbit(d, n)
    return RodShape(True, "rod reconstructed from the orbit (state + frame + centreline integrated together)",
                    rod["s"], rod["r"], rod["D"], rod["x"], rod["orthonormality"], rod["det"],
                    rod["field_consistency"], rod["deviation_from_symmetric_orbit"], rod["deviation_first_half"],
                    np.asarray(rod["pars"], float), float(rod["T"]))
