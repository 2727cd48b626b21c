"""The integrability report: Casimirs found, involution tables per regime, reduction verified, I2bar
conservation cases, read from the checked-in derivation report generated/report.json (no SymPy), or computed
live by SymPy (`rederive`, `custom_involution`: needs the `derive` extra)."""
from __future__ import annotations

import json
from dataclasses import dataclass
from importlib import resources

from ..core.results import Result

SECTIONS = ("casimirs", "involution", "jacobi", "poisson_map", "I2bar_conservation")


def load_report(rederive: bool = False) -> dict:
    """The symbolic integrability report: generated/report.json as shipped, or (rederive=True) every result
    re-derived now with SymPy (magrod.derive; slow)."""
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
    # the paper's rod is the registry's default model: its exact integrability analyses (Kovalevskaya exponents,
    # Yoshida, Morales-Ramis, stored in generated/decided/registry.json) belong to its report too
    from ..core.models import DEFAULT
    from .decided import rows as decided_rows, stored

    dec = decided_rows(stored()["models"][DEFAULT])
    return {"ok": True, "source": rep["source"], "results": chosen + dec,
            "statuses": {**{r["key"]: r["status"] for r in res}, **{r["key"]: r["status"] for r in dec}},
            "disagreements_with_paper": disagreements}


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


def row_details(r: dict) -> list:
    """The indented detail lines of one report row (brackets, Casimirs, integrals found, candidates, the decided
    rows): the one rendering of `magrod check`, for the paper's rod and for any model."""
    d, lines = r["details"], []
    if r["key"] == "casimirs" and "basis_found (lambda = 0)" in d:
        lines.append("    basis found (lambda generic): " + "; ".join(d["basis_found"]))
        lines.append("    basis found (lambda = 0):     " + "; ".join(d["basis_found (lambda = 0)"]))
    elif r["key"].startswith("involution") and "tables" in d:
        for reg, table in d["tables"].items():
            nz = {k: v for k, v in table.items() if v != "0"}
            lines.append(f"    {reg}: " + ("all brackets vanish" if not nz else
                                             "non-zero: " + "; ".join(f"{k} = {v}" for k, v in nz.items())))
    elif r["key"] == "involution" and "table" in d:
        nz = {k: v for k, v in d["table"].items() if v != "0"}
        lines.append("    " + ("all brackets vanish" if not nz else "non-zero: " + "; ".join(
            f"{k} = {v}" for k, v in nz.items())))
    elif r["key"] == "casimirs" and "basis_found" in d and isinstance(d["basis_found"], dict):
        lines.append("    found: " + "; ".join(f"{k} = {v}" for k, v in d["basis_found"].items()))
    elif r["key"] == "integrals_found":
        lines.append(f"    dim ker {d['dim_kernel']} vs known algebra {d['dim_known_algebra']}; beyond: "
                     + ("; ".join(d["beyond_the_algebra"]) or "none"))
    elif r["key"] == "candidates":
        lines.append("    " + ("; ".join(f"{k}: {'integral' if v else 'NOT an integral'} ({d['references'][k]})"
                                         for k, v in d["first_integral"].items())
                              or "none declared (the model file's CANDIDATES)"))
    elif r["key"] in ("kovalevskaya_exponents", "morales_ramis"):
        from .decided import detail_lines

        lines += detail_lines(r)
    elif r["key"] == "I2bar_conservation":
        for case, v in d["cases"].items():
            lines.append(f"    {{I2bar, Hbar}} at {case}: {'0 (conserved)' if v == '0' else 'non-zero'}")
    return lines


def format_text(out: dict) -> str:
    """Plain-text rendering of summary() / custom_involution() (used by `magrod check` and REPORT.md)."""
    lines = [f"magrod integrability report{' of the model ' + out['model'] if out.get('model') else ''} "
             f"({out['source']})", ""]
    for r in out["results"]:
        lines.append(f"[{r['status']}] {r['label']}: {r['title']}")
        lines.append(f"    shown by: {r['method']}")
        lines += row_details(r)
        lines.append("")
    if not out.get("model"):  # a model of the family is not the printed paper's rod: no such line
        lines.append("disagreements with the printed paper (see docs/errata.md): "
                     + (", ".join(out["disagreements_with_paper"]) or "none"))
    return "\n".join(lines)


