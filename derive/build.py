"""Run every derivation and write generated/: heyoka-building modules and the derivation report."""
from __future__ import annotations

import json
import random
import time
from pathlib import Path

import mpmath
import sympy as sp

from . import numeric_scale as ns
from . import homoclinic, melnikov, poisson, reduction, splitting, symmetry
from . import floquet  # the saddle-type sets for mu != 2 lambdabar
from . import validated  # the validated integrator's ball fields
from . import audit, first_integrals, generic_splitting  # the rigorous and exact checks
from .codegen import HeyokaPrinter, function_source, module_source
from .model import X, phi, psi, theta
from .paper import delta, gamma, lambar, m, mu, pps, pth
from .results import CONDITIONAL, DISAGREES, Result

PAR_NAMES = {m: "m", mu: "mu", gamma: "gamma", delta: "delta", lambar: "lam"}
PAR_ARGS = ["m", "mu", "gamma", "delta", "lam"]
RED_NAMES = {theta: "theta", psi: "psi", pth: "ptheta", pps: "ppsi", **PAR_NAMES}
RED_ARGS = ["theta", "psi", "ptheta", "ppsi"]
BODY_ARGS = ["m1", "m2", "m3", "n1", "n2", "n3", "e31", "e32", "e33"]
BODY_NAMES = {**dict(zip(X, BODY_ARGS)), **PAR_NAMES}


CHART_ARGS = ["theta", "psi", "phi", "ptheta", "ppsi"]
NAMES_IMPORT = ("from .names import PARAMS",)


def _pars_src():
    return ('def pars():\n    """The runtime parameters PARAMS = (m, mu, gamma, delta, lambdabar) as heyoka parameters '
            'hy.par[0..4]."""\n    return [hy.par[i] for i in range(len(PARAMS))]\n')


def names_module(model_consts: dict | None = None):
    """generated/names.py: the model's state and parameter names, importable without heyoka or SymPy; with
    `model_consts` (paper_model().names) also what the registry's model needs (core.models.ModelCode.names)."""
    ev = list(ns.events_body())
    consts = {"BODY_STATE": tuple(BODY_ARGS), "REDUCED_STATE": tuple(RED_ARGS), "CHART": tuple(CHART_ARGS),
              "PARAMS": tuple(PAR_ARGS), "BODY_EVENTS": tuple(ev),
              "CLOSED_FORM_REGULAR": homoclinic.CLOSED_FORM_REGULAR}
    for k, v in (model_consts or {}).items():
        if k in consts and consts[k] != v:
            raise AssertionError(f"the registry's paper model and the paper's tree disagree on {k}: {v} != {consts[k]}")
        consts.setdefault(k, v)
    return module_source("Names and order of the model's state variables, chart coordinates and runtime parameters "
                         "(hy.par[i] is PARAMS[i]).  The single source of these lists for magrod; also the names of "
                         "the registry's default model 'magnetic-extensible', which is this tree.", "build.py", [],
                         consts, lib=None)


def paper_model() -> dict:
    """The paper's rod as the registry's default model (derive/models/magnetic_extensible.py: the same H, J and
    Casimirs at the same numeric scale), generated once with the paper's tree: {"names": constants for names.py,
    "body": functions for body.py, "integrals.py", "model_report.json", "model_report.md": texts}."""
    from .models import DEFAULT, get, pipeline

    model = get(DEFAULT)
    if [str(p) for p in model.params] != PAR_ARGS or [str(x) for x in model.state] != BODY_ARGS:
        raise AssertionError("derive/models/magnetic_extensible.py must use the paper's state and parameters")
    fs = pipeline.integrals(model)
    files = pipeline.model_files(model, fs=fs)
    return {"names": pipeline.names_constants(model, fs), "body": pipeline.body_parts(model, fs),
            "integrals.py": files["first_integrals.py"], "model_report.json": files["report.json"],
            "model_report.md": files["report.md"]}


