"""The symbolic pipeline for any registered or user model: from the model's state, W or H and J
(derive/models/spec.py) to its derivation report and its generated modules under generated/models/<name>/.

Derived, never typed in:
  * H from W by the Legendre transform (spec.legendre), or H as given;
  * the equations x' = J grad H;
  * the Jacobi identity of J (every index triple);
  * the Casimirs, found by solving J grad C = 0 over all polynomials of degree <= 2 (a linear system over the
    parameters' rational functions; its null space is the answer);
  * the S^1 symmetry (rotation of the body frame about d3) tested on H: the Euler-angle chart of the paper needs it;
  * the involution table of H, the Casimirs and the model's literature candidates (symbolic brackets, factored).
Generated per model: names.py (names only), body.py (heyoka expressions), first_integrals.py (exact rational data
for magrod/integrability/first_integrals.py), report.json / report.md."""
from __future__ import annotations

import itertools
import json

import sympy as sp

from ..codegen import HeyokaPrinter, function_source, module_source
from ..codegen import FractionPrinter
from ..results import DISAGREES, HOLDS, Result, fmt
from .spec import Model, jacobi_failures

CASIMIR_DEGREE = 2


def gradient(f, X):
    return sp.Matrix([sp.diff(f, x) for x in X])


def bracket(model: Model, f, g):
    """{f, g} = grad f . J grad g."""
    return sp.expand((gradient(f, model.state).T * model.J * gradient(g, model.state))[0, 0])


def equations(model: Model):
    return sp.expand(model.J * gradient(model.H, model.state))


def casimirs(model: Model, degree: int = CASIMIR_DEGREE) -> list:
    """A basis of the non-constant polynomial Casimirs of degree <= `degree` (J grad C = 0), found from the null
    space of the linear system for a general polynomial ansatz; each normalised to a leading coefficient 1 on its
    first monomial (in SymPy's sort order), constants removed."""
    X = model.state
    monos = sorted((mm for mm in sp.itermonomials(X, degree) if mm != 1), key=sp.default_sort_key)
    cs = sp.symbols(f"c0:{len(monos)}")
    ans = sum(c * mm for c, mm in zip(cs, monos))
    eqs = []
    for comp in model.J * gradient(ans, X):
        eqs.extend(sp.Poly(sp.expand(comp), *X).coeffs())
    A, _ = sp.linear_eq_to_matrix(eqs, cs)
    out = []
    for vec in A.rref(simplify=True)[0].nullspace(simplify=True) if A.rows else [sp.eye(len(cs))[:, i] for i in range(len(cs))]:
        out.append(sp.expand(sum(c * mm for c, mm in zip(primitive(vec, model.params), monos))))
    return sorted(out, key=sp.default_sort_key)


def primitive(vec, params) -> list:
    """The coefficients `vec` (rational functions of the parameters) scaled to polynomials in the parameters with
    no common factor, the first non-zero one with a positive leading coefficient: kappa m^2 + n^2, never
    m^2 + n^2/kappa, so a Casimir stays defined (and non-zero) at every parameter value where the bracket is."""
    fr = [sp.fraction(sp.factor(sp.together(v))) for v in vec]
    den = sp.Integer(1)
    for _, d in fr:
        den = sp.lcm(den, d)
    nums = [sp.expand(sp.cancel(n * den / d)) for n, d in fr]
    g = sp.Integer(0)
    for n in nums:
        g = sp.gcd(g, n)
    nums = [sp.expand(sp.cancel(n / g)) for n in nums]
    lead = next(n for n in nums if n != 0)
    sign = sp.Poly(lead, *params).LC() if params and lead.free_symbols else lead
    return [-n if sign < 0 else n for n in nums]


def body_vectors(model: Model) -> list:
    """The state read as body vectors: the symbols named <stem>1, <stem>2, <stem>3 for a common stem (m1 m2 m3,
    e31 e32 e33), wherever they sit in STATE; if the names do not form such triples, consecutive triples of the
    state."""
    X = model.state
    by = {str(x): x for x in X}
    vecs, used = [], set()
    for x in X:
        name = str(x)
        if name in used or not name.endswith("1"):
            continue
        stem = name[:-1]
        trip = [by.get(f"{stem}{i}") for i in (1, 2, 3)]
        if stem and all(trip):
            vecs.append(trip)
            used.update(str(t) for t in trip)
    if len(used) == len(X):
        return vecs
    if len(X) % 3:
        return []
    return [X[k:k + 3] for k in range(0, len(X), 3)]


