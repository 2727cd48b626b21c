"""The rod's 3-D shape from a body-frame solution: directors and centreline (paper sec. 2, eq:hyperelastic).

Scale (derive/numeric_scale.py): B = C = m3 = 1, so t = s is arclength in units of B/m3 and the compliances
are 1/H = 1/J = delta m^2, 1/K = (gamma + delta) m^2.  Strains from the constitutive law: u = dH/dm = m and
v = dH/dn = (delta m^2 n1, delta m^2 n2, 1 + (gamma + delta) m^2 n3) -- the extensible, shearable v, not d3.

The frame D = [d1 d2 d3] (columns = space components of the directors) obeys D' = D hat(u) and the
centreline r' = D v; both are integrated by heyoka together with the 9-D state (21 equations), so the frame is
as accurate as the state (orthonormality drift ~1e-14 over the orbits of Figs 6-7).  The space frame is fixed by
e3 (the field) = z: the third row of D is e3's body components, D(0)^T z = e3_body(0)."""
from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import heyoka as hy
import numpy as np

from .errors import ParameterError
from .generated import body
from .systems import body_vars


@lru_cache(maxsize=None)
def _rod_integrator():
    x = body_vars()
    p = body.pars()
    H = body.hamiltonian(*x, *p)
    u = [hy.diff(H, x[i]) for i in range(3)]
    v = [hy.diff(H, x[3 + i]) for i in range(3)]
    D = hy.make_vars(*[f"D{i}{j}" for i in range(3) for j in range(3)])
    r = hy.make_vars("r1", "r2", "r3")
    hat = [[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]]
    sys_ = list(zip(x, body.rhs(*x, *p)))
    for i in range(3):
        for j in range(3):
            sys_.append((D[3 * i + j], hy.sum([D[3 * i + k] * hat[k][j] for k in range(3) if not
                                                (isinstance(hat[k][j], int))])))
    for i in range(3):
        sys_.append((r[i], hy.sum([D[3 * i + k] * v[k] for k in range(3)])))
    return hy.taylor_adaptive(sys_, [0.0] * 21, pars=[1.0] * 5, tol=0.0)


