"""Costs of the rod family, measured in one run on this machine:

  regenerate   the symbolic pipeline + code generation of one model (`python -m derive --model NAME`)
  search       the exact degree-4 first-integral search per model (target <= 30 s for a 6-D model), with a peer:
               SymPy's exact rank of the same matrix L (degree <= 4, the same rational parameters) for a 6-D model
  landscape    `magrod landscape` (quick and full, and quick without the homoclinic splitting), in a fresh process
  splitting    the homoclinic splitting of the anisotropic and curved rods (magrod.separatrix.model_splitting): the
               first call (compiles two cfuncs and one integrator per model) and a second one, at the landscape's
               quick and full settings (full: with the long-double check)

python benchmarks/models.py [--out benchmarks/models.json] [--part splitting landscape]
(--part: run only those parts and update their keys in the existing --out file)
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import _smoke  # noqa: E402  (benchmarks/: on sys.path as the script's directory)


def regenerate() -> dict:
    from magrod.derive import models
    from magrod.derive.build import models_files

    out = {}
    for name in _smoke.n(models.NAMES, models.NAMES[:1]):
        t0 = time.perf_counter()
        models_files([name])
        out[name] = round(time.perf_counter() - t0, 2)
    return out


def search() -> dict:
    from magrod.integrability.model_search import model_search

    out = {}
    for name in ("kirchhoff", "anisotropic", "curved", "extensible", "magnetic", "magnetic-extensible"):
        model_search(name, 2)  # imports and first compile out of the timing
        t0 = time.perf_counter()
        r = model_search(name, _smoke.n(4, 2))
        out[name] = {"s": round(time.perf_counter() - t0, 3), "certified": r.certified}
    t0 = time.perf_counter()
    r = model_search("anisotropic", _smoke.n(4, 3), values={"B1": 1, "B2": 4, "C": 4}, level={"C2": 0})
    out["anisotropic 1:4:4 on C2 = 0 (Goryachev-Chaplygin)"] = {"s": round(time.perf_counter() - t0, 3),
                                                                 "new": r.new_integrals}
    return out


def sympy_peer() -> dict:
    """SymPy's exact rank of L (all monomials of degree <= 4, 6-D anisotropic rod) against magrod's modular
    kernel dimension on the same matrix."""
    import sympy as sp

    from magrod.core.models import resolve
    from magrod.integrability.exact import _column, monomials
    from magrod.integrability.model_search import parameter_values, vector_field

    mc = resolve("anisotropic")
    vals = parameter_values(mc, None, 20)
    X = vector_field(mc, vals)
    D = _smoke.n(4, 2)
    cols = [_column(X, mu) for mu in monomials(D, mc.dim)]
    rows = sorted({r for c in cols for r in c})
    ri = {r: i for i, r in enumerate(rows)}
    M = sp.zeros(len(rows), len(cols))
    for j, c in enumerate(cols):
        for r, v in c.items():
            M[ri[r], j] = sp.Rational(v.numerator, v.denominator)
    t0 = time.perf_counter()
    rank = M.rank()
    t_sympy = time.perf_counter() - t0
    from magrod.integrability.model_search import model_search

    t0 = time.perf_counter()
    r = model_search(mc, D, seed=20, exact_new=False)  # the same rational parameters as the matrix above
    t_magrod = time.perf_counter() - t0
    return {"matrix": [len(rows), len(cols)], "sympy_rank_s": round(t_sympy, 3), "magrod_search_s": round(t_magrod, 3),
            "ratio": round(t_sympy / t_magrod, 1), "kernel_sympy": len(cols) - rank, "kernel_magrod": r.kernel_dims[-1]}


def splitting() -> dict:
    from magrod.separatrix.model_splitting import model_splitting

    out = {}
    for name in _smoke.n(("anisotropic", "curved"), ("anisotropic",)):
        for label, kw in _smoke.n((("quick", {"eps": (0.02, 0.01), "n_phase": 24}), ("full", {"precision_check": True})), (("quick", {"eps": (0.02, 0.01), "n_phase": 24}),)):
            times = []
            for _ in range(_smoke.n(2, 1)):
                t0 = time.perf_counter()
                r = model_splitting(name, **kw)
                times.append(round(time.perf_counter() - t0, 3))
            out[f"{name} {label}"] = {"first_s": times[0], "again_s": times[-1], "success": r.success,
                                      "melnikov_unit": r.melnikov_unit, "scaling_order": round(r.scaling_order, 3)}
    return out


def landscape_cli() -> dict:
    out = {}
    for label, extra in _smoke.n((("quick", ["--quick"]), ("quick, no splitting", ["--quick", "--no-splitting"]),
                                  ("full", [])),
                                 (("tiny", ["--no-scan", "--no-splitting", "--degree", "2", "--t-max", "20"]),)):
        t0 = time.perf_counter()
        p = subprocess.run([sys.executable, "-m", "magrod.cli", "landscape", "--json", *extra], capture_output=True,
                           text=True, env={**os.environ, "PYTHONWARNINGS": "ignore"})
        out[label] = {"s": round(time.perf_counter() - t0, 1), "exit": p.returncode,
                      "message": json.loads(p.stdout)["message"] if p.returncode == 0 else p.stderr[-200:]}
        if _smoke.ON and p.returncode != 0:
            raise RuntimeError(f"magrod landscape {' '.join(extra)}: exit {p.returncode}: {p.stderr[-400:]}")
    return out


PARTS = {"regenerate_s": regenerate, "search_degree4": search, "peer_sympy_rank": sympy_peer,
         "landscape": landscape_cli, "splitting": splitting}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path(__file__).with_name("models.json"))
    ap.add_argument("--part", nargs="+", choices=sorted(PARTS), default=None)
    ap.add_argument("--smoke", action="store_true", help=_smoke.HELP)
    a = ap.parse_args(argv)
    if _smoke.enable(a.smoke):
        for key in a.part or PARTS:
            print(key, PARTS[key](), flush=True)
        return
    res = json.loads(a.out.read_text()) if a.part and a.out.exists() else {}
    for key in a.part or PARTS:
        res[key] = PARTS[key]()
        if a.part:  # the parts re-run later than the rest: each with its own load
            res.setdefault("load_average_by_part", {})[key] = os.getloadavg()
    if not a.part:
        res["load_average"] = os.getloadavg()
        res.pop("load_average_by_part", None)
    a.out.write_text(json.dumps(res, indent=1) + "\n")
    print(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