def s1_symmetric(model: Model) -> bool:
    """True if H is invariant under a rotation of the body frame about d3: every body vector a = (a1, a2, a3) of
    the state (body_vectors: by name, whatever the order of STATE) moves with the generator a -> (-a2, a1, 0)."""
    vecs = body_vectors(model)
    if not vecs:
        return False
    delta = {}
    for a1, a2, a3 in vecs:
        delta.update({a1: -a2, a2: a1, a3: 0})
    return sp.expand(sum(sp.diff(model.H, x) * delta[x] for x in model.state)) == 0


def named_casimirs(model: Model) -> dict:
    """{"C1": ..}: the Casimirs found (casimirs()), or the model's own CASIMIRS where it gives them -- each checked
    (J grad C = 0 expanded) and together spanning exactly the Casimirs found (ModelError otherwise)."""
    found = casimirs(model)
    if not model.casimirs:
        return {f"C{i}": c for i, c in enumerate(found, 1)}
    from .spec import ModelError

    for k, c in model.casimirs.items():
        bad = [r for r in sp.expand(model.J * gradient(c, model.state)) if r != 0]
        if bad:
            raise ModelError("casimirs", f"{k} = {c} is not a Casimir: J grad {k} has the entry {bad[0]}")
    given = list(model.casimirs.values())
    r = _span_rank(found, model.state)
    if not (_span_rank(given, model.state) == r == _span_rank(found + given, model.state) == len(given)):
        raise ModelError("casimirs", f"CASIMIRS do not form a basis of the {r} Casimirs of degree <= "
                                     f"{CASIMIR_DEGREE} found: {'; '.join(str(c) for c in found)}")
    return dict(model.casimirs)


def integrals(model: Model) -> dict:
    """{name: polynomial}: H, the Casimirs C1.. (found, or the model's own where it names them), the candidates."""
    out = {"H": model.H}
    out.update(named_casimirs(model))
    for k, (e, _) in model.candidates.items():
        out[k] = sp.expand(sp.sympify(e, strict=True))  # checked SymPy (spec.sym)
    return out


def involution_table(model: Model, fs: dict | None = None) -> dict:
    fs = fs or integrals(model)
    return {f"{{{a},{b}}}": (lambda r: "0" if r == 0 else fmt(r))(sp.factor(bracket(model, fa, fb)))
            for (a, fa), (b, fb) in itertools.combinations(fs.items(), 2)}


def _span_rank(polys, X):
    if not polys:
        return 0
    ps = [sp.Poly(sp.expand(p), *X) for p in polys]
    monos = sorted({mn for p in ps for mn in p.monoms()})
    return sp.Matrix([[p.coeff_monomial(mn) for mn in monos] for p in ps]).rank(simplify=True)


def integrals_by_ansatz(model: Model, known: dict, degree: int = 2) -> dict:
    """Every polynomial F of degree <= `degree` with {F, H} = 0 (identically in the parameters): the null space of
    the linear system for a general ansatz; compared with the algebra generated by `known` (products of degree
    <= `degree`).  Returns the dimensions and a basis of integrals beyond the algebra (found, never typed in)."""
    X = model.state
    monos = sorted(sp.itermonomials(X, degree), key=sp.default_sort_key)
    cs = sp.symbols(f"c0:{len(monos)}")
    ans = sum(c * mm for c, mm in zip(cs, monos))
    eqs = sp.Poly(bracket(model, ans, model.H), *X).coeffs()
    A, _ = sp.linear_eq_to_matrix(eqs, cs)
    ker = [sp.expand(sum(v * mm for v, mm in zip(vec, monos))) for vec in A.nullspace(simplify=True)]
    names = list(known)
    degs = {k: sp.Poly(known[k], *X).total_degree() for k in names}
    alg = [sp.Integer(1)]
    for r in range(1, degree + 1):
        for combo in itertools.combinations_with_replacement(names, r):
            if sum(degs[k] for k in combo) <= degree:
                alg.append(sp.expand(sp.Mul(*[known[k] for k in combo])))
    ra = _span_rank(alg, X)
    extra, span = [], list(alg)
    for f in ker:
        if _span_rank(span + [f], X) > _span_rank(span, X):
            span.append(f)
            extra.append(f)
    return {"degree": degree, "dim_kernel": len(ker), "dim_known_algebra": ra, "extra": extra, "span": span}


