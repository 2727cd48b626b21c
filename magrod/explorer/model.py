"""What the explorer draws, computed without a page: the energy-level boundary of the section, the colour of an
orbit's chaos indicator, parameter parsing as the CLI parses, and the 3-D rod of a selected orbit.

The section sin(psi) = 0 is drawn in (theta, pbar_theta).  Hbar = pbar_theta^2/(2) + V(theta, psi, pbar_psi)
(eq:full_ham_nondim: the only pbar_theta term is m^2 pbar_theta^2 / (2 m^2)), so a point (theta, pbar_theta) of
the section is reachable at level h iff pbar_theta^2 <= 2 (h - min_pbar_psi V(theta, psi, pbar_psi)), the
minimum taken over the admissible pbar_psi (mu - 2 lam pbar_psi >= 0).  `energy_boundary` computes
V_min(theta) on a grid (a coarse scan of pbar_psi, widened until the minimum is interior, then refined by
zooming), so the drawn curve is pbar_theta = +- sqrt(2 (h - V_min)).  It is a drawing aid: whether a click has an
energy root is decided by magrod.chaos.section.solve_p_psi, never by this curve.

The section sin(psi) = 0 has two branches, psi = 0 and psi = pi (an orbit's crossings are recorded on both unless
its options say otherwise), and V depends on psi: each branch has its own boundary (`section_boundaries`).  The
page draws each branch's points with its own marker over its own boundary and "no root" shading, since a psi = pi
point may lie where psi = 0 has no root.
"""
from __future__ import annotations

import numpy as np

from ..core.errors import MAX_MAGNITUDE, ParameterError, require_finite
from ..core.limits import LIMITS, integer
from ..core.params import RodParams

GROWTH_VMAX = 1000.0  # top of the colour scale: the Fig 4 orbits reach growth exponents ~10-1000 at T = 3000
REGULAR_COLOUR = "#313695"


def _V(theta, psi, ppsi, params: RodParams):
    """Hbar at pbar_theta = 0 (the compiled generated Hbar), +inf where the radicand is negative."""
    from ..core import systems

    th = np.asarray(theta, float)
    q = np.asarray(ppsi, float)
    th, q = np.broadcast_arrays(th, q)
    x = np.ascontiguousarray(np.vstack([th.ravel(), np.full(th.size, float(psi)), np.zeros(th.size), q.ravel()]))
    with np.errstate(invalid="ignore"):
        v = systems.reduced_functions()["H"](x, params.array())[0].reshape(th.shape)
    return np.where(np.isfinite(v), v, np.inf)


def energy_boundary(params: RodParams, h: float, psi: float = 0.0, n: int = 361) -> dict:
    """theta (n,) in (0, pi) and pmax (n,) = sqrt(2 max(h - V_min(theta), 0)), V_min (n,), the minimising pbar_psi
    (n,), and `allowed` (n,) = V_min <= h.  The reachable part of the section at level h is |pbar_theta| <= pmax."""
    theta = np.linspace(0.0, np.pi, n + 2)[1:-1]
    s, c = np.sin(theta), np.cos(theta)
    edge = np.inf
    if params.lam != 0:  # admissible pbar_psi: mu - 2 lam pbar_psi >= 0
        edge = params.mu / (2 * params.lam)
    u = np.linspace(-1.0, 1.0, 801)
    W = 2.0 * s * np.sqrt(2.0 * abs(h) + 4.0) + 1.0  # the quadratic term (pbar_psi - cos)^2 / (2 sin^2) dominates
    for _ in range(40):
        q = c[:, None] + W[:, None] * u[None, :]
        if np.isfinite(edge):
            q = np.where((params.lam > 0) & (q > edge), edge, q)
            q = np.where((params.lam < 0) & (q < edge), edge, q)
        v = _V(theta[:, None], psi, q, params)
        i = np.argmin(v, axis=1)
        at_end = ((i == 0) | (i == u.size - 1)) & ~np.isclose(q[np.arange(theta.size), i], edge)
        if not at_end.any():
            break
        W = np.where(at_end, 2 * W, W)
    rows = np.arange(theta.size)
    best_q, best_v = q[rows, i], v[rows, i]
    step = W * (u[1] - u[0])
    for _ in range(8):  # zoom in around the minimum
        z = np.linspace(-1.0, 1.0, 41)
        qq = best_q[:, None] + step[:, None] * z[None, :]
        if np.isfinite(edge):
            qq = np.where((params.lam > 0) & (qq > edge), edge, qq)
            qq = np.where((params.lam < 0) & (qq < edge), edge, qq)
        vv = _V(theta[:, None], psi, qq, params)
        j = np.argmin(vv, axis=1)
        better = vv[rows, j] < best_v
        best_q = np.where(better, qq[rows, j], best_q)
        best_v = np.where(better, vv[rows, j], best_v)
        step = step / 10.0
    pmax = np.sqrt(2.0 * np.clip(h - best_v, 0.0, None))
    return {"theta": theta, "pmax": pmax, "V_min": best_v, "p_psi_min": best_q, "allowed": best_v <= h}