@dataclass(repr=False)
class IntegrabilityReport(Result):
    """The derivation's integrability results: rows (one dict per result: key, label, status, title, method,
    details), statuses {key: status}, the keys that disagree with the printed paper, and where they came from
    (generated/report.json, re-derived now, or computed now for a substitution)."""

    success: bool
    message: str
    source: str  # where the results came from: generated/report.json, re-derived now, or computed now
    rows: list  # one dict per result: key, label, status, title, method, details
    statuses: dict  # {key: status}
    disagreements_with_paper: list  # the keys whose result disagrees with the printed paper
    substitution: str | None = None  # the parameter substitution the results were computed for, if any
    model: str | None = None  # a model of the family (model_report): no comparison with the printed paper

    _repr_fields = ("source", "substitution", "disagreements_with_paper")

    def row(self, key: str) -> dict:
        """The result with this key (KeyError naming the known keys otherwise)."""
        for r in self.rows:
            if r["key"] == key:
                return r
        raise KeyError(f"no result {key!r}; known: {', '.join(r['key'] for r in self.rows)}")

    def involution(self) -> dict:
        """{regime: {bracket: value}} of the involution tables in this report."""
        out = {}
        for r in self.rows:
            if r["key"].startswith("involution"):
                out.update(r["details"]["tables"])
        return out

    def text(self) -> str:
        """The report as `magrod check` prints it."""
        return format_text({"source": self.source, "results": self.rows, "model": self.model,
                            "disagreements_with_paper": self.disagreements_with_paper})


def _subs_text(subs) -> str:
    """A substitution given as a dict {symbol: value} in the grammar of derive.poisson.parse_substitution."""
    from ..core.errors import ParameterError

    if isinstance(subs, str):
        return subs
    if not isinstance(subs, dict) or not subs:
        raise ParameterError("subs", f"must be a non-empty dict {{symbol: value}} or 'NAME=VALUE,...', got {subs!r}")
    parts = []
    for k, v in subs.items():
        if isinstance(v, bool) or not isinstance(v, (int, float, str)):
            raise ParameterError("subs", f"value of {k!r} must be a number or a symbol name, got {v!r}")
        parts.append(f"{k}={v}")
    return ",".join(parts)


def model_report(model, decided: bool = True, morales_ramis: bool = False) -> IntegrabilityReport:
    """The derivation report of a rod model of the family (generated/models/<name>/report.json, or a model file's
    cache entry: derive/models/pipeline.py), as an IntegrabilityReport, followed by the decided rows
    (magrod.integrability.decided: Kovalevskaya exponents and the Painleve test, Yoshida, Morales-Ramis; stored for
    registered models, computed now with SymPy for a model file unless decided=False; Morales-Ramis for a model file
    only with morales_ramis=True)."""
    from ..core.models import resolve
    from . import decided as _decided

    mc = resolve(model)
    rows = list(mc.report["results"])
    rows += _decided.rows(_decided.model_result(mc, live=decided, morales_ramis=morales_ramis),
                          skipped_reason="skipped (--fast): exponents and Morales-Ramis of a model file take SymPy "
                                         "time")
    statuses = {r["key"]: r["status"] for r in rows}
    bad = [r["key"] for r in rows if r["status"] == "disagrees"]
    from ..core.models import DEFAULT

    src = ("generated/model_report.json" if mc.origin == "registry" and mc.name == DEFAULT else
           f"generated/models/{mc.name.replace('-', '_')}/report.json" if mc.origin == "registry"
           else f"{mc.origin} (compiled into {mc.directory})")
    return IntegrabilityReport(not bad, "ok" if not bad else f"checks that fail: {', '.join(bad)}", src, rows,
                               statuses, [], None, mc.name)