def derive_results(model: Model) -> list:
    X = model.state
    fs = integrals(model)
    cas = {k: v for k, v in fs.items() if k.startswith("C") and k[1:].isdigit()}
    res = []
    res.append(Result("hamiltonian", "hamiltonian", "H = Legendre transform of W" if model.W is not None else "H as given",
                      HOLDS, "symbolic: x = dW/ds solved for the free strains, fixed strains substituted" if
                      model.W is not None else "given", {"H": fmt(model.H)}))
    eom = equations(model)
    res.append(Result("equations", "equations", "x' = J grad H", HOLDS, "symbolic: J grad H expanded",
                      {str(x): fmt(e) for x, e in zip(X, eom)}))
    bad = jacobi_failures(model.J, X)
    n3 = len(list(itertools.combinations(range(len(X)), 3)))
    res.append(Result("jacobi", "jacobi", f"Jacobi identity of J (all {n3} index triples)",
                      HOLDS if not bad else DISAGREES, "symbolic: every cyclic sum expands to 0",
                      {"failing_triples": [str(b[0]) for b in bad]}))
    # every Casimir commutes with every coordinate function: J grad C = 0 exactly
    resid = {k: [fmt(r) for r in sp.expand(model.J * gradient(c, X)) if r != 0] for k, c in cas.items()}
    ok = all(not v for v in resid.values())
    res.append(Result("casimirs", "casimirs",
                      f"Casimirs found by solving J grad C = 0 over all polynomials of degree <= {CASIMIR_DEGREE}",
                      HOLDS if ok else DISAGREES, "symbolic: null space of the ansatz system; {C, x_i} = 0 re-checked "
                      "for every coordinate", {"basis_found": {k: fmt(v) for k, v in cas.items()},
                                                "nonzero {C, x_i}": resid}))
    sym = s1_symmetric(model)
    res.append(Result("s1_symmetry", "s1_symmetry", "S^1 symmetry: H invariant under rotation of the body frame about d3",
                      HOLDS if sym else "absent", "symbolic: derivative of H along the generator a -> d3 x a expanded",
                      {"symmetric": sym, "euler_chart": "applicable" if sym else
                       "not applicable: H is not invariant under rotations about d3"}))
    table = involution_table(model, fs)
    res.append(Result("involution", "involution", "Brackets among H, the Casimirs found and the candidate integrals",
                      HOLDS, "symbolic: each bracket grad f . J grad g expanded and factored", {"table": table}))
    cands = {k: table.get(f"{{H,{k}}}") == "0" for k in model.candidates}
    res.append(Result("candidates", "candidates", "Literature candidate integrals: is {H, I} = 0?", HOLDS,
                      "symbolic: from the involution table",
                      {"first_integral": cands, "references": {k: r for k, (_, r) in model.candidates.items()}}))
    # the known algebra: H, the Casimirs and every coordinate that is an integral (m3 of a rod symmetric about d3),
    # whatever the candidates are called
    coords = {str(x): x for x in X if bracket(model, x, model.H) == 0}
    found = integrals_by_ansatz(model, {**cas, "H": model.H, **coords})
    inspan = {k: _span_rank(found["span"] + [fs[k]], X) == _span_rank(found["span"], X) for k in model.candidates}
    beyond = {k: _span_rank(found["span"][:found["dim_known_algebra"]] + [fs[k]], X) > found["dim_known_algebra"]
              for k in model.candidates}
    res.append(Result("integrals_found", "integrals_found",
                      "Polynomial integrals of degree <= 2 found by an ansatz ({F, H} = 0 identically in the "
                      "parameters), against the algebra of H, the Casimirs and the coordinates that are integrals"
                      + (f" ({', '.join(coords)})" if coords else ""),
                      HOLDS, "symbolic: null space of the ansatz system; spans compared by rank",
                      {"dim_kernel": found["dim_kernel"], "dim_known_algebra": found["dim_known_algebra"],
                       "coordinate_integrals": list(coords),
                       "beyond_the_algebra": [fmt(e) for e in found["extra"]],
                       "candidate in the span found": inspan,
                       "candidate beyond H, Casimirs, coordinate integrals": beyond}))
    return res


# --------------------------------------------------------------------------------------------------------------
# code generation
# --------------------------------------------------------------------------------------------------------------
def _names(model):
    return {s: str(s) for s in model.state + model.params}


