"""`magrod rod --from FILE`: 3-D rod shape (directors and centreline) of an orbit file: one of the paper's rod from
`magrod multipulse`, or one of any other model from `magrod homoclinic --model` or `magrod multipulse --model`.  A
model's orbit file records the model and its parameters: the rod is that model's (give --model / --model-params only
to check them: a different model or parameter value is refused, naming it), and the orbit is re-shot from the
file's unknowns before its rod is integrated (`mr.rod_shape`)."""
from __future__ import annotations

from pathlib import Path


def add_arguments(p):
    p.add_argument("--from", dest="source", required=True,
                   help="orbit .npz written by `magrod multipulse` or `magrod homoclinic --model`")
    from .options import add_model, add_out

    add_out(p, files=True)
    p.add_argument("--points", default="3001", help="samples along the rod")
    add_model(p, help="the rod model of the orbit file (default: the one the file records; given, it must be "
                      "that one)")


def run(args) -> dict:
    from ..core.io import is_model_orbit_file
    from .options import integer, out_dir

    points = integer("points", args.points, minimum=2)
    out = out_dir("out", args.out)
    if is_model_orbit_file(args.source):
        return _model_run(args, points, out)
    from .options import is_paper_model

    if not is_paper_model(args.model):
        from ..core.errors import ParameterError
        from ..core.io import load_orbit_file

        load_orbit_file(args.source)  # a missing or broken file: ParameterError("from"), as for the paper's rod
        raise ParameterError("model", f"{str(args.source)!r} is an orbit file of the paper's rod, not of the model "
                                      f"{str(args.model)[:80]!r}")
    if args.model_params:
        from ..core.errors import ParameterError

        raise ParameterError("model_params", "needs --model (an orbit file of the paper's rod carries its parameters)")
    from ..figures.rod import plot_rod, rod_from_orbit_file
    from ..core.io import atomic_write_json, versions

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


def _model_run(args, points: int, out) -> dict:
    """A model's orbit file: the system it records (checked against --model / --model-params), the orbit re-shot
    (magrod.orbits.orbit_from_file), its rod (mr.rod_shape) with the frame checks, the picture and the JSON."""
    import magrod as mr

    from ..core.errors import ParameterError
    from ..core.io import atomic_write_json, load_model_orbit_file, versions
    from ..core.system import as_system
    from ..figures.rod import plot_rod
    from ..orbits import orbit_from_file
    from .options import is_paper_model, model_params

    d = load_model_orbit_file(args.source)
    recorded = dict(zip(d["param_names"], (float(v) for v in d["pars"])))
    if not is_paper_model(args.model):
        given, _ = as_system(args.model)
        if given.model != d["model"]:
            raise ParameterError("model", f"the orbit file {str(args.source)!r} is of the model {d['model']!r}, not "
                                          f"{given.model!r}")
    elif args.model is not None:
        raise ParameterError("model", f"the orbit file {str(args.source)!r} is of the model {d['model']!r}, not the "
                                      "paper's rod")
    # --model-params over the recorded values: an unknown name is refused by as_system, a value other than the
    # file's by orbit_from_file (naming the parameter)
    system, _ = as_system(d["model"], **{**recorded, **model_params(args)})
    orbit = orbit_from_file(system, d)
    rod = mr.rod_shape(system, orbit, n=points)
    stem = Path(args.source).stem
    pars = ", ".join(f"{k} = {v:.6g}" for k, v in system.params.items())
    paths = plot_rod({"s": rod.s, "r": rod.r}, out, stem, title=f"{stem}: the model {system.model} at {pars}",
                     scale="the model's units; z along the field, or along the force n where the model has no field")
    res = {"ok": bool(rod.success), "source": str(args.source), "model": system.model, "params": system.params,
           "pulses": orbit.pulses, "paths": paths, "length": rod.length, "end_to_end": rod.end_to_end,
           "accuracy": {**rod.accuracy, "orbit": orbit.accuracy, **orbit.extra.get("from_file", {})},
           "orthonormality": rod.orthonormality, "det": rod.det, "field_consistency": rod.field_consistency,
           "message": rod.message,
           "scale": "the model's own units; z along the field, or along the force where the model has no field"}
    res["paths"].append(str(atomic_write_json(out / f"{stem}_rod.json", {**res, "versions": versions()})))
    return res


def format_text(d: dict) -> str:
    if d.get("model"):
        return (f"rod of the model {d['model']} from {d['source']}: length {d['length']:.6g}, orthonormality "
                f"{d['orthonormality']:.1e}, det {d['det']:.1e}, field consistency {d['field_consistency']:.1e}, "
                f"orbit residual {d['accuracy']['orbit']['residual']:.1e}\n  " + "\n  ".join(d["paths"]))
    return (f"rod from {d['source']}: length {d['length']:.6g} (units B/m3), orthonormality {d['orthonormality']:.1e}, "
            f"det {d['det']:.1e}, field consistency {d['field_consistency']:.1e}, deviation from symmetric orbit "
            f"{d['deviation_from_symmetric_orbit']:.1e}\n  " + "\n  ".join(d["paths"]))