def integrability_report(system=None, *, subs=None, rederive: bool = False, everything: bool = False,
                         model=None) -> IntegrabilityReport:
    """The symbolic integrability checks: Casimirs, Jacobi identity, involution of H, I1, I2, the Poisson map of
    the reduction and when I2bar is conserved.

    Parameters
    ----------
    system : System, model name, model file, panel key or RodParams, optional
        What is studied (magrod.core.system.as_system); the report is symbolic, so only its model matters.  None or
        the paper's rod: the paper's report below; any other model: its derivation report (equations, Jacobi
        identity, Casimirs found, S^1 symmetry, involution table, candidate integrals, integrals found).
    subs : dict or str, keyword-only, optional
        Compute the involution table live for a modified model, e.g. {"lambda": 0} or "B2=B1,c_J=c_H" (symbols
        B1 B2 C c_H c_J c_K lambda; c = 1/stiffness, so c_H = c_J = c_K = 0 is the inextensible, unshearable
        rod).  Needs SymPy (the `derive` extra).
    rederive : bool
        Re-run the whole SymPy derivation instead of reading generated/report.json (~1 min).
    everything : bool
        Every derived result, not only the integrability ones.
    model : str or path, keyword-only
        Deprecated spelling of `system` for a model (kept for one release): that model's derivation report.

    Returns
    -------
    IntegrabilityReport
        rows, statuses, disagreements_with_paper; `text()` as `magrod check` prints it.

    Raises
    ------
    ParameterError
        Naming `subs` if the substitution is refused by its grammar (user input is data, never code); `model` for
        an unknown model; `system` for what does not convert to a System.

    Examples
    --------
    >>> import magrod as mr
    >>> rep = mr.integrability_report()
    >>> rep.statuses["casimirs"], "melnikov_vanishes" in rep.disagreements_with_paper
    ('holds', True)
    >>> mr.integrability_report("magnetic").row("integrals_found")["details"]["beyond_the_algebra"]
    ['B*e33*lam + m1*n1 + m2*n2 + m3*n3']

    Notes
    -----
    Each row says how it was shown (symbolic simplification to 0, polynomial identity, or seeded high-precision
    points) and its status (proved / numerical / disagrees with the paper).  Reading the checked-in report costs
    nothing; `subs` costs a few seconds of SymPy.
    """
    import warnings

    from ..core.errors import ParameterError

    if isinstance(system, dict) or (isinstance(system, str) and "=" in system):
        # the old first argument was the substitution: integrability_report({"lambda": 0}) / ("B2=B1")
        warnings.warn("integrability_report(subs) is deprecated: the first argument is now the system; pass "
                      "subs=...", DeprecationWarning, stacklevel=2)
        if subs is not None:
            raise ParameterError("subs", "given twice (as the first argument and as subs=)")
        system, subs = None, system
    if model is not None:
        warnings.warn("integrability_report(model=...) is deprecated: the argument is now called system",
                      DeprecationWarning, stacklevel=2)
        if system is not None:
            raise ParameterError("model", "give the model as the first argument (system), not also as model=")
    elif system is not None:
        from ..core.system import as_system

        resolved, _ = as_system(system)
        model = None if resolved.is_paper else resolved.model
    if model is not None:
        if subs is not None or rederive or everything:
            raise ParameterError("model", "a model's report is read as derived: do not combine it with subs, "
                                          "rederive or everything (those apply to the paper's rod)")
        return model_report(model)
    if subs is not None:
        if rederive or everything:
            raise ParameterError("subs", "computes one custom table: do not combine it with rederive or everything")
        out = custom_involution(_subs_text(subs))
    else:
        out = summary(rederive, everything)
    return IntegrabilityReport(True, "ok", out["source"], out["results"], out["statuses"],
                               out["disagreements_with_paper"], out.get("substitution"))
