"""The package layout and its rules (docs/architecture.md), enforced on the source (AST) and at import.

As heyoka.py's test_package_layout does, the public names are pinned: adding or removing one is a decision,
made here and in docs/architecture.md, never a side effect."""
from __future__ import annotations

import ast
import dataclasses
import inspect
import subprocess
import sys
from pathlib import Path

import pytest

import magrod
from magrod.core.precision import Precision

ROOT = Path(magrod.__file__).resolve().parent
NUMERICS = ("core", "orbits", "chaos", "separatrix", "integrability", "proof")  # the numerics wing (subpackages)

PUBLIC = {
    "System", "RodParams", "Precision", "ParameterError", "panel",
    "poincare_section", "poincare_sections", "section_start", "section_points", "SectionStart", "SectionOptions",
    "section_portrait", "orbit_diagram", "lyapunov", "lyapunov_spectrum",
    "gali", "chaos_map",
    "saddle", "homoclinic_orbit", "multipulse_orbits", "continue_branch", "rod_shape",
    "splitting", "integrability_report",
    "explore",
}


def _modules(*subpackages):
    for sub in subpackages:
        for path in sorted((ROOT / sub).rglob("*.py")):
            yield path, ast.parse(path.read_text(), filename=str(path))


def _rel(path: Path) -> str:
    return str(path.relative_to(ROOT))


# --------------------------------------------------------------------------------------------------------------
# the face
def test_public_names_are_pinned():
    assert set(magrod.__all__) == PUBLIC
    for name in PUBLIC:
        assert getattr(magrod, name) is not None
    assert set(dir(magrod)) >= PUBLIC


@pytest.mark.parametrize("name", sorted(PUBLIC))
def test_public_docstrings_are_numpydoc(name):
    """Every public function documents Parameters, Returns, Raises, Examples and Notes; every public class has a
    docstring with an Examples section or documented fields."""
    obj = getattr(magrod, name)
    doc = inspect.getdoc(obj) or ""
    assert doc, name
    if inspect.isfunction(obj):
        for section in ("Parameters", "Returns", "Raises", "Examples", "Notes"):
            assert f"\n{section}\n" + "-" * len(section) in doc, f"{name}: no {section} section"
        assert ">>> " in doc, f"{name}: the Examples section has no example"


def _result_classes():
    import importlib
    import pkgutil

    from magrod.core.results import Result

    for mod in pkgutil.walk_packages([str(ROOT)], prefix="magrod."):
        if mod.name.startswith(("magrod.cli", "magrod.figures", "magrod.derive", "magrod.generated")):
            continue
        importlib.import_module(mod.name)
    seen, todo = [], list(Result.__subclasses__())
    while todo:
        c = todo.pop()
        seen.append(c)
        todo.extend(c.__subclasses__())
    return seen


def test_results_share_one_face():
    """Every result class: a dataclass with success and message, the short repr of Result (not the dataclass's
    field dump: @dataclass(repr=False)), and a registered plotter."""
    from magrod.core.results import Result
    from magrod.figures.plots import PLOTTERS

    classes = _result_classes()
    assert len(classes) >= 4
    for c in classes:
        assert dataclasses.is_dataclass(c), c
        names = {f.name for f in dataclasses.fields(c)}
        assert {"success", "message"} <= names, c
        assert c.__repr__ is Result.__repr__, f"{c.__name__}: use @dataclass(repr=False)"
        assert c.__name__ in PLOTTERS, f"{c.__name__} has no plotter in magrod/figures/plots.py"


# --------------------------------------------------------------------------------------------------------------
# rules on the source
def test_only_systems_builds_heyoka_integrators():
    builders = {"taylor_adaptive", "taylor_adaptive_batch"}
    offenders = []
    for path, tree in _modules(*NUMERICS, "figures", "cli"):
        if _rel(path) == "core/systems.py":
            continue
        for node in ast.walk(tree):
            if isinstance(node, ast.Attribute) and node.attr in builders:
                offenders.append(f"{_rel(path)}:{node.lineno} {node.attr}")
    assert not offenders, offenders


# The body state has 9 components, its variational matrix 81, with the parameters 9 x 14 = 126 ... : sizes come
# from generated/names.py through systems.dim/state_index/par_index, never as literals.  Allowed literals are
# listed with the reason.
STATE_SIZES = {9, 14, 81, 126, 135}
ALLOWED_LITERALS = {
    ("core/systems.py", 9): "_unit_state: the nine components of the straight rod, a placeholder state",
    ("orbits/rod.py", 9): "the 3 x 3 director frame D stacked after the state",
}


def test_no_literal_state_sizes_in_the_numerics():
    offenders = []
    for path, tree in _modules(*NUMERICS):
        for node in ast.walk(tree):
            if isinstance(node, ast.Constant) and type(node.value) is int and node.value in STATE_SIZES:
                if (_rel(path), node.value) not in ALLOWED_LITERALS:
                    offenders.append(f"{_rel(path)}:{node.lineno}: {node.value}")
    assert not offenders, offenders