def scalars_module():
    """generated/scalars.py: closed-form scalars as plain-float Python (no heyoka, no SymPy), for validation
    and for constants the runtime needs before any integrator exists."""
    pm = HeyokaPrinter(PAR_NAMES, lib="math")
    h, _, _, _ = homoclinic.roots_and_k()
    Vpp0 = sp.simplify(sp.limit(sp.diff(homoclinic.potential(), theta, 2), theta, 0))
    _, defect, mu_sol = ns.straight_rod_analysis()
    parts = [
        function_source("homoclinic_energy", ["m", "gamma"], h, pm,
                        "Homoclinic level h = V(0) at lambdabar = 0 (eq:eq_oscillator; report entry oscillator)."),
        function_source("m_critical", ["gamma"], 2 * sp.sqrt(1 + gamma), pm,
                        "m_c = 2 sqrt(1 + gamma): theta = 0 is a saddle iff m < m_c (eq:buckling_load_2)."),
        function_source("potential_dd0", ["m", "gamma"], Vpp0, pm,
                        "V''(0) = 1/4 - (1 + gamma)/m^2 at lambdabar = 0 (report entry fixed_points); < 0 iff m < m_c."),
        function_source("saddle_rate", ["m", "gamma"], sp.sqrt(-Vpp0), pm,
                        "kappa = sqrt(-V''(0)), the saddle's eigenvalue (report entry saddle_rate); m < m_c only."),
        function_source("straight_rod_state", PAR_ARGS, ns.straight_rod_state(), pm,
                        "Body state (BODY_STATE order) of the straight rod aligned with the field: an equilibrium for "
                        "all parameters (report entry straight_rod)."),
        function_source("straight_rod_level_defect", PAR_ARGS, defect, pm,
                        "C1(straight rod) - C1 on the chart: zero iff the straight rod lies on the chart's Casimir "
                        "level (report entry straight_rod)."),
        function_source("straight_rod_mu", PAR_ARGS, mu_sol[0], pm,
                        "The mu at which the straight rod lies on the chart's level (solves straight_rod_level_defect = 0)."),
        function_source("straight_rod_mu_gradient", PAR_ARGS, [sp.diff(mu_sol[0], q) for q in PAR_NAMES],
                        pm, "Gradient of straight_rod_mu with respect to PARAMS: how mu moves to keep the straight rod "
                        "on the level when another parameter moves."),
        function_source("radicand_root_ppsi", PAR_ARGS, sp.solve(reduction.RHO2_BAR, pps)[0], pm,
                        "The pbar_psi at which the radicand mu - 2 lambdabar pbar_psi vanishes (lambdabar != 0)."),
        function_source("radicand_slope_ppsi", PAR_ARGS, sp.diff(reduction.RHO2_BAR, pps), pm,
                        "d(radicand)/d(pbar_psi): its sign says on which side of radicand_root_ppsi the chart exists."),
        function_source("straight_rod_stretch", PAR_ARGS, ns.stretch_analysis()["v3_straight_rod"], pm,
                        "Axial stretch v3 = dH/dn3 of the straight rod (n3 = C2): 1 + gamma + delta (report entry "
                        "axial_stretch)."),
        function_source("casimir_values", PAR_ARGS, ns.casimir_values(), pm,
                        "(C1, C2, C3) on the Euler-angle chart at the numeric scale."),
        function_source("hamiltonian_offset", PAR_ARGS, ns.hamiltonian_offset(), pm,
                        "H_body - Hbar on the chart (the constants dropped in eq:full_ham_nondim)."),
    ]
    return module_source("Closed-form scalars of the model in plain Python arithmetic (importable without heyoka; "
                         "np.longdouble inputs give long double results where no math function is involved).",
                         "build.py", parts, lib="math")


def _system_src(state_args, rhs_name):
    return (f'def system():\n    """[(variable, rhs)] for hy.taylor_adaptive, parameters hy.par[0..4] = {PAR_ARGS}."""\n'
            f'    xs = hy.make_vars(*STATE)\n'
            f'    return list(zip(xs, {rhs_name}(*xs, *pars())))\n')