def _rangestr(b):
    b = sp.sympify(b, strict=True)
    return "inf" if b == sp.oo else "-inf" if b == -sp.oo else float(b)


def names_module(model: Model, fs: dict) -> str:
    return module_source(f"Names of the model {model.name!r} ({model.title}): state, parameters with meanings, "
                         "ranges and defaults, the Casimirs found, the candidates.", "models/pipeline.py", [],
                         names_constants(model, fs), lib=None)


def names_constants(model: Model, fs: dict) -> dict:
    """The constants of a model's names module (core.models.ModelCode.names)."""
    cas = tuple(k for k in fs if k.startswith("C") and k[1:].isdigit())
    return {"NAME": model.name, "TITLE": model.title, "SOURCE": model.source,
              "STATE": tuple(str(x) for x in model.state), "PARAMS": tuple(str(p) for p in model.params),
              "MEANINGS": tuple(v[0] for v in model.parameters.values()),
              "RANGES": tuple((_rangestr(v[1][0]), _rangestr(v[1][1])) for v in model.parameters.values()),
              "DEFAULTS": tuple(float(sp.sympify(v[2], strict=True)) for v in model.parameters.values()),
              "CASIMIRS": cas, "CANDIDATES": tuple(model.candidates), "S1_SYMMETRIC": s1_symmetric(model),
              "REFERENCE": tuple(model.reference[x] for x in model.state)}


def body_parts(model: Model, fs: dict) -> list:
    """The functions of a model's body module that the paper's own body.py (derive/build.py) does not write:
    candidates, constraints, constraint_gradients."""
    X = model.state
    pr = HeyokaPrinter(_names(model))
    args = [str(x) for x in X] + [str(p) for p in model.params]
    cas = [v for k, v in fs.items() if k.startswith("C") and k[1:].isdigit()]
    cons = [model.H] + cas
    grads = [sp.diff(c, x) for c in cons for x in X]
    cands = [fs[k] for k in model.candidates]
    return [
        function_source("candidates", args, cands or [sp.Integer(0)], pr, "The candidate integrals, CANDIDATES order."),
        function_source("constraints", args, cons, pr, "(H, C1, ...): the level of a section."),
        function_source("constraint_gradients", args, grads, pr,
                        "Gradients of (H, C1, ...) w.r.t. the state, row by row (flattened)."),
    ]


def body_module(model: Model, fs: dict) -> str:
    X = model.state
    pr = HeyokaPrinter(_names(model))
    args = [str(x) for x in X] + [str(p) for p in model.params]
    cas = [v for k, v in fs.items() if k.startswith("C") and k[1:].isdigit()]
    extra = body_parts(model, fs)
    parts = [
        function_source("hamiltonian", args, model.H, pr, "H(x)."),
        function_source("rhs", args, list(equations(model)), pr, "x' = J(x) grad H."),
        function_source("casimirs", args, cas or [sp.Integer(0)], pr, "The Casimirs found, in CASIMIRS order."),
        extra[0],
        function_source("section", args, model.section, pr, "The Poincare section function (crossed upwards)."),
        extra[1],
        extra[2],
        'def pars():\n    """hy.par[i] = PARAMS[i]."""\n    return [hy.par[i] for i in range(len(PARAMS))]\n',
        ('def system():\n    """[(variable, rhs)] for hy.taylor_adaptive."""\n    xs = hy.make_vars(*STATE)\n'
         '    return list(zip(xs, rhs(*xs, *pars())))\n'),
    ]
    return module_source(f"Body-frame system of the model {model.name!r}: x' = J grad H in {tuple(args[:len(X)])}.",
                         "models/pipeline.py", parts, {"STATE": tuple(args[:len(X)]),
                                                       "PARAMS": tuple(str(p) for p in model.params)})


def _poly(expr, X):
    P = sp.Poly(sp.expand(expr), *X)
    terms = sorted(P.terms(), key=lambda mc: mc[0])
    return [tuple(int(k) for k in mono) for mono, _ in terms], [sp.factor(c) for _, c in terms]


def _exact(value) -> str:
    """A default as an exact rational 'p/q' (a float default by its decimal digits: 0.1 -> '1/10')."""
    from fractions import Fraction

    v = sp.sympify(value, strict=True)
    if v.is_Rational:
        return str(Fraction(int(v.p), int(v.q)))
    if v.is_Float:
        return str(Fraction(str(v)).limit_denominator(10**15))
    return str(Fraction(float(v)).limit_denominator(10**12))


