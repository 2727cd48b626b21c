"""Integrability decided for a rod model: the strongest exact result each tool gives, labelled.

  * Kovalevskaya exponents and the Painleve (ARS) test (derive/painleve.py): evidence;
  * Yoshida's theorem where the whole field is weighted-homogeneous (derive/painleve.py): proved, about
    weighted-homogeneous polynomial integrals;
  * Morales-Ramis along the pendulum solutions (derive/morales_ramis.py, Kovacic's algorithm on the normal
    variational equation at a generic energy): proved non-integrability on the pendulums' symplectic leaf where G0
    is not abelian; no conclusion where it is abelian;
  * for the anisotropic rod, the theorem for the symmetric family B2 = C = r B1 (exceptional set {1, 2, 4}).

`model_decided(model)` works for every model, a user's model file included; `registry_results()` is what
`python -m derive` writes to generated/models/decided.json (the runtime reads it, no SymPy)."""
from __future__ import annotations

import sympy as sp

from . import morales_ramis as MR
from . import painleve

MR_LEVEL = 0  # the energy of the generic level at which Kovacic's algorithm is run (a Heun-type NVE)


def morales_ramis_summary(model, values: dict | None = None, energy=MR_LEVEL) -> dict:
    """Per pendulum found: the NVE (rational, in z), Kovacic's verdict on it at `energy`, and the overall verdict."""
    _, _, vals = painleve.model_field(model, values)
    planes = MR.invariant_planes(model, vals)
    rows = []
    decided = None
    for pl in planes:
        row = {"normal": [str(model.state[i]) for i in pl[0]], "tangent": [str(model.state[i]) for i in pl[1]],
               "pendulum_casimir": str(pl[2]), "frozen": [str(v) for v in pl[4]]}
        res = MR.nve_reason(model, vals, pl, energy)
        if isinstance(res, str):
            row["nve"] = "not reduced: " + res
            rows.append(row)
            continue
        p, q, d = res
        used = energy
        irrational = MR.irrational_singular_points(p, q)
        if irrational:  # another energy whose singular points are all rational (any level of the pendulum will do)
            alt = _rational_level(model, vals, pl)
            if alt is not None:
                used, p, q = alt
        row.update({"nve": {"p": str(sp.factor(p)), "q": str(sp.factor(q)), **d}, "energy": str(used)})
        if MR.irrational_singular_points(p, q):
            row["galois"] = {"not_run": ("the singular points of the NVE are roots of " + ", ".join(irrational) +
                                         " (irreducible over Q), and at no energy k/8, |k| <= "
                                         f"{LEVEL_SEARCH}, are they all rational: Kovacic's algorithm here needs "
                                         "them in closed form and is impractically slow with them")}
            rows.append(row)
            continue
        g = MR.galois_of(p, q)
        row["galois"] = g.as_dict()
        rows.append(row)
        if not g.abelian_identity_component:
            decided = row
            break
    if not planes:
        verdict = {"label": "no conclusion", "verdict": "no invariant coordinate subspace with a one-degree-of-freedom "
                   "flow on a non-degenerate symplectic leaf found (no particular solution for Morales-Ramis)"}
    elif decided is not None:
        verdict = {"label": painleve.PROVED, "verdict": "not integrable on the pendulum's symplectic leaf",
                   "statement": (f"Morales-Ramis: along the pendulum {decided['normal']} = 0 at energy {energy}, the "
                                 f"normal variational equation has G0 not abelian ({decided['galois']['group']}, "
                                 "Kovacic's algorithm, exact): no meromorphic first integral independent of H on the "
                                 "symplectic leaf of the pendulum, near it")}
    elif rows and all("case" in r.get("galois", {}) for r in rows):
        verdict = {"label": "no conclusion", "verdict": "G0 abelian along every pendulum tried (no obstruction)"}
    elif any("galois" in r for r in rows):
        verdict = {"label": "no conclusion", "verdict": "normal variational equations derived; Galois group not "
                   "decided (" + "; ".join(sorted({r["galois"].get("not_run", "G0 abelian") for r in rows if "galois" in r}))
                   + ")"}
    else:
        verdict = {"label": "no conclusion", "verdict": "particular solutions found but no normal variational equation "
                   "reduced to a second-order equation with rational coefficients (" +
                   "; ".join(sorted({r["nve"] for r in rows})) + ")"}
    return {"pendulums": rows, **verdict}


LEVEL_SEARCH = 40  # energies k/8, |k| <= 40, tried (in the order 0, 1, -1, 2, ...) for rational singular points


def _rational_level(model, vals, plane):
    """(energy, p, q) at the first energy k/8 (k = 0, 1, -1, 2, -2, ..., |k| <= LEVEL_SEARCH) at which every
    singular point of the pendulum's NVE is rational, or None."""
    res = MR.nve(model, vals, plane, MR.h)
    if res is None:
        return None
    p, q, _ = res
    for k in sorted(range(-LEVEL_SEARCH, LEVEL_SEARCH + 1), key=lambda k: (abs(k), -k)):
        e = sp.Rational(k, 8)
        try:
            pe, qe = sp.cancel(p.subs(MR.h, e)), sp.cancel(q.subs(MR.h, e))
        except ZeroDivisionError:
            continue
        if pe.has(sp.zoo, sp.nan) or qe.has(sp.zoo, sp.nan):
            continue
        if not MR.irrational_singular_points(pe, qe):
            return e, pe, qe
    return None


def model_decided(model, values: dict | None = None, *, morales_ramis: bool = True) -> dict:
    """Painleve/Kovalevskaya, Yoshida and Morales-Ramis for one model at exact parameter values (default: the
    model's defaults), JSON-able."""
    out = {"model": model.name, **painleve.model_analysis(model, values)}
    if morales_ramis:
        out["morales_ramis"] = morales_ramis_summary(model, values)
    out["strongest"] = strongest(out)
    return out


def strongest(res: dict) -> dict:
    """The strongest labelled result: a proof of non-integrability (Morales-Ramis, Yoshida) first, then the
    Painleve evidence."""
    mr = res.get("morales_ramis") or {}
    if mr.get("label") == painleve.PROVED:
        return {"label": "proved", "text": "Morales-Ramis: " + mr["verdict"]}
    y = res.get("yoshida") or {}
    if y.get("label") == painleve.PROVED and y.get("obstruction"):
        return {"label": "proved", "text": "Yoshida: no further weighted-homogeneous polynomial integral independent "
                                           "at a balance"}
    pv = res["painleve"]
    return {"label": "evidence", "text": pv["verdict"]}


def registry_results() -> dict:
    """What generated/models/decided.json holds: every registered model at its defaults, and the theorem."""
    from . import models

    out = {"models": {}}
    for name in models.NAMES:
        m = models.get(name)
        out["models"][name] = model_decided(m)
    out["symmetric_anisotropic_theorem"] = MR.symmetric_rod_theorem()
    from . import kovalevskaya1889

    out["kovalevskaya_1889"] = kovalevskaya1889.conditions()
    return out


def files() -> dict:
    """{path relative to generated/: text}: generated/decided/registry.json (deterministic: sorted keys, exact
    values as strings).  Kept out of generated/models/ so the per-model pipeline (and its tests) do not pay for it;
    `python -m derive` writes it and `--check` diffs it."""
    import json

    return {"decided/registry.json": json.dumps(registry_results(), indent=1, sort_keys=True, default=str) + "\n"}
