"""The integrability report: Casimirs found, involution tables per regime, reduction verified, I2bar
conservation cases, read from the checked-in derivation report generated/report.json (no SymPy), or computed
live by SymPy (`rederive`, `custom_involution`: needs the `derive` extra)."""
from __future__ import annotations

import json
from importlib import resources

SECTIONS = ("casimirs", "involution", "jacobi", "poisson_map", "I2bar_conservation")


def load_report(rederive: bool = False) -> dict:
    if rederive:
        from ..derive.build import all_results

        results, _ = all_results()
        return {"results": [r.as_dict() for r in results], "source": "re-derived now"}
    text = resources.files("magrod.generated").joinpath("report.json").read_text()
    rep = json.loads(text)
    rep["source"] = "generated/report.json"
    return rep


def summary(rederive: bool = False, everything: bool = False) -> dict:
    """The integrability results (all derived results if `everything`), their statuses and the keys that
    disagree with the printed paper."""
    rep = load_report(rederive)
    res = rep["results"]
    chosen = res if everything else [r for r in res if r["key"] in SECTIONS]
    disagreements = [r["key"] for r in res if r["status"] == "disagrees"]
    return {"ok": True, "source": rep["source"], "results": chosen,
            "statuses": {r["key"]: r["status"] for r in res}, "disagreements_with_paper": disagreements}


def custom_involution(text: str) -> dict:
    """Brackets among H, I1, I2 and the Casimirs for the model with the substitution `text` (live SymPy)."""
    from ..core.errors import EnvironmentFault, ParameterError

    try:
        from ..derive import poisson
    except ImportError as exc:
        raise EnvironmentFault("subs", f"needs SymPy (pip install '.[derive]'): {exc}") from None

    try:
        sub = poisson.parse_substitution(text)
    except ValueError as exc:  # SubstitutionError: the text was refused by the bounded grammar
        raise ParameterError("subs", str(exc)) from None
    table = poisson.involution_table(sub)
    res = {"key": "involution (custom)", "label": "eq:magnetic_lagrange, eq:int2", "status": "computed",
           "title": f"Brackets among H, I1, I2 and the Casimirs with {text}",
           "method": "symbolic: grad f . J grad g expanded and factored (live)",
           "details": {"tables": {text: table}}}
    return {"ok": True, "source": "computed now", "results": [res], "statuses": {},
            "disagreements_with_paper": [], "substitution": text}


def format_text(out: dict) -> str:
    """Plain-text rendering of summary() / custom_involution() (used by `magrod check` and REPORT.md)."""
    lines = [f"magrod integrability report ({out['source']})", ""]
    for r in out["results"]:
        lines.append(f"[{r['status']}] {r['label']}: {r['title']}")
        lines.append(f"    shown by: {r['method']}")
        d = r["details"]
        if r["key"] == "casimirs":
            lines.append("    basis found (lambda generic): " + "; ".join(d["basis_found"]))
            lines.append("    basis found (lambda = 0):     " + "; ".join(d["basis_found (lambda = 0)"]))
        elif r["key"].startswith("involution"):
            for reg, table in d["tables"].items():
                nz = {k: v for k, v in table.items() if v != "0"}
                lines.append(f"    {reg}: " + ("all brackets vanish" if not nz else
                                                 "non-zero: " + "; ".join(f"{k} = {v}" for k, v in nz.items())))
        elif r["key"] == "I2bar_conservation":
            for case, v in d["cases"].items():
                lines.append(f"    {{I2bar, Hbar}} at {case}: {'0 (conserved)' if v == '0' else 'non-zero'}")
        lines.append("")
    lines.append("disagreements with the printed paper (see docs/errata.md): "
                 + (", ".join(out["disagreements_with_paper"]) or "none"))
    return "\n".join(lines)
