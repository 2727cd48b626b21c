"""The landscape of the paper's sec. 1, re-derived from the models (`magrod landscape`).

Each line of sec. 1 is a claim with a citation.  For each, magrod's evidence from the model's own W and J:
  integrable     -- proved: the Casimirs found (k of them on the n-D state) and (n - k)/2 integrals in involution
                    (every bracket expands to 0: the model's report) whose gradients together with the Casimirs'
                    have rank k + (n - k)/2 (exact, at a seeded rational point: then on an open dense set);
  not integrable -- the strongest evidence available, labelled: the candidate integral lost (symbolic bracket),
                    no polynomial integral beyond H and the Casimirs up to degree D (certified exact search,
                    generic parameters), a chaotic orbit (numerical: Lyapunov estimate above the regular bound, H
                    and Casimirs conserved), for the anisotropic and curved rods the splitting of the straight
                    twisted rod's homoclinic manifold (derived Mel'nikov function with simple zeros; the measured
                    splitting, numerical, with its eps scaling and controls: magrod.separatrix.model_splitting),
                    and for the paper's rod the splitting/Mel'nikov results of
                    docs/nonintegrability.md (generated/report.json keys).
The heavy rod [Gottlieb99] is not a model of the registry (derive/models/heavy.py): its line says why and that
magrod does not test the claim.  Where the evidence disagrees with, or qualifies, the cited claim, the line says so.

The anisotropic scan: B1 : B2 : C over a rational grid, each entry in GRID, at degree 4 on
generic Casimir levels and on m.n = 0 (C2 = 0); every ratio with an integral beyond H and the Casimirs is listed
with the integral, its exact re-check ({F, H} = 0, or = (m.n) G on the level, from J and H directly) and the
explanation (the Kirchhoff kinetic analogue: the rod is a heavy top with moments (B1, B2, C) and the centre of mass
on the d3 axis, so Lagrange (B1 = B2), Kovalevskaya (the pair containing C equal, twice the third) and
Goryachev-Chaplygin (the pair containing C equal, four times the third, on m.n = 0) are the expected cases).
Ratios are classes up to a common factor: (m, n) -> (t m, t n) maps the rod with stiffnesses t B to the rod with
B, preserving polynomial degree.

Cost: ~1 min for the whole landscape with the scan (benchmarks/models.py); quick=True a few seconds.
"""
from __future__ import annotations

import itertools
import math
import random
import time
from dataclasses import dataclass, field
from fractions import Fraction

from ..core.results import Result

GRID = (Fraction(1, 4), Fraction(1, 3), Fraction(1, 2), Fraction(1), Fraction(2), Fraction(3), Fraction(4))
QUICK_GRID = (Fraction(1, 2), Fraction(1), Fraction(2), Fraction(4))

# (model, cited as integrable?, reference key, the sentence of sec. 1)
CLAIMS = (
    ("kirchhoff", True, "Kehrbaum97b", "the isotropic Kirchhoff rod is completely integrable"),
    ("anisotropic", False, "Mielke88", "anisotropy destroys integrability"),
    ("curved", False, "Champneys97a, Leung04", "intrinsic curvature destroys integrability"),
    ("heavy", False, "Gottlieb99", "gravity destroys integrability"),
    ("extensible", True, "Stump00", "extensibility and shearability do not destroy integrability"),
    ("magnetic", True, "Sinden08", "a uniform magnetic field on an inextensible rod does not destroy integrability"),
    ("magnetic-extensible", False, "this paper", "extensibility together with a magnetic field destroys integrability"),
)
PAPER_SPLITTING_KEYS = ("melnikov_vanishes", "splitting_leading_term", "splitting_integrand_ball",
                        "generic_leading_term")


