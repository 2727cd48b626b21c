"""Integrability decided, at run time: the Kovalevskaya exponents and Painleve test, Yoshida's theorem and
Morales-Ramis along the pendulum solutions of a rod model, as rows of the integrability report.

Registered models are read from generated/decided/registry.json (written by `python -m derive` from
derive/decided.py; no SymPy here).  A model file is analysed live with SymPy (the `derive` extra; ~10 s to a few
minutes: `live=False` skips it and says so).  Each row carries its label: *proved* (an exact computation and a
theorem whose hypotheses are checked) or *evidence* (the Painleve test) or *no conclusion*."""
from __future__ import annotations

import json
from importlib import resources

ROW_KEYS = ("kovalevskaya_exponents", "yoshida", "morales_ramis")


def stored() -> dict:
    """generated/decided/registry.json: {"models": {name: result}, "symmetric_anisotropic_theorem": {...}}."""
    text = resources.files("magrod.generated").joinpath("decided", "registry.json").read_text()
    return json.loads(text)


def theorem() -> dict:
    """The proved theorem for the symmetric anisotropic rod B2 = C = r B1 (exceptional set, steps, hypotheses)."""
    return stored()["symmetric_anisotropic_theorem"]


def model_result(mc, *, live: bool = True, morales_ramis: bool = False) -> dict | None:
    """The decided result of a resolved model (magrod.core.models.ModelCode): stored for registered models,
    computed now for a model file (None if live=False): the exponents and Yoshida (seconds), and Morales-Ramis only
    if `morales_ramis` (Kovacic on a Heun-type equation: tens of seconds per pendulum)."""
    if mc.origin == "registry":
        return stored()["models"][mc.name]
    if not live:
        return None
    from pathlib import Path

    from ..core.errors import EnvironmentFault

    try:
        from ..derive import decided
        from ..derive.models import spec
    except ImportError as exc:
        raise EnvironmentFault("model", f"the exponents of a model file need SymPy (pip install 'magrod[derive]'): "
                                        f"{exc}") from None
    res = decided.model_decided(spec.load_file(Path(mc.origin)), morales_ramis=morales_ramis)
    if not morales_ramis:
        res["morales_ramis"] = {"label": "not run", "verdict": "not run for a model file unless asked "
                                "(--morales-ramis; magrod.integrability.model_report(model, morales_ramis=True))",
                                "pendulums": []}
    return json.loads(json.dumps(res, default=str))


def _balance_line(b: dict) -> str:
    ex = ", ".join(f"{e}" + (f" (x{m})" if m > 1 else "") for e, m in b["exponents"]) or "vary along the family"
    fam = f"{b['dimension']}-parameter family, " if b["dimension"] else ""
    return f"{fam}c = ({', '.join(b['point'].values())}): exponents {ex}: {b['verdict']}"


def rows(res: dict | None, *, skipped_reason: str = "") -> list:
    """Report rows (key, label, status, title, method, details) for a decided result."""
    if res is None:
        return [{"key": "kovalevskaya_exponents", "label": "-", "status": "skipped",
                 "title": "Kovalevskaya exponents, Painleve test, Morales-Ramis: not computed",
                 "method": skipped_reason or "skipped on request", "details": {}}]
    bal = [b for ch in res["choices"] for b in ch["balances"]]
    weights = "; ".join(", ".join(f"{k}:{v}" for k, v in ch["weights"].items()) +
                        (" (whole field weighted-homogeneous)" if ch["homogeneous"] else " (dominant part)")
                        for ch in res["choices"])
    out = [{"key": "kovalevskaya_exponents", "label": "Painleve test", "status": res["painleve"]["label"],
            "title": f"Kovalevskaya exponents of the dominant balances: {res['painleve']['verdict']}",
            "method": ("exact: weights " + (weights or "none found") + "; balances by Groebner decomposition; "
                       "exponents = eigenvalues of K = Df0(c) + diag(w) classified by factoring over Q; ARS "
                       "compatibility at the integer resonances"),
            "details": {"parameters": res["parameters"], "balances": [_balance_line(b) for b in bal],
                        "painleve": res["painleve"]}}]
    y = res["yoshida"]
    out.append({"key": "yoshida", "label": "Yoshida 1983", "status": y["label"],
                "title": "Yoshida's theorem: " + (y.get("statement") or y.get("reason") or ""),
                "method": "exact: K^T grad I = M grad I checked for H and the Casimirs at each balance; left "
                          "eigenspaces of rational exponents counted", "details": y})
    mr = res.get("morales_ramis")
    if mr is not None:
        out.append({"key": "morales_ramis", "label": "Morales-Ramis", "status": mr["label"],
                    "title": "Morales-Ramis along the pendulum solutions: " + mr["verdict"],
                    "method": "exact: invariant coordinate subspaces with a one-degree-of-freedom flow on a "
                              "non-degenerate leaf; the NVE cut down by the linearised Casimirs and integrals and the "
                              "quotient by the symmetry field, reduced to y'' + p y' + q y = 0 with p, q rational in "
                              "z; Kovacic's algorithm (cases 1-3 and the abelian test of G0)",
                    "details": {"pendulums": [{k: v for k, v in p.items() if k != "nve"} | (
                        {"nve": p["nve"]} if isinstance(p.get("nve"), str) else {}) for p in mr["pendulums"]],
                        **({"statement": mr["statement"]} if "statement" in mr else {})}})
    return out


