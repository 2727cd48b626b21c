"""Figures of sec. 8, symmetric multipulse homoclinic orbits: fig:multimodal1 (Figure 6) and fig:multimodal2
(Figure 7), and the files of `magrod multipulse` for either saddle (`write_search`: one orbit file per orbit,
magrod.core.io.write_orbit; a table of all N), all from the result of the public search (multipulse_orbits)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..core.io import atomic_write_json, ensure_writable_dir, versions, write_orbit
from ..paper import MULTIPULSE
from ..core.progress import bar
from ..core.tolerances import LAUNCH_DISTANCES
from .. import multipulse_orbits
from ..orbits import THETA_CUT
from .common import atomic_savefig, pyplot
from .rod import plot_rod, rod_from_orbit_file

TAU = f"(s - T)/L, L = T - s(theta first >= {THETA_CUT})"
UNCERTAINTY_METHOD = (f"{{free}}* at launch distances {LAUNCH_DISTANCES} in double and long double; value = long "
                      "double at the smaller launch distance, uncertainty = max(long double spread over launch distances, Newton resolution "
                      "through J^-1 at the residual or noise floor); double_check = |double - value| (double floor "
                      "1e-8..1e-6 after near-saddle passages)")


def write_search(search, out_dir, stem: str = "multipulse") -> dict:
    """The files of a multipulse search (a MultipulseSearch, magrod.orbits.multipulse.multipulse_orbits): one
    orbit file per orbit found (magrod.core.io.write_orbit, the schema `magrod rod --from` reads) with its
    search's row as metadata, and for the straight rod a table (JSON) of all N.  Writes nothing else and
    computes nothing: the figures and `magrod multipulse` pass the search they have.  Returns {"files": [the two
    paths of each orbit, in search.orbits order], "table": the table's path or None, "rows": the table rows}."""
    out = ensure_writable_dir(out_dir)
    files, rows = [], []
    if search.kind == "equilibrium":
        extra = {"nominal_params": search.params.to_dict(), "free": search.free}
        for ps in search.searches:
            row = ps.row()
            if ps.success:
                meta = {**row, "tau": TAU, **extra}
                row["paths"] = write_orbit(out, f"{stem}_N{ps.pulses_target}", ps.orbit, samples=ps.samples[0],
                                           meta=meta)
                files.append(row["paths"])
            rows.append(row)
        table = {"ok": True, "params": search.params.to_dict(), "free": search.free, "span": search.span,
                 "samples": search.samples, "orbits": rows, "wall_time_s": search.wall_time_s,
                 "uncertainty_method": UNCERTAINTY_METHOD.format(free=search.free),
                 "note": "symmetric homoclinic orbits of the straight rod are of codimension one (the launch phase is "
                         f"a symmetry): each orbit exists at its own value of {search.free}, found by Newton on (T, "
                         f"{search.free})"}
        path = str(atomic_write_json(Path(out) / f"{stem}_table.json", {**table, "versions": versions()}))
        return {"files": files, "table": path, "rows": rows}
    for ps in search.searches:  # the periodic saddle: generic orbits, several per N
        if not ps.success:
            rows.append(ps.row())
        for k, r in enumerate(ps.orbits):
            row = {"pulses_target": ps.pulses_target, "pulses": ps.pulses_target, "index": k, **r.to_dict(arrays=False)}
            row["paths"] = write_orbit(out, f"{stem}_periodic_N{ps.pulses_target}_{k}", r, meta=dict(row))
            files.append(row["paths"])
            rows.append(row)
    return {"files": files, "table": None, "rows": rows}


def _lam_text(ps) -> str:
    u = ps.uncertainty or {}
    return u["significant"] if u.get("success") else f"{ps.summary['free_value']:.6g}"


def _figure(number: int, out_dir, quick: bool = False, progress: bool = False) -> list[str]:
    plt = pyplot()
    spec = MULTIPULSE[number]
    out_dir = ensure_writable_dir(out_dir)
    max_pulses = max(spec["show"]) if quick else 6
    samples = 41 if quick else 81
    with bar(samples, "scan lam", progress) as update:
        search = multipulse_orbits(spec["params"], max_pulses, samples=samples, with_uncertainty=True,
                                   progress=update)
    written = write_search(search, out_dir, stem=f"figure{number}")
    paths = [written["table"]]
    for row in written["rows"]:
        paths += row.get("paths", [])
    fig, ax = plt.subplots(figsize=(7, 3.2))
    top = 0.0
    for N, style in zip(spec["show"], ("-", "--")):
        ps = search.search(N)
        if not ps.success:
            continue
        tau = ps.samples[0]["tau"]  # the scaled arclength of MultipulseOrbit.sample
        win = np.abs(tau) <= 1.0
        # the residual of each orbit is in its sidecar (figure<n>_N<N>.json), not in the legend: a short legend fits
        # inside the axes (a long one was moved outside, leaving a third of the width blank)
        ax.plot(tau[win], ps.samples[0]["theta"][win], style, color="k", lw=1.2,
                label=f"{N}-pulse, $\\bar\\lambda^* = {_lam_text(ps)}$")
        top = max(top, float(np.nanmax(ps.samples[0]["theta"][win])))
    p = spec["params"]
    ax.set_xlim(-1, 1)
    ax.set_ylim(0, 1.45 * top if top > 0 else None)  # headroom for the legend above the pulses
    ax.set_xlabel(r"$(s - s_{sym})/L$")
    ax.set_ylabel(r"$\theta$")
    ax.set_title(f"Fig. {number} ({spec['label']}): $m = {p.m}$, $\\gamma = {p.gamma}$, $\\delta = {p.delta}$, "
                 f"$\\mu = 2\\bar\\lambda$ (paper: $\\bar\\lambda = {p.lam}$)", fontsize=9)
    ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    paths.append(str(atomic_savefig(fig, Path(out_dir) / f"figure{number}.png", dpi=150)))
    plt.close(fig)
    # 3-D rod shapes of the orbits shown (directors + extensible centreline, magrod.orbits.rod), from the files just written
    for N in spec["show"]:
        ps = search.search(N)
        if not ps.success:
            continue
        stem = f"figure{number}_N{N}"
        r = rod_from_orbit_file(Path(out_dir) / f"{stem}.npz")
        paths += plot_rod(r, out_dir, stem, title=f"Fig. {number}: {N}-pulse rod, lam* = {_lam_text(ps)}, "
                                                         f"orthonormality {r['orthonormality']:.1e}")
    return paths


def figure_6(out_dir, *, quick: bool = False, progress: bool = False) -> list[str]:
    """fig:multimodal1: two- and four-pulse orbits near lam = 0.001 (mu = 2 lam), plus N <= 6 table."""
    return _figure(6, out_dir, quick, progress)


def figure_7(out_dir, *, quick: bool = False, progress: bool = False) -> list[str]:
    """fig:multimodal2: two- and three-pulse orbits near lam = 0.5 (mu = 2 lam), plus N <= 6 table."""
    return _figure(7, out_dir, quick, progress)