# the two branches of the section sin(psi) = 0: the key of each (SectionOptions.branch's spelling) and its psi
BRANCH_PSI = {"0": 0.0, "pi": float(np.pi)}
BRANCH_LABEL = {"0": "ψ = 0", "pi": "ψ = π"}


def section_boundaries(params: RodParams, h: float, n: int = 361) -> dict:
    """{branch: energy_boundary(params, h, psi)} for the branches "0" (psi = 0) and "pi" (psi = pi)."""
    return {k: energy_boundary(params, h, psi=psi, n=n) for k, psi in BRANCH_PSI.items()}


def branch_of(psi) -> np.ndarray:
    """The branch key ("0" or "pi") of section points with angle psi: cos psi > 0 is psi = 0, as the section's
    branch flag (PoincareResult.branch) decides it."""
    return np.where(np.cos(np.asarray(psi, float)) > 0, "0", "pi")


def no_root(theta, ptheta, boundary: dict) -> np.ndarray:
    """True where (theta, pbar_theta) lies in the "no root" region of `boundary` (an energy_boundary), beyond
    the drawing's own resolution: |pbar_theta| exceeds the largest pmax of the two grid intervals around theta
    (the drawn curve is piecewise linear between grid points)."""
    th, pmax = boundary["theta"], boundary["pmax"]
    theta, ptheta = np.asarray(theta, float), np.asarray(ptheta, float)
    i = np.clip(np.searchsorted(th, theta), 1, len(th) - 1)
    local = np.max([pmax[np.clip(i + d, 0, len(th) - 1)] for d in (-2, -1, 0, 1)], axis=0)
    return np.abs(ptheta) > local + 1e-12


# ----------------------------------------------------------------------------------------------------------
# colours: the growth exponent on the chaos map's scale (magrod.figures.chaos.growth_norm)
# ----------------------------------------------------------------------------------------------------------
POINT_SHADE = 0.8  # RGB factor: the chaos map's colours, darkened so that near-threshold (pale) points show on white


def growth_scale(threshold: float, vmax: float = GROWTH_VMAX):
    """(norm, cmap): the chaos map's colour scale, linear on [0, threshold], logarithmic above (growth_norm), on
    the chaos map's colour map (RdYlBu_r: blue regular, red chaotic) darkened by POINT_SHADE: its pale middle
    (the threshold) would vanish as small points on a white page."""
    import matplotlib
    from matplotlib.colors import ListedColormap

    from ..figures.chaos import growth_norm

    base = matplotlib.colormaps["RdYlBu_r"](np.linspace(0.0, 1.0, 256))
    base[:, :3] *= POINT_SHADE
    return growth_norm(vmax, threshold), ListedColormap(base, name="RdYlBu_r_dark")


def growth_colour(g: float, threshold: float, vmax: float = GROWTH_VMAX) -> str:
    """Hex colour of a growth exponent g on the chaos map's scale."""
    from matplotlib.colors import to_hex

    norm, cmap = growth_scale(threshold, vmax)
    return to_hex(cmap(float(norm(min(max(g, 0.0), vmax)))))


def palette(threshold: float, vmax: float = GROWTH_VMAX, n: int = 256) -> list[str]:
    from matplotlib.colors import to_hex

    _, cmap = growth_scale(threshold, vmax)
    return [to_hex(cmap(k / (n - 1))) for k in range(n)]


def colorbar_ticks(threshold: float, vmax: float = GROWTH_VMAX) -> dict:
    """{position on the normalised bar (0..1): label} at the chaos map's ticks (growth_ticks)."""
    from ..figures.chaos import growth_ticks

    norm, _ = growth_scale(threshold, vmax)
    return {float(norm(t)): (f"{t:g}" + (" (threshold)" if t == threshold else "")) for t in
            growth_ticks(vmax, threshold)}


# ----------------------------------------------------------------------------------------------------------
# inputs, parsed as the CLI parses them (the same parsers, core.limits.integer), errors naming the field
# ----------------------------------------------------------------------------------------------------------
FIELDS = ("m", "mu", "gamma", "delta", "lam", "h", "iterates")
ITERATES_MAX = LIMITS["iterates"]  # the limit of poincare_section and the command line (core/limits.py)


def parse_inputs(values: dict) -> tuple[RodParams, float, int]:
    """(RodParams, h, iterates) from the widgets' strings; ParameterError names the first offending field, with
    the message `magrod poincare` would print for it (same parsers: require_finite to 1e6, RodParams' checks,
    the CLI's integer rule for --iterates)."""
    nums = {}
    for name in ("m", "mu", "gamma", "delta", "lam", "h"):
        nums[name] = require_finite(name, str(values[name]).strip(), MAX_MAGNITUDE)
    params = RodParams(**{k: nums[k] for k in ("m", "mu", "gamma", "delta", "lam")})
    iterates = integer("iterates", str(values["iterates"]).strip(), maximum=ITERATES_MAX)
    return params, nums["h"], iterates