def compact(expr, groups):
    """Regroup an expanded expression (collect on `groups`, factor each coefficient) so that the generated
    code evaluates (pbar_psi - cos theta)^2 / sin^2 theta instead of cancelling 1/sin^2 terms; the regrouped
    form is checked to equal the input."""
    c = sp.collect(sp.expand(expr), groups, func=sp.factor)
    assert sp.simplify(c - expr) == 0
    return c


def reduced_module():
    _, _, Hbar, _ = reduction.reduced_hamiltonians()
    _, I2bar = reduction.i2_canonical()
    r = sp.sqrt(mu - 2 * lambar * pps)
    Hbar = compact(Hbar, [1 / sp.sin(theta) ** 2, sp.cos(psi) ** 2, r])
    I2bar = compact(I2bar, [r])
    rhs = [sp.diff(Hbar, pth), sp.diff(Hbar, pps), -sp.diff(Hbar, theta), -sp.diff(Hbar, psi)]
    pr = HeyokaPrinter(RED_NAMES)
    args = RED_ARGS + PAR_ARGS
    parts = [
        function_source("hamiltonian", args, Hbar, pr, "Hbar(theta, psi, pbar_theta, pbar_psi), eq:full_ham_nondim (derived)."),
        function_source("rhs", args, rhs, pr, "Hamilton's equations of Hbar: (theta', psi', pbar_theta', pbar_psi')."),
        function_source("i2bar", args, I2bar, pr, "I2bar, eq:constraint_nonsim (derived)."),
        function_source("radicand", args, reduction.RHO2_BAR, pr,
                        "mu - 2 lambdabar pbar_psi: must stay > 0 (eq:alignment_condition)."),
        function_source("section", args, sp.sin(psi), pr, "sin(psi): the Poincare section of sec:numerics."),
        function_source("sin_theta", args, sp.sin(theta), pr, "sin(theta): distance from the chart's poles."),
        function_source("stretch", args, ns.stretch_chart(), pr,
                        "Axial stretch v3 = 1 + n3/K on the chart (report entry axial_stretch); v3 > 0 for a physical rod."),
        _pars_src(), _system_src(RED_ARGS, "rhs"),
    ]
    return module_source("Reduced canonical 4-D system in (theta, psi, pbar_theta, pbar_psi) (paper sec. 4).",
                         "reduction.py", parts, {"STATE": tuple(RED_ARGS)},
                         imports=NAMES_IMPORT), {"Hbar": Hbar, "rhs": rhs, "I2bar": I2bar}


def body_module(extra=()):
    """generated/body.py (and the expressions validated.py is built from); `extra`: more functions of the registry's
    model (paper_model()["body"]: candidates, constraints, constraint_gradients)."""
    H = ns.body_hamiltonian()
    rhs = ns.body_rhs()
    pr = HeyokaPrinter(BODY_NAMES)
    args = BODY_ARGS + PAR_ARGS
    red_pr = HeyokaPrinter({**RED_NAMES, phi: "phi"})
    parts = [
        function_source("hamiltonian", args, H, pr, "H(m, n) of eq:magnetic_ham at the numeric scale (numeric_scale.py)."),
        function_source("rhs", args, rhs, pr, "x' = J(x; lambda) grad H, lambda = lambdabar/m^4."),
        function_source("casimirs", args, ns.casimirs_body(), pr, "C1, C2, C3 of eq:magnetic_casimirs1-3."),
        function_source("casimir_values", PAR_ARGS, ns.casimir_values(), HeyokaPrinter(PAR_NAMES),
                        "Values of (C1, C2, C3) on the Euler-angle chart: ((mu+1)/(2 m^4), 1/m^2, 1)."),
        function_source("hamiltonian_offset", PAR_ARGS, ns.hamiltonian_offset(), HeyokaPrinter(PAR_NAMES),
                        "H_body - Hbar on the chart (the constants dropped in eq:full_ham_nondim)."),
        function_source("euler_to_body", ["theta", "psi", "phi", "ptheta", "ppsi"] + PAR_ARGS, ns.euler_to_body(),
                        red_pr, "(m, n, e3) from (theta, psi, phi, pbar_theta, pbar_psi), p_phi = 1 (eq:canonical_moment, eq:canonical_force)."),
        function_source("body_to_euler", args, [ns.body_to_euler()[k] for k in ("theta", "psi", "phi", "pbar_theta", "pbar_psi")],
                        pr, "(theta, psi, phi, pbar_theta, pbar_psi) from (m, n, e3); valid for sin(theta) > 0."),
        *[function_source(name, args, e, pr, doc) for (name, e), doc in zip(ns.events_body().items(), (
            "e31 n2 - e32 n1 = sin(theta) rho sin(psi): the section sin(psi) = 0 with its crossing direction.",
            "e31^2 + e32^2 = sin(theta)^2: distance from the chart's poles.",
            "mu - 2 lambdabar m.e3 = mu - 2 lambdabar pbar_psi: the radicand of eq:alignment_condition.",
            "e32 m1 - e31 m2 = sin(theta) pbar_theta: zero at the turning points of theta."))],
        *extra,
        _pars_src(), _system_src(BODY_ARGS, "rhs"),
    ]
    return module_source("Singularity-free 9-D body-frame system in (m, n, e3) (paper sec. 2), at the numeric scale "
                         "B = C = m3 = 1 of derive/numeric_scale.py.  Event functions in BODY_EVENTS order.",
                         "numeric_scale.py", parts, {"STATE": tuple(BODY_ARGS)},
                         imports=NAMES_IMPORT), {"H": H, "rhs": rhs}