def test_no_literal_parameter_indices():
    """pars[4] or p[1] would silently mean another parameter if PARAMS changed: use systems.par_index(name)."""
    offenders = []
    for path, tree in _modules(*NUMERICS):
        for node in ast.walk(tree):
            if (isinstance(node, ast.Subscript) and isinstance(node.value, ast.Name)
                    and node.value.id in ("pars", "p", "params", "par") and isinstance(node.slice, ast.Constant)
                    and type(node.slice.value) is int):
                offenders.append(f"{_rel(path)}:{node.lineno}")
    assert not offenders, offenders


def test_numerics_do_not_import_matplotlib():
    """Results draw through magrod.figures (Result.plot imports it lazily); the numerics never import
    matplotlib themselves."""
    offenders = []
    for path, tree in _modules(*NUMERICS):
        for node in ast.walk(tree):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else (
                [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            if any(n.split(".")[0] == "matplotlib" for n in names):
                offenders.append(f"{_rel(path)}:{node.lineno}")
    assert not offenders, offenders


def _module_level_calls(tree):
    """Calls executed at import: statements of the module body (and of if/try/with blocks in it), not inside
    functions or classes."""
    stack = list(tree.body)
    while stack:
        node = stack.pop()
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Lambda)):
            continue
        if isinstance(node, ast.Call):
            yield node
        stack.extend(ast.iter_child_nodes(node))


def test_no_process_wide_settings_anywhere_at_import():
    """No matplotlib.use anywhere; no signal handler, logger level or heyoka logger change executed at import
    (the CLI sets them in main() and restores them)."""
    offenders = []
    for path, tree in _modules(*NUMERICS, "figures", "cli"):
        for node in ast.walk(tree):
            if isinstance(node, ast.Attribute) and node.attr == "use" and isinstance(node.value, ast.Name) \
                    and node.value.id in ("matplotlib", "mpl"):
                offenders.append(f"{_rel(path)}:{node.lineno} matplotlib.use")
        for call in _module_level_calls(tree):
            f = call.func
            name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
            if name in ("signal", "setLevel", "basicConfig", "set_logger_level_critical", "set_logger_level_off",
                        "filterwarnings", "simplefilter", "use"):
                offenders.append(f"{_rel(path)}:{call.lineno} {name}() at import")
    assert not offenders, offenders


