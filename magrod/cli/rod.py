"""`magrod rod`: 3-D rod shape (directors and extensible centreline) of an orbit file from `magrod multipulse`."""
from __future__ import annotations

from pathlib import Path


def add_arguments(p):
    p.add_argument("--from", dest="source", required=True, help="orbit .npz written by `magrod multipulse`")
    from .options import add_out

    add_out(p, files=True)
    p.add_argument("--points", default="3001", help="samples along the rod")


def run(args) -> dict:
    from ..figures.rod import plot_rod, rod_from_orbit_file
    from ..core.io import atomic_write_json, versions
    from .options import integer, out_dir

    points = integer("points", args.points, minimum=2)
    out = out_dir("out", args.out)
    r = rod_from_orbit_file(args.source, n=points)
    stem = Path(args.source).stem
    paths = plot_rod(r, out, stem, title=f"{stem}: pars (m, mu, gamma, delta, lam) = "
                                             f"{[float(f'{v:.6g}') for v in r['pars']]}")
    res = {"ok": True, "source": str(args.source), "paths": paths, "length": float(r["s"][-1] - r["s"][0]),
           "end_to_end": float(abs(r["r"][-1] - r["r"][0]).max()), "orthonormality": r["orthonormality"],
           "det": r["det"], "field_consistency": r["field_consistency"],
           "deviation_from_symmetric_orbit": r["deviation_from_symmetric_orbit"],
           "deviation_first_half": r["deviation_first_half"],
           "scale": "B = C = m3 = 1: s and r in units of B/m3; z along the field"}
    res["paths"].append(str(atomic_write_json(out / f"{stem}_rod.json", {**res, "versions": versions()})))
    return res


def format_text(d: dict) -> str:
    return (f"rod from {d['source']}: length {d['length']:.6g} (units B/m3), orthonormality {d['orthonormality']:.1e}, "
            f"det {d['det']:.1e}, field consistency {d['field_consistency']:.1e}, deviation from symmetric orbit "
            f"{d['deviation_from_symmetric_orbit']:.1e}\n  " + "\n  ".join(d["paths"]))