def check_chart_numerically(n=200, seed=7) -> Result:
    """Round trip body_to_euler(euler_to_body(q, p)) = (q, p), H_body = Hbar + offset, Casimir values, at n
    seeded random points with 50-digit mpmath."""
    _, _, Hbar, _ = reduction.reduced_hamiltonians()
    fwd = ns.euler_to_body()
    inv = ns.body_to_euler()
    Hb = ns.body_hamiltonian()
    off = ns.hamiltonian_offset()
    cas = ns.casimirs_body()
    vals = ns.casimir_values()
    red = [theta, psi, phi, pth, pps, m, mu, gamma, delta, lambar]
    f_fwd = sp.lambdify(red, fwd, "mpmath")
    f_inv = sp.lambdify(X, [inv[k] for k in ("theta", "psi", "phi", "pbar_theta", "pbar_psi")], "mpmath")
    f_H = sp.lambdify(X + [m, mu, gamma, delta, lambar], Hb - off, "mpmath")
    f_Hbar = sp.lambdify(red, Hbar, "mpmath")
    f_cas = sp.lambdify(X + [m, mu, gamma, delta, lambar], [c - v for c, v in zip(cas, vals)], "mpmath")
    rng = random.Random(seed)
    worst = {"round trip": 0.0, "H_body - offset - Hbar": 0.0, "Casimirs": 0.0}
    with mpmath.workdps(50):
        for _ in range(n):
            q = [mpmath.mpf(rng.uniform(0.05, 3.09)), mpmath.mpf(rng.uniform(-3.1, 3.1)),
                 mpmath.mpf(rng.uniform(-3.1, 3.1)), mpmath.mpf(rng.uniform(-2, 2)), mpmath.mpf(rng.uniform(-2, 2))]
            prm = [mpmath.mpf(rng.uniform(0.5, 3)), mpmath.mpf(rng.uniform(0, 5)), mpmath.mpf(rng.uniform(0, 3)),
                   mpmath.mpf(rng.uniform(0, 3)), mpmath.mpf(rng.uniform(-1, 1))]
            if prm[1] - 2 * prm[4] * q[4] <= 0.01:
                prm[1] = 2 * prm[4] * q[4] + mpmath.mpf(rng.uniform(0.1, 2))
            x = f_fwd(*q, *prm)
            back = f_inv(*x)
            dq = [back[0] - q[0], mpmath.sin((back[1] - q[1]) / 2), mpmath.sin((back[2] - q[2]) / 2),
                  back[3] - q[3], back[4] - q[4]]
            worst["round trip"] = max(worst["round trip"], float(max(abs(d) for d in dq)))
            worst["H_body - offset - Hbar"] = max(worst["H_body - offset - Hbar"],
                                                  float(abs(f_H(*x, *prm) - f_Hbar(q[0], q[1], q[2], q[3], q[4], *prm))))
            worst["Casimirs"] = max(worst["Casimirs"], float(max(abs(c) for c in f_cas(*x, *prm))))
    ok = all(v < 1e-40 for v in worst.values())
    return Result("chart_numeric", "eq:canonical_moment, eq:canonical_force, eq:full_ham_nondim",
                  "Numeric scale: euler_to_body and body_to_euler are inverse, H_body = Hbar + offset, Casimirs "
                  "take their chart values", CONDITIONAL if ok else DISAGREES,
                  f"numeric: {n} seeded points, 50 digits, max residuals "
                  + ", ".join(f"{k} {v:.1e}" for k, v in worst.items()),
                  {"domain": "0 < theta < pi, mu - 2 lambdabar pbar_psi > 0", "max_residual": worst})


