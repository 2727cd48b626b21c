"""Figures of sec. 8, symmetric multipulse homoclinic orbits: fig:multimodal1 (Figure 6) and fig:multimodal2
(Figure 7), and the files of `magrod multipulse` for either saddle (one orbit file per orbit, magrod.core.io
.write_orbit; a table of all N)."""
from __future__ import annotations

import time
from pathlib import Path

from ..core.io import atomic_write_json, ensure_writable_dir, versions, write_orbit
from ..core.printed import MULTIPULSE
from ..core.progress import bar
from ..core.tolerances import LAUNCH_DISTANCES
from ..orbits.equilibrium import straight_rod
from ..orbits.multipulse import find_orbits
from ..orbits.shooting import THETA_CUT, scaled_arclength
from .common import atomic_savefig, pyplot
from .rod import plot_rod, rod_from_orbit_file

TAU = f"(s - T)/L, L = T - s(theta first >= {THETA_CUT})"


def write_entry(entry: dict, out_dir, stem: str, extra: dict | None = None) -> list[str]:
    """One find_orbits entry as an orbit file (magrod.core.io.write_orbit) with the entry's summary as metadata."""
    meta = {k: v for k, v in entry.items() if k not in ("result", "orbit")}
    meta.update({"tau": TAU, **(extra or {})})
    return write_orbit(out_dir, stem, entry["result"], samples=entry["orbit"], meta=meta)


def multipulse(params, out_dir=None, *, free: str = "lam", max_pulses: int = 6, span: float = 0.5,
               samples: int = 81, stem: str = "multipulse", progress: bool = False,
               with_uncertainty: bool = True) -> tuple:
    """find_orbits + files: one .npz/.json per orbit found and a table (JSON) of all N <= max_pulses, each
    found orbit with the free parameter at two eps and two precisions (multipulse.uncertainty: value, uncertainty,
    significant digits) unless with_uncertainty is False.  Returns (summary dict, the find_orbits entries)."""
    straight_rod(params)  # bad input fails before any file is written
    if out_dir is not None:
        ensure_writable_dir(out_dir)
    t0 = time.perf_counter()
    with bar(samples, f"scan {free}", progress) as update:
        found = find_orbits(params, free=free, max_pulses=max_pulses, span=span, samples=samples, progress=update,
                            with_uncertainty=with_uncertainty)
    rows = []
    for e in found:
        row = {k: v for k, v in e.items() if k not in ("result", "orbit")}
        if e["success"] and out_dir is not None:
            row["paths"] = write_entry(e, out_dir, f"{stem}_N{e['pulses']}",
                                       {"nominal_params": params.as_dict(), "free": free})
        rows.append(row)
    out = {"ok": True, "params": params.as_dict(), "free": free, "span": span, "samples": samples,
           "orbits": rows, "wall_time_s": time.perf_counter() - t0,
           "uncertainty_method": f"{free}* at launch distances eps = {LAUNCH_DISTANCES} in double and long double; "
                                 "value = long double at the smaller eps, uncertainty = max(long double spread "
                                 "over eps, Newton resolution through J^-1 at the residual or noise floor); "
                                 "double_check = |double - value| (double floor 1e-8..1e-6 after near-saddle "
                                 "passages)",
           "note": "symmetric homoclinic orbits of the straight rod are of codimension one (the launch phase is a "
                   f"symmetry): each orbit exists at its own value of {free}, found by Newton on (T, {free})"}
    if out_dir is not None:
        out["table"] = str(atomic_write_json(Path(out_dir) / f"{stem}_table.json", {**out, "versions": versions()}))
    return out, found


def periodic_multipulse(params, out_dir, *, max_pulses: int = 3, samples: int = 121,
                         progress: bool = False) -> dict:
    """`magrod multipulse` for mu != 2 lam: periodic_multipulse.multipulse_rows plus one orbit file per orbit found
    (magrod.core.io.write_orbit: the schema `magrod rod --from` reads)."""
    from ..orbits import periodic_multipulse as pm

    out = ensure_writable_dir(out_dir) if out_dir is not None else None
    summary, found = pm.multipulse_rows(params, max_pulses=max_pulses, samples=samples)
    for row, r in found:
        if out is None:
            continue
        stem = f"multipulse_periodic_N{row['pulses']}_{row['index']}"
        row["paths"] = write_orbit(out, stem, r, meta=dict(row))
    return summary


def _lam_text(e: dict) -> str:
    u = e.get("uncertainty") or {}
    return u["significant"] if u.get("success") else f"{e['free_value']:.6g}"


def _figure(number: int, out_dir, quick: bool = False, progress: bool = False) -> list[str]:
    plt = pyplot()
    spec = MULTIPULSE[number]
    out_dir = ensure_writable_dir(out_dir)
    max_pulses = max(spec["show"]) if quick else 6
    summary, found = multipulse(spec["params"], out_dir, max_pulses=max_pulses, samples=41 if quick else 81,
                                stem=f"figure{number}", progress=progress)
    paths = [summary["table"]]
    for row in summary["orbits"]:
        paths += row.get("paths", [])
    fig, ax = plt.subplots(figsize=(7, 3.2))
    for N, style in zip(spec["show"], ("-", "--")):
        e = found[N - 1]
        if not e["success"]:
            continue
        tau, win = scaled_arclength(e["orbit"])
        ax.plot(tau[win], e["orbit"]["theta"][win], style, color="k", lw=1.2,
                label=f"{N}-pulse, $\\bar\\lambda^*$ = {_lam_text(e)}, residual {e['residual']:.1e}")
    p = spec["params"]
    ax.set_xlim(-1, 1)
    ax.set_ylim(bottom=0)
    ax.set_xlabel(r"$(s - s_{sym})/L$")
    ax.set_ylabel(r"$\theta$")
    ax.set_title(f"Fig. {number} ({spec['label']}): m={p.m}, $\\gamma$={p.gamma}, $\\delta$={p.delta}, "
                 f"$\\mu = 2\\bar\\lambda$ "
                 f"(paper $\\bar\\lambda$={p.lam})", fontsize=9)
    ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    paths.append(str(atomic_savefig(fig, Path(out_dir) / f"figure{number}.png", dpi=150)))
    plt.close(fig)
    # 3-D rod shapes of the orbits shown (directors + extensible centreline, magrod.orbits.rod), from the files just written
    for N in spec["show"]:
        e = found[N - 1]
        if not e["success"]:
            continue
        stem = f"figure{number}_N{N}"
        r = rod_from_orbit_file(Path(out_dir) / f"{stem}.npz")
        paths += plot_rod(r, out_dir, stem, title=f"Fig. {number}: {N}-pulse rod, lam* = {_lam_text(e)}, "
                                                         f"orthonormality {r['orthonormality']:.1e}")
    return paths


def figure_6(out_dir, *, quick: bool = False, progress: bool = False) -> list[str]:
    """fig:multimodal1: two- and four-pulse orbits near lam = 0.001 (mu = 2 lam), plus N <= 6 table."""
    return _figure(6, out_dir, quick, progress)


def figure_7(out_dir, *, quick: bool = False, progress: bool = False) -> list[str]:
    """fig:multimodal2: two- and three-pulse orbits near lam = 0.5 (mu = 2 lam), plus N <= 6 table."""
    return _figure(7, out_dir, quick, progress)