def _gradient_rank(mc, polys: dict, names: list, seed: int) -> int:
    """Rank over Q of the gradients of `names` at a seeded random rational point (exact, python-flint)."""
    from flint import fmpq, fmpq_mat

    from .exact import _diff

    rng = random.Random(seed)
    x = [Fraction(rng.randint(1, 97), rng.randint(1, 97)) for _ in range(mc.dim)]

    def ev(q):
        tot = Fraction(0)
        for mono, c in q.items():
            t = c
            for xi, a in zip(x, mono):
                t *= xi**a
            tot += t
        return tot

    M = fmpq_mat(len(names), mc.dim)
    for i, k in enumerate(names):
        for j in range(mc.dim):
            v = ev(_diff(polys[k], j))
            M[i, j] = fmpq(v.numerator, v.denominator)
    return M.rank()


def splitting_evidence(model: str, *, quick: bool, seed: int):
    """(evidence items, ModelSplitting) of the homoclinic splitting for a model of SPLITTING_MODELS
    (magrod.separatrix.model_splitting; quick: eps = 0.02, 0.01 and 24 phases, else 0.04, 0.02, 0.01, 32 phases
    and the long-double check)."""
    from ..separatrix.model_splitting import model_splitting

    eps = (0.02, 0.01) if quick else (0.04, 0.02, 0.01)
    r = model_splitting(model, eps=eps, n_phase=24 if quick else 32, precision_check=not quick, seed=seed)
    k = r.harmonic
    trig = f"sin({'2 ' if k == 2 else ''}phi0)"
    rows = "; ".join(f"eps = {x['eps']:g}: c/eps = {x['A'] / x['eps']:.6g} (A-B {x['A_minus_B']:.0e}, vs Mel'nikov "
                     f"{x['relative_difference']:.1e})" for x in r.rows)
    ev = [{"label": "derived (orbit and integrand proved symbolically; the Fourier integrals checked by quadrature "
                    "to {:.0e})".format(r.quadrature_error),
           "what": "Mel'nikov function of the straight twisted rod's homoclinic orbit (M = T = 1)",
           "detail": f"Delta(phi0) = eps ({r.melnikov_unit:.6g}) {trig} + O(eps^2), {r.perturbation}: simple zeros, "
                     "so the manifolds of the saddle-focus intersect transversally for small eps (conditional: eps "
                     "small enough; Devaney's theorem then gives horseshoes)"},
          {"label": r.status_label,
           "what": "splitting of the stable and unstable manifolds on the midpoint section (m3 jump)",
           "detail": f"{rows}; remainder order {r.scaling_order:.2f} (expected "
                     f"{1 if k == 2 else 2}); delta/10 changes c by {r.delta_change:.0e}, an eigenvector phase by "
                     f"{r.phase_change:.0e}"
                     + ("" if math.isnan(r.precision_change) else f", long double by {r.precision_change:.0e}")
                     + f"; integrable member (eps = 0): |Delta| <= {r.control:.0e}"
                     + ("" if r.success else f"; FAILED: {r.message}")}]
    return ev, r