def all_results(pre: dict | None = None):
    """Every derived result, in the report's order.  pre: {module name: its derive_all() results} computed
    elsewhere (build's second process), used instead of deriving them here."""
    pre = pre or {}

    def part(mod):
        name = mod.__name__.rsplit(".", 1)[-1]
        return pre[name] if name in pre else mod.derive_all()

    results = []
    results += part(poisson)
    results += part(reduction)
    results.append(check_chart_numerically())
    results += part(ns)
    results += part(homoclinic)
    results += part(melnikov)
    results += part(symmetry)
    results += part(floquet)
    results += part(splitting)
    results += part(first_integrals)
    results += part(generic_splitting)
    results += part(audit)  # the authors' Fortran
    return results, {}


# The derivation's second half (build(workers=2)): the two ball-arithmetic modules and the two slowest result
# groups, ~36 s of the ~77 s, independent of the rest (each derivation seeds its own random.Random and sets its own
# mpmath precision), so a second process halves the wall time of `python -m derive [--check]` and of the test suite's
# regenerate-and-diff.  What it returns is pickled back; the files are text, identical to the serial build's
# (tests/test_derive.py::test_generated_is_fresh diffs them against generated/).
SECOND_HALF_MODULES = ("splitting_ball.py", "generic_splitting.py")
SECOND_HALF_RESULTS = ("homoclinic", "splitting")


def second_half() -> tuple[dict, dict]:
    files = {"splitting_ball.py": splitting.ball_module(), "generic_splitting.py": generic_splitting.ball_module()}
    return files, {"homoclinic": homoclinic.derive_all(), "splitting": splitting.derive_all()}


def _start_second_half(workers: int):
    """A future of second_half() in a fresh (spawned, not forked: the caller may hold heyoka's threads) process;
    None (do it here) for workers <= 1 or where no process can be started."""
    if workers <= 1:
        return None, None
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    try:
        pool = ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn"))
        return pool, pool.submit(second_half)
    except (OSError, ValueError):
        return None, None


def report_markdown(results) -> str:
    lines = ["# magrod derivation report", "",
             "Written by `python -m derive` (derive/build.py) -- do not edit.  Every row is a result derived with "
             "SymPy from the model of sec. 2 (derive/model.py) and compared with the printed formula "
             "(derive/paper.py).", "",
             "| key | paper label | result | status | how shown |", "|---|---|---|---|---|"]
    for r in results:
        lines.append(f"| {r.key} | {r.label} | {r.title} | **{r.status}** | {r.method} |")
    lines.append("")
    for r in results:
        if not r.details:
            continue
        lines.append(f"## {r.key} ({r.label})")
        lines.append("")
        lines.append("```json")
        lines.append(json.dumps(r.details, indent=2, sort_keys=True, default=str))
        lines.append("```")
        lines.append("")
    return "\n".join(lines)