def test_importing_everything_changes_nothing_in_the_process():
    """Import magrod and every module of the numerics, figures and CLI wings in a fresh interpreter: the SIGINT
    handler is Python's default, matplotlib is not imported by the numerics, no backend was chosen."""
    code = (
        "import importlib, pkgutil, signal, sys, warnings\n"
        "before = (signal.getsignal(signal.SIGINT), warnings.showwarning)\n"
        "import magrod\n"
        "for m in pkgutil.walk_packages(magrod.__path__, 'magrod.'):\n"
        "    if not m.name.startswith(('magrod.derive', 'magrod.cli.__main__')):\n"
        "        importlib.import_module(m.name)\n"
        "after = (signal.getsignal(signal.SIGINT), warnings.showwarning)\n"
        "assert before == after, (before, after)\n"
        "import matplotlib\n"
        "assert matplotlib.rcParams._get_backend_or_none() is None, matplotlib.rcParams._get_backend_or_none()\n"
        "print('ok')\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0 and r.stdout.strip() == "ok", r.stderr[-2000:]


def test_import_magrod_is_light():
    """`import magrod` loads neither heyoka nor matplotlib nor dask (PEP 562 lazy names)."""
    code = ("import sys, magrod\n"
            "heavy = [m for m in ('heyoka', 'matplotlib', 'dask', 'scipy') if m in sys.modules]\n"
            "print(heavy)\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert r.stdout.strip() == "[]", r.stdout + r.stderr


def test_cli_main_restores_the_process_settings():
    import signal
    import warnings

    from magrod import cli

    before = (signal.getsignal(signal.SIGINT), warnings.showwarning)
    assert cli.main(["check", "--json"]) == 0
    assert (signal.getsignal(signal.SIGINT), warnings.showwarning) == before


def test_every_package_is_installed():
    """CI installs magrod non-editably (`pip install .`): a subpackage missing from pyproject's list is absent there
    although every test passes in an editable checkout. That happened once (magrod.proof); this keeps it from recurring."""
    import tomllib

    repo = Path(__file__).resolve().parents[1]  # the checkout, not the installed package
    conf = tomllib.loads((repo / "pyproject.toml").read_text())["tool"]["setuptools"]
    listed = set(conf["packages"])
    dirs = {v: k for k, v in conf["package-dir"].items()}  # folder -> package name
    found = set()
    for top, name in dirs.items():
        for init in (repo / top).rglob("__init__.py"):
            rel = init.parent.relative_to(repo / top)
            found.add(".".join([name, *rel.parts]))
    assert found - listed == set(), f"packages with an __init__.py that pyproject.toml does not install: {found - listed}"
    assert listed - found == set(), f"pyproject.toml lists packages that do not exist: {listed - found}"


def test_one_class_per_name_for_the_shared_concepts():
    """One Crossing (issue 25: orbits/shooting.py's record and proof/taylor.py's enclosure were both `Crossing`; the
    rigorous one is CrossingEnclosure).  Read from the source: a second class of a listed name anywhere fails."""
    names = {"Crossing", "Saddle", "SectionStart", "SectionOptions", "Branch"}
    seen = {}
    for path, tree in _modules(*NUMERICS, "store", "figures", "cli", "explorer"):
        for node in ast.walk(tree):
            if isinstance(node, ast.ClassDef) and node.name in names:
                seen.setdefault(node.name, []).append(_rel(path))
    assert {k: v for k, v in seen.items() if len(v) > 1} == {}


# --------------------------------------------------------------------------------------------------------------
# one calling convention: what is studied comes first, as `system` (anything magrod.core.system.as_system takes);
# a function that continues a result takes it second; the options are keyword-only, spelled the same everywhere
# (T is the rod's tension and M its twisting moment in the paper's notation, never a time: not listed below)
CONVENTION = {"precision", "tol", "t_max", "iterates", "progress", "workers", "verify"}
OTHER_SPELLINGS = {  # a parameter spelt like this means one of CONVENTION
    "fp_type": "precision", "dtype": "precision", "prec": "precision", "rtol": "tol", "atol": "tol",
    "tolerance": "tol", "tmax": "t_max", "t_end": "t_max", "max_time": "t_max", "t_final": "t_max",
    "n_iterates": "iterates", "n_iter": "iterates", "iterations": "iterates", "n_points": "iterates",
    "callback": "progress", "progress_bar": "progress", "threads": "workers", "n_workers": "workers",
    "jobs": "workers", "n_jobs": "workers", "processes": "workers", "check": "verify", "validate": "verify",
}
NOT_STUDIED = {"panel": "a look-up of the paper's printed panels by key: it returns what converts to a System"}

def _public_functions():
    return {n: getattr(magrod, n) for n in sorted(PUBLIC) if inspect.isfunction(getattr(magrod, n))}


def _converted(fn) -> bool:
    params = list(inspect.signature(fn).parameters.values())
    return bool(params) and params[0].name == "system" and params[0].kind in (
        inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD)


def _convention_offences(name, fn) -> list:
    """What in fn's signature breaks the one calling convention (empty if nothing)."""
    bad = []
    params = list(inspect.signature(fn).parameters.values())
    if not _converted(fn):
        first = params[0].name if params else "(none)"
        bad.append(f"{name}: first parameter {first!r}, not a positional 'system'")
    for p in params:
        if p.name in OTHER_SPELLINGS:
            bad.append(f"{name}: {p.name}= is spelt {OTHER_SPELLINGS[p.name]}= everywhere")
        if p.name in CONVENTION and p.kind is not p.KEYWORD_ONLY:
            bad.append(f"{name}: {p.name}= is not keyword-only")
        if p.name == "tol" and p.default is not None and p.default is not inspect.Parameter.empty:
            bad.append(f"{name}: tol= defaults to {p.default!r}, not None (the method's default)")
        if p.name == "precision" and not (p.default is None or isinstance(p.default, (str, Precision))):
            bad.append(f"{name}: precision= defaults to {p.default!r}, not a Precision, its name or None")
    return bad


@pytest.mark.parametrize("name", sorted(set(_public_functions()) - set(NOT_STUDIED)))
def test_one_calling_convention(name):
    """Walk the public functions: the first argument is `system`, the options keyword-only and spelt as everywhere
    else (precision=, tol= defaulting to None, t_max=, iterates=, progress=, workers=, verify=).  Seen to fail on
    integrability_report(subs, ...) and explore(panel, ...) before they took the system first."""
    fn = _public_functions()[name]
    bad = _convention_offences(name, fn)
    assert not bad, bad


def test_the_convention_check_catches_each_offence():
    """The walk's own check, on functions written to break each rule once."""
    def ok(system, orbit=None, *, precision=None, tol=None, t_max=1.0, iterates=10, progress=None, workers=None,
           verify=True):
        pass

    def first(params, *, tol=None):
        pass

    def spelt(system, *, fp_type=None, threads=2):
        pass

    def positional_option(system, tol=None):
        pass

    def zero_tol(system, *, tol=0.0):
        pass

    assert _convention_offences("ok", ok) == []
    assert "'params'" in _convention_offences("first", first)[0]
    assert len(_convention_offences("spelt", spelt)) == 2
    assert "keyword-only" in _convention_offences("positional_option", positional_option)[0]
    assert "not None" in _convention_offences("zero_tol", zero_tol)[0]


def test_the_allowlists_name_public_functions():
    assert set(NOT_STUDIED) <= set(_public_functions())