def line(model: str, integrable_claim: bool, reference: str, sentence: str, *, degree: int, t_max: float,
         seed: int, splitting: bool = False, quick: bool = False) -> dict:
    """The evidence for one line of sec. 1 (module docstring); `splitting`: add the homoclinic splitting for the
    models that have the straight rod's homoclinic orbit (magrod.separatrix.model_splitting)."""
    if model == "heavy":
        import json
        from importlib import resources

        heavy = json.loads(resources.files("magrod.generated").joinpath("models/heavy.json").read_text())["results"][0]
        return {"model": "heavy", "reference": reference, "claim": sentence, "claim_integrable": integrable_claim,
                "verdict": "not tested: outside the registry", "agreement": "not tested",
                "evidence": [{"label": "proved (symbolic)", "what": heavy["title"],
                              "detail": heavy["details"]["reason"]}],
                "note": "The heavy rod's field changes the Casimir e3.n of every registered bracket, so it is not a "
                        "Lie-Poisson system of the registry (derive/models/heavy.py); magrod has no evidence for or "
                        "against the cited claim."}
    from ..chaos.model_chaos import model_lyapunov
    from ..core.models import resolve
    from .model_search import model_search, parameter_values, polynomial

    mc = resolve(model)
    rep = {r["key"]: r for r in mc.report["results"]}
    table = rep["involution"]["details"]["table"]
    n, k = mc.dim, len(mc.names.CASIMIRS)
    need = (n - k) // 2
    s = model_search(mc, degree, seed=seed)
    kept = s.candidates_found
    commuting = ["H"] + [c for c in kept if all(table.get(f"{{{a},{b}}}", table.get(f"{{{b},{a}}}")) == "0"
                                                 for a, b in itertools.combinations(["H"] + kept, 2) if c in (a, b))]
    vals = parameter_values(mc, None, seed)
    polys = {q: polynomial(mc, q, vals) for q in mc.fi.POLYNOMIALS}
    rank = _gradient_rank(mc, polys, list(mc.names.CASIMIRS) + commuting, seed)
    liouville = len(commuting) >= need and rank == k + len(commuting)
    ev = [{"label": "proved (symbolic)", "what": f"Casimirs found by the ansatz ({k} on the {n}-D state: leaves of "
                                                 f"dimension {n - k}, {need} integrals in involution needed)",
           "detail": "; ".join(f"{a} = {b}" for a, b in rep["casimirs"]["details"]["basis_found"].items())}]
    for c in rep["candidates"]["details"]["first_integral"]:
        ev.append({"label": "proved (symbolic)", "what": f"candidate {c} ({rep['candidates']['details']['references'][c]})",
                   "detail": "{H, " + c + "} = " + table.get(f"{{H,{c}}}", "?")})
    ev.append({"label": "proved (exact modular certificate)" if s.certified else "exact search",
               "what": f"polynomial integrals of degree <= {degree}", "detail": s.message})
    ly = model_lyapunov(mc, t_max=t_max, seed=seed)
    ev.append({"label": "numerical", "what": f"Lyapunov estimate at t = {t_max:g} (bound 10 ln t / t = "
                                             f"{ly.regular_bound:.3g})",
               "detail": f"lyap = {ly.lyap:.3g}: {'chaotic' if ly.chaotic else 'regular'}; max |H - h| = "
                         f"{ly.energy_error:.1e}, max |C - C0| = {ly.casimir_error:.1e}"})
    split = None
    if splitting:
        from ..separatrix.model_splitting import SPLITTING_MODELS

        if model in SPLITTING_MODELS:
            more, split = splitting_evidence(model, quick=quick, seed=seed)
            ev += more
    note = ""
    chaotic_paper = False
    if model == "magnetic-extensible":
        import json
        from importlib import resources

        paper = {r["key"]: r for r in json.loads(resources.files("magrod.generated").joinpath("report.json")
                                                 .read_text())["results"]}
        from ..chaos.lyapunov import lyapunov

        ly4 = lyapunov("4a")  # the paper's own chart and panel, its default T = 3000 (the Fig 4 orbits are sticky)
        ev.append({"label": "numerical", "what": "the Fig 4(a) orbit of the paper's rod (fig:poincare1), paper's chart",
                   "detail": f"growth exponent {ly4.growth_exponent:.3g}, lyap {ly4.lyap:.3g} at T = {ly4.t_max:g}: "
                             f"{'chaotic' if ly4.chaotic else 'regular'} ({ly4.criterion()}); max |dH| "
                             f"{ly4.max_abs_dH:.1e}"})
        chaotic_paper = bool(ly4.chaotic)
        for key in PAPER_SPLITTING_KEYS:
            if key in paper:
                ev.append({"label": f"derived (generated/report.json: {key}; against the printed paper: "
                                    f"{paper[key]['status']})", "what": paper[key]["title"],
                           "detail": paper[key]["method"]})
        note = ("The paper's own first-order Mel'nikov integral vanishes identically (melnikov_vanishes, docs/errata.md); "
                "the non-integrability rests on the second-order splitting S (computer-verified non-zero) and "
                "the conditional statements of docs/nonintegrability.md.")
    if model == "anisotropic":
        note = ("Holds generically: special stiffness ratios are integrable (Lagrange B1 = B2, Kovalevskaya 1:2:2, and "
                "Goryachev-Chaplygin 1:4:4 on m.n = 0; the scan).")
    if model == "curved":
        note = "With k1 = 0 (pure pre-twist) m3 is again an integral: the claim needs curvature in the bending plane."
    if liouville:
        ev.append({"label": "proved (symbolic brackets; exact rank at a rational point)",
                   "what": "Liouville integrability on the symplectic leaves",
                   "detail": f"{', '.join(commuting)} in involution, gradients with the Casimirs' of rank "
                             f"{rank} = {k} + {len(commuting)}"})
        verdict = "integrable (proved)"
    else:
        chaotic = ly.chaotic or (model == "magnetic-extensible" and chaotic_paper)
        verdict = ("no polynomial integral beyond H and the Casimirs up to degree "
                   f"{degree} (certified){' and chaotic (numerical)' if chaotic else ''}"
                   + ("; split homoclinic manifolds, as Mel'nikov predicts (numerical)" if split and split.success
                      else ""))
    from .decided import landscape_evidence

    more, strongest = landscape_evidence(model)
    ev += more
    if strongest and not liouville:
        verdict = f"{strongest}; {verdict}"
    agree = "agrees" if liouville == integrable_claim else "disagrees"
    if split is not None and not split.success:
        agree = "disagrees"  # the measurement contradicts its own first-order theory: the line cannot stand
    out = {"model": model, "reference": reference, "claim": sentence, "claim_integrable": integrable_claim,
           "verdict": verdict, "agreement": agree, "evidence": ev, "note": note,
           "search": {"kernel_dims": s.kernel_dims, "algebra_dims": s.algebra_dims, "values": s.values}}
    if split is not None:
        out["splitting"] = split.to_dict()
    return out