def first_integrals_module(model: Model, fs: dict) -> str:
    X = model.state
    pr = FractionPrinter({p: str(p) for p in model.params})
    pnames = [str(p) for p in model.params]
    consts = {"PARAMETERS": tuple(pnames), "DEFAULTS": tuple(_exact(v[2]) for v in model.parameters.values()),
              "NVAR": len(X), "POLYNOMIALS": tuple(fs)}
    parts = []
    for k, e in fs.items():
        monos, coefs = _poly(e, X)
        consts[f"{k}_MONOMIALS"] = tuple(monos)
        parts.append(function_source(k, pnames, list(coefs), pr, f"Coefficients of {k} in the order of {k}_MONOMIALS."))
    terms = []
    for i in range(len(X)):
        for j in range(len(X)):
            e = sp.expand(model.J[i, j])
            if e != 0:
                for mono, c in sorted(sp.Poly(e, *X).terms()):
                    terms.append(((i, j, tuple(int(a) for a in mono)), c))
    consts["STRUCTURE_TERMS"] = tuple(t for t, _ in terms)
    parts.append(function_source("structure", pnames, [c for _, c in terms] or [sp.Integer(0)], pr,
                                 "Coefficients c with J_ij = sum c x^mono, in the order of STRUCTURE_TERMS (i, j, mono)."))
    return module_source(f"Exact data of the first-integral search for the model {model.name!r}: H, J, the Casimirs "
                         "and the candidates as monomials with rational coefficients.", "models/pipeline.py", parts,
                         consts, lib=None, imports=("from fractions import Fraction as _Q",))


def report_markdown(model: Model, results) -> str:
    lines = [f"# derivation report: model `{model.name}`", "", f"{model.title}. Source: {model.source}.", "",
             "Written by `python -m derive` (derive/models/pipeline.py) -- do not edit.", "",
             "| key | result | status | how shown |", "|---|---|---|---|"]
    lines += [f"| {r.key} | {r.title} | **{r.status}** | {r.method} |" for r in results]
    lines.append("")
    for r in results:
        lines += [f"## {r.key}", "", "```json", json.dumps(r.details, indent=2, sort_keys=True, default=str), "```", ""]
    return "\n".join(lines)


CACHED_HEADER = ("Compiled from a model file into magrod's model cache; recompiled whenever the evaluated model\n"
                 "changes (`magrod check --model FILE --no-cache` compiles afresh).")


def model_files(model: Model, cached: bool = False, fs: dict | None = None, results: list | None = None) -> dict:
    """{filename: text} of generated/models/<ident>/; `cached`: of a user's model file's cache entry (its header
    says so, not how to regenerate the registry).  `fs`, `results`: integrals() and derive_results() if known."""
    fs = integrals(model) if fs is None else fs
    results = derive_results(model) if results is None else results
    params = [{"name": str(p), "meaning": v[0], "range": [str(v[1][0]), str(v[1][1])], "default": str(v[2])}
              for p, v in model.parameters.items()]
    rep = {"model": model.name, "title": model.title, "source": model.source, "state": [str(x) for x in model.state],
           "parameters": params, "results": [r.as_dict() for r in results]}
    files = {"names.py": names_module(model, fs), "body.py": body_module(model, fs),
             "first_integrals.py": first_integrals_module(model, fs),
             "report.json": json.dumps(rep, indent=1, sort_keys=True, default=str) + "\n",
             "report.md": report_markdown(model, results)}
    files["__init__.py"] = (f'"""Machine-written by derive/models/pipeline.py (python -m derive) -- DO NOT EDIT BY HAND.\n\n'
                            f'Model {model.name!r}: {model.title}."""\n')
    if cached:
        from ..codegen import HEADER

        regen = HEADER.split("\n")[3]
        files = {k: v.replace(regen, CACHED_HEADER).replace("(python -m derive) -- DO NOT EDIT BY HAND.",
                                                            "-- DO NOT EDIT BY HAND.")
                 for k, v in files.items()}
        files["report.md"] = files["report.md"].replace("Written by `python -m derive` (derive/models/pipeline.py) "
                                                        "-- do not edit.", "Compiled from the model file by "
                                                        "derive/models/pipeline.py -- do not edit.")
    return files