def detail_lines(r: dict) -> list:
    """The indented detail lines of one decided row (balances; pendulums) for the text report."""
    return format_rows([r])[2:-1]


def format_rows(rs: list) -> list:
    """Text lines for `magrod check`."""
    lines = []
    for r in rs:
        lines.append(f"[{r['status']}] {r['label']}: {r['title']}")
        lines.append(f"    shown by: {r['method']}")
        if r["key"] == "kovalevskaya_exponents":
            lines += [f"    balance: {b}" for b in r["details"].get("balances", [])]
        if r["key"] == "morales_ramis":
            for p in r["details"]["pendulums"]:
                g = p.get("galois") or {}
                if "case" in g:
                    what = (f"G = {g['group']}, G0 {'abelian' if g['abelian_identity_component'] else 'NOT abelian'}"
                            f" (Kovacic case {g['case']}, energy {p['energy']})")
                elif "not_run" in g:
                    what = "NVE derived; Kovacic not run: " + g["not_run"]
                else:
                    what = p.get("nve", "")
                frozen = f" ({', '.join(p['frozen'])} = 1)" if p.get("frozen") else ""
                lines.append(f"    particular solution {', '.join(p['normal'])} = 0{frozen}: {what}")
        lines.append("")
    return lines


def theorem_lines() -> list:
    t = theorem()
    return [f"[{t['status']}] {t['theorem']}", f"    exceptional set: {{{', '.join(t['exceptional_set'])}}}; " +
            "; ".join(f"r = {k}: {v}" for k, v in t["explanations"].items()), f"    not proved: {t['not_proved']}"]


def landscape_evidence(model: str) -> tuple:
    """(evidence items for the landscape line of a registered model, the strongest proved sentence or "").  The
    anisotropic line also carries the theorem for the symmetric family."""
    data = stored()
    res = data["models"].get(model)
    if res is None:
        return [], ""
    ev = [{"label": res["painleve"]["label"], "what": "Painleve test (Kovalevskaya exponents, ARS)",
           "detail": res["painleve"]["verdict"] + f" at {res['parameters']}"}]
    y = res["yoshida"]
    ev.append({"label": y["label"], "what": "Yoshida's theorem",
               "detail": "obstruction: no further weighted-homogeneous polynomial integral independent at a balance"
               if y.get("obstruction") else (y.get("reason") or "no obstruction")})
    mr = res.get("morales_ramis") or {}
    if mr:
        ev.append({"label": mr["label"], "what": "Morales-Ramis along the pendulums", "detail": mr["verdict"]})
    strongest = ""
    if mr.get("label") == "proved":
        strongest = (f"not integrable on the pendulums' symplectic leaf at {res['parameters']} "
                     "(proved: Morales-Ramis, Kovacic)")
    if model == "anisotropic":
        t = data["symmetric_anisotropic_theorem"]
        ev.append({"label": t["status"], "what": "Morales-Ramis theorem, symmetric family B2 = C = r B1",
                   "detail": f"not integrable on m.n = 0 for every r > 0 outside {{{', '.join(t['exceptional_set'])}}} "
                             "(" + "; ".join(f"r = {k}: {v}" for k, v in t["explanations"].items()) + ")"})
    return ev, strongest