def explain(b1, b2, c, level: str) -> str:
    """The known integrable case (Kirchhoff kinetic analogue) a ratio is, or ''."""
    if b1 == b2:
        return "Lagrange (B1 = B2: the symmetric top; m3)"
    if (b2 == c == 2 * b1) or (b1 == c == 2 * b2):
        return "Kovalevskaya (two equal stiffnesses, one of them C, twice the third)"
    if level == "C2=0" and ((b2 == c == 4 * b1) or (b1 == c == 4 * b2)):
        return "Goryachev-Chaplygin (two equal, one of them C, four times the third; on m.n = 0)"
    return ""


def anisotropic_scan(grid=GRID, degree: int = 4, seed: int = 20) -> list:
    """Every ratio class B1 : B2 : C with entries in `grid` (module docstring) on the generic level and on C2 = 0:
    the rows where an integral beyond H and the Casimirs exists (the candidate m3, or new ones found exactly)."""
    from .model_search import model_search

    classes = {}
    for b1, b2, c in itertools.product(grid, repeat=3):
        classes.setdefault((b1 / c, b2 / c), (b1, b2, c))
    rows = []
    for (r1, r2), rep in sorted(classes.items()):
        den = math.lcm(*(v.denominator for v in rep))  # the smallest integer triple of the class
        ints = [int(v * den) for v in rep]
        g = math.gcd(*ints)
        b1, b2, c = (Fraction(v // g) for v in ints)
        for level in ("generic", "C2=0"):
            r = model_search("anisotropic", degree, values={"B1": b1, "B2": b2, "C": c},
                             level={"C2": 0} if level == "C2=0" else None, seed=seed)
            beyond = ["I1 = m3 (candidate kept)"] if "I1" in r.candidates_found else []
            beyond += r.new_integrals
            if beyond:
                rows.append({"B1": str(b1), "B2": str(b2), "C": str(c), "ratio": f"{r1}:{r2}:1", "level": level,
                             "integrals": beyond, "verified": r.new_verified, "certified_otherwise": r.success,
                             "explanation": explain(b1, b2, c, level) or "UNEXPLAINED"})
    return rows, len(classes)


MAX_GRID_POINTS = 4096


def stiffness_scan(model, grid: dict, degree: int = 4, *, values=None, level=None, seed: int | None = None) -> dict:
    """The exact search (model_search) at every point of a parameter grid of any model -- a registered one or a
    model file: `grid` {parameter: [exact values]}, the other parameters from `values` or the model's defaults.
    Returns {"model", "degree", "level", "points": [{name: value}], "rows": [...]}, one row per point with an integral
    beyond H and the Casimirs (a candidate kept, or integrals found exactly, each re-checked {F, H} = 0 from J and H
    directly): its values, the integrals, their re-checks, and whether the rest is certified.  ParameterError naming
    `grid` or a parameter for a bad grid (a name the model lacks, a value outside its range or where the model is
    singular, more than MAX_GRID_POINTS points)."""
    from ..core.errors import ParameterError
    from ..core.models import resolve
    from .model_search import _frac, model_search

    mc = resolve(model)
    if not isinstance(grid, dict) or not grid:
        raise ParameterError("grid", "must name at least one parameter with its values: {name: [v1, v2, ...]}")
    axes = {}
    for k, vs in grid.items():
        if k not in mc.names.PARAMS:
            raise ParameterError("grid", f"{k!r} is not a parameter of the model {mc.name!r} "
                                         f"({', '.join(mc.names.PARAMS)})")
        if isinstance(vs, (str, bytes)) or not hasattr(vs, "__iter__"):
            raise ParameterError("grid", f"the values of {k} must be a list")
        vs = [_frac(k, v) for v in vs]
        if not vs:
            raise ParameterError("grid", f"{k} has no values")
        axes[k] = list(dict.fromkeys(vs))
    values = dict(values or {})
    both = sorted(set(values) & set(axes))
    if both:
        raise ParameterError("grid", f"{', '.join(both)} is given both as a grid axis and a fixed value")
    if math.prod(len(v) for v in axes.values()) > MAX_GRID_POINTS:
        raise ParameterError("grid", f"has more than {MAX_GRID_POINTS} points")
    points, rows = [], []
    for combo in itertools.product(*axes.values()):
        point = dict(zip(axes, combo))
        points.append({k: str(v) for k, v in point.items()})
        r = model_search(mc, degree, values={**values, **point}, level=level, seed=seed)
        beyond = [f"{k} (candidate kept)" for k in r.candidates_found] + list(r.new_integrals)
        if beyond:
            rows.append({"values": {k: str(v) for k, v in point.items()}, "integrals": beyond,
                         "verified": list(r.new_verified), "certified": r.certified})
    return {"model": mc.name, "degree": int(degree), "level": {k: str(v) for k, v in (level or {}).items()},
            "fixed": {k: str(v) for k, v in values.items()}, "points": points, "rows": rows}


@dataclass(repr=False)
class Landscape(Result):
    """The lines of sec. 1 (claim, reference, verdict, labelled evidence, agreement) and the anisotropic scan."""

    success: bool
    message: str
    degree: int  # the degree D of the exact first-integral searches
    t_max: float  # length of the Lyapunov runs behind the "chaotic orbit" evidence
    #: one dict per line of sec. 1: model, reference, claim, claim_integrable, verdict, agreement ("agrees",
    #: "disagrees", "not tested", ...), evidence (list of {label, what, detail}), note
    lines: list
    #: the anisotropic scan: one dict per special (ratio, level) pair: B1, B2, C, ratio, level, integrals (found
    #: beyond H and the Casimirs), verified (their exact re-checks), certified_otherwise, explanation
    scan: list
    scan_classes: int  # the number of B1 : B2 : C ratio classes scanned (up to a common factor)
    scan_grid: list  # the grid of stiffness entries the ratios were drawn from, as strings
    wall_time_s: float  # seconds taken
    notes: list = field(default_factory=list)  # remarks added by the caller (none by default)

    _repr_fields = ("degree", "scan_classes", "wall_time_s")


def landscape(degree: int = 4, *, quick: bool = False, scan: bool = True, t_max: float | None = None,
              seed: int = 20, splitting: bool = True) -> Landscape:
    """Re-derive every line of the paper's sec. 1 from the rod models, and scan the anisotropic family.

    Parameters
    ----------
    degree : int
        Degree D of the exact searches (1 ... 12; the anisotropic scan's: 4).
    quick : bool, keyword-only
        A smaller grid (QUICK_GRID) and t_max = 500 (seconds instead of a minute).
    scan : bool, keyword-only
        Run the anisotropic B1 : B2 : C scan.
    t_max : float, keyword-only
        Length of the Lyapunov runs (default 2000, quick 500).
    seed : int, keyword-only
        Seed of the random rational parameters and of the orbits' starts.
    splitting : bool, keyword-only
        For the anisotropic and curved rods, measure the splitting of the straight twisted rod's homoclinic
        manifold against its Mel'nikov function (magrod.separatrix.model_splitting; ~1 s).

    Returns
    -------
    Landscape
        success False if a line's evidence disagrees with its citation or a scan integral is unexplained or fails
        its re-check (the message says which).

    Raises
    ------
    ParameterError
        Naming degree or t_max.

    Examples
    --------
    >>> land = landscape(2, quick=True, scan=False, t_max=200.0)
    >>> [ln["agreement"] for ln in land.lines]
    ['agrees', 'agrees', 'agrees', 'not tested', 'agrees', 'agrees', 'agrees']

    Notes
    -----
    Evidence labels and method: module docstring.
    """
    from ..core.errors import ParameterError
    from .exact import _degree

    t0 = time.perf_counter()
    D = _degree(degree)
    t_max = (500.0 if quick else 2000.0) if t_max is None else t_max
    if isinstance(t_max, bool) or not isinstance(t_max, (int, float)) or not 10 <= t_max <= 1e6:
        raise ParameterError("t_max", f"must be a number in [10, 1e6], got {t_max!r}")
    lines = [line(*c, degree=D, t_max=float(t_max), seed=seed, splitting=splitting, quick=quick) for c in CLAIMS]
    grid = QUICK_GRID if quick else GRID
    rows, ncls = anisotropic_scan(grid, D, seed) if scan else ([], 0)
    bad = [ln["model"] for ln in lines if ln["agreement"] == "disagrees"]
    unexplained = [r["ratio"] + " " + r["level"] for r in rows if r["explanation"] == "UNEXPLAINED" or
                   not all(r["verified"])]
    ok = not bad and not unexplained
    msg = ("every tested line agrees with its citation" + (f"; scan: {len(rows)} special (ratio, level) pairs among "
                                                          f"{ncls} ratio classes, all explained" if scan else "")
           if ok else f"disagreements: {bad}; unexplained or unverified scan rows: {unexplained}")
    return Landscape(ok, msg, D, float(t_max), lines, rows, ncls, [str(g) for g in grid], time.perf_counter() - t0)


def format_text(d: dict) -> str:
    """The landscape (`landscape()`) as the text `magrod landscape` prints: one block per line of sec. 1, its
    agreement, verdict and evidence."""
    out = [f"the landscape of sec. 1, re-derived (exact search to degree {d['degree']}; Lyapunov t = {d['t_max']:g})", ""]
    for ln in d["lines"]:
        out.append(f"[{ln['agreement']}] {ln['model']}: \"{ln['claim']}\" [{ln['reference']}]")
        out.append(f"    magrod: {ln['verdict']}")
        for e in ln["evidence"]:
            out.append(f"    - {e['label']}: {e['what']}: {e['detail']}")
        if ln.get("note"):
            out.append(f"    note: {ln['note']}")
        out.append("")
    if d["scan"] or d["scan_classes"]:
        out.append(f"anisotropic scan: B1:B2:C with entries in {{{', '.join(d['scan_grid'])}}} ({d['scan_classes']} "
                   f"ratio classes), degree {d['degree']}, generic levels and m.n = 0")
        for r in d["scan"]:
            out.append(f"  B1:B2:C = {r['B1']}:{r['B2']}:{r['C']} ({r['level']}): {r['explanation']}")
            for f, ok in zip(r["integrals"], [True] * (len(r["integrals"]) - len(r["verified"])) + r["verified"]):
                out.append(f"      {f}" + ("" if ok else "   [RE-CHECK FAILED]"))
        out.append("  every other ratio and level: no polynomial integral beyond H, C1, C2 (certified)")
    out += ["", d["message"]]
    return "\n".join(out)