def build(out_dir: Path, verbose=True, workers: int = 2) -> dict:
    """Write every generated file into out_dir; returns {filename: text}.  workers=2 (default): the derivation's
    second half runs in a second process (SECOND_HALF_*); workers=1: all of it here."""
    t0 = time.perf_counter()
    pool, later = _start_second_half(workers)
    files = {}
    src, red = reduced_module()
    files["reduced.py"] = src
    pm = paper_model()  # the registry's default model is this tree: its pieces go into names.py, body.py, ...
    src, bod = body_module(pm["body"])
    files["body.py"] = src
    for k in ("integrals.py", "model_report.json", "model_report.md"):
        files[k] = pm[k]
    files["validated.py"] = validated.module(red, bod)
    files["homoclinic.py"] = homoclinic.module()
    files["melnikov.py"] = melnikov.module()
    files["symmetry.py"] = symmetry.module()
    files["floquet.py"] = floquet.module()
    files["splitting.py"] = splitting.module()
    files["first_integrals.py"] = first_integrals.module()  # exact first-integral search data
    # the rest of the other results are derived here while the second process works
    pre = {}
    if later is None:
        files["splitting_ball.py"] = splitting.ball_module()  # S in ball arithmetic
        files["generic_splitting.py"] = generic_splitting.ball_module()  # the a > 2b coefficient
    else:
        pre = {"melnikov": melnikov.derive_all(), "generic_splitting": generic_splitting.derive_all(),
               "poisson": poisson.derive_all(), "reduction": reduction.derive_all()}
        from concurrent.futures.process import BrokenProcessPool

        try:
            with pool:
                more, done = later.result()
        except BrokenProcessPool:  # the child could not start (e.g. a __main__ it cannot re-import): do it here
            more, done = second_half()
        files.update(more)
        pre.update(done)
    files["names.py"] = names_module(pm["names"])
    files["scalars.py"] = scalars_module()
    results, _ = all_results(pre)
    results += validated.derive_all(red, bod)
    files["report.json"] = json.dumps({"results": [r.as_dict() for r in results]}, indent=1, sort_keys=True,
                                      default=str) + "\n"
    files["report.md"] = report_markdown(results)
    files["__init__.py"] = ('"""Machine-written by derive/ (python -m derive) -- DO NOT EDIT BY HAND.\n\n'
                            'Modules: ' + ", ".join(sorted(k[:-3] for k in files if k.endswith(".py"))) +
                            '; report.json / report.md: the derivation report."""\n')
    out_dir.mkdir(parents=True, exist_ok=True)
    for name, text in sorted(files.items()):
        (out_dir / name).write_text(text)
    if verbose:
        bad = [r.key for r in results if r.status == DISAGREES]
        print(f"derive: wrote {len(files)} files to {out_dir} in {time.perf_counter() - t0:.1f} s; "
              f"{len(results)} results, disagreements with the paper: {bad or 'none'}")
    return files


# --------------------------------------------------------------------------------------------------------------
# the model family: generated/models/<ident>/ per registered model
# --------------------------------------------------------------------------------------------------------------
def models_files(names=None, verbose=False) -> dict:
    """{relative path under generated/: text} for the registered models (all, or `names`), plus
    generated/models/__init__.py (the list of models).  The default model, the paper's rod, is not among them: it
    is the paper's tree at generated/ top level (paper_model(), written by build())."""
    from . import models
    from .models import pipeline

    out = {}
    chosen = [n for n in (models.NAMES if names is None else names) if n != models.DEFAULT]  # the paper's tree above
    for name in chosen:
        t0 = time.perf_counter()
        m = models.get(name)
        for fname, text in pipeline.model_files(m).items():
            out[f"models/{m.ident}/{fname}"] = text
        if verbose:
            print(f"derive: model {name}: {time.perf_counter() - t0:.1f} s")
    if names is None:
        from .models import heavy

        out["models/heavy.json"] = json.dumps({"results": [r.as_dict() for r in heavy.derive_results()]}, indent=1,
                                              sort_keys=True, default=str) + "\n"
        out["models/__init__.py"] = ('"""Machine-written by derive/build.py (python -m derive) -- DO NOT EDIT BY HAND.\n\n'
                                     'The registered rod models (derive/models/), one package each."""\n\n'
                                     f"MODELS = {tuple(models.NAMES)!r}\nDEFAULT = {models.DEFAULT!r}\n")
    return out


def write_files(out_dir: Path, files: dict) -> None:
    for rel, text in sorted(files.items()):
        p = out_dir / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)