def input_errors(values: dict) -> tuple[tuple | None, dict]:
    """((RodParams, h, iterates), {}) if every field is valid, else (None, {field: message}) naming every field
    that is wrong at once (parse_inputs stops at the first): each number is parsed on its own, the iterate count
    on its own; RodParams' checks and the energy level (check_energy_level) are judged only once every number
    parses, and name their field."""
    errors, nums = {}, {}
    for name in ("m", "mu", "gamma", "delta", "lam", "h"):
        try:
            nums[name] = require_finite(name, str(values[name]).strip(), MAX_MAGNITUDE)
        except ParameterError as exc:
            errors[name] = str(exc)
    try:
        iterates = integer("iterates", str(values["iterates"]).strip(), maximum=ITERATES_MAX)
    except ParameterError as exc:
        errors["iterates"] = str(exc)
    if errors:
        return None, errors
    try:
        params = RodParams(**{k: nums[k] for k in ("m", "mu", "gamma", "delta", "lam")})
        check_energy_level(params, nums["h"])
    except ParameterError as exc:
        return None, {exc.name if exc.name in FIELDS else "h": str(exc)}
    return (params, nums["h"], iterates), {}


def check_energy_level(params: RodParams, h: float) -> dict:
    """The boundary at (params, h); ParameterError("mu") if the square root sqrt(mu - 2 lam pbar_psi) of Hbar is
    imaginary for every pbar_psi (the root solver's rule), ParameterError("h") if no point of the section
    psi = 0 is reachable."""
    from ..chaos import admissible_interval

    admissible_interval(params)
    b = energy_boundary(params, h)
    if not b["allowed"].any():
        raise ParameterError("h", f"no point of the section psi = 0 lies on Hbar = {h:g}: min Hbar there is "
                                  f"{float(np.min(b['V_min'])):.6g}; raise h")
    return b


# ----------------------------------------------------------------------------------------------------------
# the rod of an orbit
# ----------------------------------------------------------------------------------------------------------
def rod_of(start, length: float = 100.0, n: int = 2001) -> dict:
    """The rod's centreline and directors over arclength [0, length] from a section start (magrod.orbits.rod
    reconstruct; D0 with the field along z), with the drawing magnification (magrod.figures.rod.magnification)
    and the checks of the frame."""
    from ..core import systems
    from ..figures.rod import magnification
    from ..orbits import reconstruct_rod as reconstruct

    length = require_finite("rod_length", length)
    if not 0 < length <= 1e5:
        raise ParameterError("rod_length", f"must satisfy 0 < length <= 1e5, got {length:g}")
    pars = start.params.array()
    x0 = systems.euler_to_body(start.theta0, start.psi0, start.ptheta0, start.p_psi0, pars)
    rod = reconstruct(x0, pars, np.linspace(0.0, length, int(n)))
    M, u, perp = magnification(rod["r"])
    r = rod["r"]
    along = (r - r[0]) @ u
    rod["magnification"] = M
    rod["r_drawn"] = r[0] + np.outer(along, u) + M * perp
    return rod


def tube_mesh(c: np.ndarray, radius: float, k: int = 12) -> dict:
    """A tube of `radius` around the polyline c (N, 3): vertices (N k, 3) and triangles i, j, k, with frames
    carried along by parallel transport (no twist artefacts)."""
    c = np.asarray(c, float)
    t = np.gradient(c, axis=0)
    t /= np.linalg.norm(t, axis=1, keepdims=True) + 1e-300
    a = np.array([1.0, 0.0, 0.0]) if abs(t[0, 0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    nrm = np.cross(t[0], a)
    nrm /= np.linalg.norm(nrm)
    N = np.empty_like(c)
    for i in range(len(c)):
        if i:
            nrm = nrm - (nrm @ t[i]) * t[i]
            nrm /= np.linalg.norm(nrm) + 1e-300
        N[i] = nrm
    Bn = np.cross(t, N)
    ang = 2 * np.pi * np.arange(k) / k
    ring = np.cos(ang)[None, :, None] * N[:, None, :] + np.sin(ang)[None, :, None] * Bn[:, None, :]
    verts = (c[:, None, :] + radius * ring).reshape(-1, 3)
    ii, jj, kk = [], [], []
    for i in range(len(c) - 1):
        for q in range(k):
            a0, a1 = i * k + q, i * k + (q + 1) % k
            b0, b1 = a0 + k, a1 + k
            ii += [a0, a1]
            jj += [b0, b0]
            kk += [a1, b1]
    return {"vertices": verts, "i": np.array(ii), "j": np.array(jj), "k": np.array(kk)}