def initial_frame(e_body) -> np.ndarray:
    """A rotation D0 with third row e_body (so D0^T z = e_body): the space z-axis is the field direction."""
    e = np.asarray(e_body, float) / np.linalg.norm(e_body)
    a = np.array([1.0, 0.0, 0.0]) if abs(e[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    r1 = a - (a @ e) * e
    r1 /= np.linalg.norm(r1)
    r2 = np.cross(e, r1)
    return np.vstack([r1, r2, e])


def reconstruct(x0, pars, s_grid, D0=None, r0=(0.0, 0.0, 0.0)) -> dict:
    """Integrate state, frame and centreline from s_grid[0] (state x0 there) over s_grid.

    Returns s (N,), x (N, 9), D (N, 3, 3), r (N, 3), and the checks: orthonormality max|D^T D - I|, max|det D - 1|,
    field consistency max|D^T z - e3_body| (the body e3 integrated by the state equations)."""
    s_grid = np.asarray(s_grid, float)
    if s_grid.ndim != 1 or s_grid.size < 2 or np.any(np.diff(s_grid) <= 0):
        raise ParameterError("s_grid", "must be an increasing 1-D array with at least 2 points")
    x0 = np.asarray(x0, float)
    D0 = initial_frame(x0[6:9]) if D0 is None else np.asarray(D0, float)
    ta = _rod_integrator()
    ta.time = float(s_grid[0])
    ta.state[:] = np.concatenate([x0, D0.ravel(), np.asarray(r0, float)])
    ta.pars[:] = np.asarray(pars, float)
    out = ta.propagate_grid(s_grid)[5]
    x, D, r = out[:, :9], out[:, 9:18].reshape(-1, 3, 3), out[:, 18:21]
    eye = np.eye(3)
    ortho = float(np.max(np.abs(np.einsum("nki,nkj->nij", D, D) - eye)))
    det = float(np.max(np.abs(np.linalg.det(D) - 1)))
    field = float(np.max(np.abs(D[:, 2, :] - x[:, 6:9])))
    return {"s": s_grid, "x": x, "D": D, "r": r, "orthonormality": ortho, "det": det, "field_consistency": field}


def from_orbit_file(path, n: int = 3001) -> dict:
    """Rod of an orbit written by magrod.shooting (npz with x0, T, pars, t, tau): integrated from the launch
    point over the plotted window |tau| <= 1 (theta >= shooting.THETA_CUT at its ends; outside, the rod is
    straight to that order).  Also reports the max deviation of the integrated states from the stored symmetric
    orbit in the window (the forward integration past the symmetric point drifts off it like
    residual * exp(a s) only as it nears the saddle)."""
    path = Path(path)
    if not path.is_file():
        raise ParameterError("from", f"no such file: {str(path)!r}")
    try:
        d = np.load(path)
        x0, T, pars, t, tau, X = d["x0"], float(d["T"]), d["pars"], d["t"], d["tau"], d["x"]
    except (KeyError, ValueError, OSError) as exc:
        raise ParameterError("from", f"{str(path)!r} is not an orbit file of magrod multipulse ({exc})") from None
    win = np.abs(tau) <= 1.0
    s_a, s_b = float(t[win][0]), float(t[win][-1])
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


def plot_rod(rod: dict, out_dir, stem: str, title: str = "") -> list[str]:
    """3-D view and three projections with equal axis scales (PNG), centreline CSV (s, x, y, z)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .io import atomic_savefig, atomic_write_text, ensure_writable_dir

    out_dir = ensure_writable_dir(out_dir)
    r = rod["r"]
    c = 0.5 * (r.max(0) + r.min(0))
    half = 0.5 * float(np.max(r.max(0) - r.min(0))) * 1.05
    fig = plt.figure(figsize=(11, 8))
    ax = fig.add_subplot(2, 2, 1, projection="3d")
    ax.plot(r[:, 0], r[:, 1], r[:, 2], "k-", lw=1)
    ax.set_xlim(c[0] - half, c[0] + half)
    ax.set_ylim(c[1] - half, c[1] + half)
    ax.set_zlim(c[2] - half, c[2] + half)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z (field)")
    for k, (i, j, lab) in enumerate([(0, 2, "x-z"), (1, 2, "y-z"), (0, 1, "x-y, looking along the field (zoomed)")]):
        a2 = fig.add_subplot(2, 2, k + 2)
        a2.plot(r[:, i], r[:, j], "k-", lw=1)
        if k < 2:
            a2.set_xlim(c[i] - half, c[i] + half)
            a2.set_ylim(c[j] - half, c[j] + half)
        else:  # the transverse excursions are small compared with the length: zoom, still equal scales
            hz = 0.5 * float(np.max(r[:, :2].max(0) - r[:, :2].min(0))) * 1.1 + 1e-12
            a2.set_xlim(c[0] - hz, c[0] + hz)
            a2.set_ylim(c[1] - hz, c[1] + hz)
        a2.set_aspect("equal")
        a2.set_title(lab, fontsize=9)
        a2.set_xlabel("xyz"[i])
        a2.set_ylabel("xyz"[j])
    fig.suptitle(title + "\nlengths in units of B/m3 (B = C = m3 = 1), z along the field", fontsize=9)
    fig.tight_layout()
    png = atomic_savefig(fig, Path(out_dir) / f"{stem}_rod.png", dpi=120)
    plt.close(fig)
    lines = ["s,x,y,z"] + [f"{s:.17g},{a:.17g},{b:.17g},{z:.17g}" for s, (a, b, z) in zip(rod["s"], r)]
    csv = atomic_write_text(Path(out_dir) / f"{stem}_centreline.csv", "\n".join(lines) + "\n")
    return [str(png), str(csv)]
