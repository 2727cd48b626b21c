"""The API reference of magrod, written from the code at build time (a local Sphinx extension, docs/conf.py).

* ``write_api_page(docs)`` writes docs/api.rst: summary tables by topic (autosummary), one page per name under
  docs/api/ (the stubs autosummary generates from docs/_templates/autosummary/).  The face's names are listed from
  ``magrod._API`` (each exactly once: a name of no topic lands in "Other names"); the result types are every
  subclass of ``magrod.core.results.Result`` in the numerics packages plus the other types the face's functions
  return, found by walking the packages, not typed here.
* ``member_tables`` (autodoc-process-docstring, before numpydoc) gives every documented class the numpydoc sections
  a reader looks for: a dataclass's fields as ``Parameters`` (an option class: what its constructor takes) or as
  ``Attributes`` (a result: what it holds), with their annotated types and the description its docstring or its
  source comments give; its properties under ``Attributes``; its public methods (inherited from ``Result``
  included: ``plot``, ``to_xarray``, ``to_dict``, ``save``) under ``Methods``.
* ``xref_aliases()`` maps each documented class's short name to its page, so that a function's ``Returns`` type
  ("PoincareResult", "list of PoincareResult") is a link (numpydoc_xref_param_type).
"""
from __future__ import annotations

import ast
import dataclasses
import functools
import importlib
import inspect
import io
import pkgutil
import re
import tokenize
from pathlib import Path

import magrod

# the face's names by topic (scipy's references group their summary tables the same way)
TOPICS = {
    "Systems and parameters": ["System", "RodParams", "Precision", "ParameterError", "panel"],
    "Sections and chaos": ["poincare_section", "poincare_sections", "section_start", "section_points",
                           "SectionStart", "SectionOptions", "section_portrait", "orbit_diagram", "lyapunov",
                           "lyapunov_spectrum", "gali", "chaos_map"],
    "Orbits": ["saddle", "homoclinic_orbit", "multipulse_orbits", "continue_branch", "rod_shape"],
    "Splitting": ["splitting"],
    "Integrability": ["integrability_report"],
    "Proofs": [],  # the proofs' settings classes (OPTION_CLASSES); `magrod prove` runs them
    "Explorer": ["explore"],
}
# beside the face, the option classes a topic's functions take (second tier, docs/architecture.md)
OPTION_CLASSES = {
    "Sections and chaos": ["magrod.chaos.maps.MapSpec"],
    "Proofs": ["magrod.proof.provers.transverse_homoclinic.ProofSettings",
               "magrod.proof.provers.horseshoe_design.HorseshoeSettings",
               "magrod.proof.provers.section_fixed_point.FixedPointSettings"],
}
TOPIC_INTRO = {
    "Systems and parameters": "What is studied: a rod model, its parameter values and the precision.  Every "
                              "function below takes a ``system`` first (a System, or what converts to one: a "
                              "panel key, a RodParams, a model name or file).",
    "Sections and chaos": "Poincaré sections, chaos indicators and chaos maps.",
    "Orbits": "Saddles, homoclinic and multipulse orbits, their continuation and the rod's shape.",
    "Splitting": "The splitting of the separatrix and its Mel'nikov coefficient.",
    "Integrability": "First integrals, the Painlevé and Kovalevskaya tests and the comparison with the paper.",
    "Proofs": "The numerical choices of the computer-assisted proofs (``magrod prove``), recorded in each "
              "certificate and replayed by its verifier.",
    "Explorer": "The interactive section explorer (in the browser or inline in Jupyter).",
    "Result types": "What the functions return.  Every result has ``success`` and ``message``, a short repr, "
                    "``to_dict()`` (JSON-able), ``to_xarray()``, ``save()``, ``plot(ax=None)`` and the accuracy it "
                    "achieved.",
}
# packages whose modules hold result types (the clients -- cli, figures -- define none)
NUMERICS = ("core", "chaos", "orbits", "separatrix", "integrability", "proof", "paper", "store", "explorer")


def _face_names() -> list[str]:
    return list(magrod.__all__)


def _walk_classes() -> dict[str, type]:
    """{module.qualname: class} of every class defined in the numerics packages."""
    found = {}
    for pkg in NUMERICS:
        base = importlib.import_module(f"magrod.{pkg}")
        mods = [base.__name__]
        if hasattr(base, "__path__"):
            mods += [m.name for m in pkgutil.walk_packages(base.__path__, f"{base.__name__}.")]
        for name in mods:
            mod = importlib.import_module(name)
            for obj in vars(mod).values():
                if inspect.isclass(obj) and obj.__module__ == name:
                    found[f"{name}.{obj.__qualname__}"] = obj
    return found


@functools.lru_cache(maxsize=None)
def _returned_names(obj) -> list[str]:
    """The class names a face function's numpydoc Returns section gives as types."""
    from numpydoc.docscrape import NumpyDocString

    doc = NumpyDocString(inspect.getdoc(obj) or "")
    return [w for p in doc["Returns"] for w in re.findall(r"\b[A-Z]\w+", p.type or p.name)]


def result_types() -> dict[str, type]:
    """{full dotted name: class} of every result type: Result's subclasses in the numerics packages and the other
    classes the face's functions return (Panel, SectionPoints, the explorer's page objects), sorted by name."""
    from magrod.core.results import Result

    classes = _walk_classes()
    face = {getattr(magrod, n) for n in _face_names()}
    out = {k: c for k, c in classes.items() if issubclass(c, Result) and c is not Result}
    by_short = {}
    for k, c in classes.items():
        by_short.setdefault(c.__name__, []).append(k)
    for n in _face_names():
        obj = getattr(magrod, n)
        if isinstance(obj, type):
            continue
        for short in _returned_names(obj):
            for k in by_short.get(short, []):
                if classes[k] not in face:
                    out[k] = classes[k]
    # a module-level alias (ModelSplitting = MelnikovScan) is one class with one page
    return dict(sorted(out.items(), key=lambda kv: kv[1].__name__.lower()))


def documented_classes() -> dict[str, str]:
    """{short class name: documented dotted name} of every class the reference has a page for."""
    out = {}
    for n in _face_names():
        if isinstance(getattr(magrod, n), type):
            out[n] = f"magrod.{n}"
    for names in OPTION_CLASSES.values():
        for full in names:
            out.setdefault(full.rsplit(".", 1)[1], full)
    for full, cls in result_types().items():
        out.setdefault(cls.__name__, full)
    return out


def xref_aliases() -> dict[str, str]:
    return documented_classes()


def _rel(full: str) -> str:
    """An autosummary entry under ``currentmodule:: magrod`` that shows the class's short name."""
    return "~" + full.removeprefix("magrod.")


def write_api_page(docs: Path) -> None:
    """docs/api.rst: the summary tables by topic; autosummary writes one page per entry into docs/api/."""
    face = _face_names()
    placed = [n for names in TOPICS.values() for n in names]
    missing = [n for n in face if n not in placed]
    topics = {t: [n for n in names if n in face] for t, names in TOPICS.items()}
    if missing:
        topics["Other names"] = missing
    lines = ["API reference", "=============", "",
             "The public API is the flat namespace ``import magrod as mr`` (the names of ``magrod.__all__``); each "
             "name has a page of its own, written from its docstring (numpydoc), and so has every type a function "
             "returns.  The command line (:doc:`cli`) calls the same functions.", "",
             ".. currentmodule:: magrod", ""]

    def table(entries, template):
        return [".. autosummary::", "   :toctree: api", f"   :template: autosummary/{template}", "   :nosignatures:", "",
                *[f"   {e}" for e in entries], ""]

    for topic in topics:
        names = topics.get(topic, [])
        extra = OPTION_CLASSES.get(topic, [])
        if not names and not extra:
            continue
        lines += [topic, "-" * len(topic), "", TOPIC_INTRO.get(topic, ""), ""]
        funcs = [n for n in names if not isinstance(getattr(magrod, n), type)]
        classes = [n for n in names if isinstance(getattr(magrod, n), type)]
        if funcs:
            lines += table(funcs, "function.rst")
        if classes or extra:
            lines += table([*classes, *[_rel(e) for e in extra]], "class.rst")
    lines += ["Result types", "------------", "", TOPIC_INTRO["Result types"], ""]
    from magrod.core.results import Result

    types = result_types()
    # a Result documents the members it inherits (plot, to_xarray, to_dict, save); the explorer's page objects do
    # not (theirs come from Panel)
    lines += table([_rel(k) for k, c in types.items() if issubclass(c, Result)], "result.rst")
    lines += table([_rel(k) for k, c in types.items() if not issubclass(c, Result)], "class.rst")
    lines += _second_tier()
    # a stub of a name that is gone (renamed, dropped) would be a page in no toctree: an error under -W
    wanted = {f"magrod.{n}.rst" for n in face} | {f"{k}.rst" for k in types} | \
        {f"{e}.rst" for names in OPTION_CLASSES.values() for e in names}
    for stub in (docs / "api").glob("*.rst"):
        if stub.name not in wanted:
            stub.unlink()
    text = "\n".join(lines)
    path = docs / "api.rst"
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


def _second_tier() -> list[str]:
    """The numerics packages' public names besides the face (docs/architecture.md): listed, not documented page by
    page (what the command line, the figures and the explorer use)."""
    lines = ["The second tier", "---------------", "",
             "Besides the face, each numerics package has a small public namespace: what the command line, the "
             "figures and the explorer use (format helpers, the scans behind a figure, the prover and the "
             "verifier, constants of a picture).  ``from magrod.chaos import MAPPABLE`` is public; "
             "``magrod.chaos.section`` and the names it does not list are internals.", ""]
    for pkg in ("chaos", "orbits", "separatrix", "integrability", "proof"):
        mod = importlib.import_module(f"magrod.{pkg}")
        lines += [f"``magrod.{pkg}``", ""]
        for name in mod.__all__:
            target = mod._API[name]
            where, attr = (target, name) if isinstance(target, str) else target
            lines.append(f"* ``{name}`` (``magrod.{pkg}.{where}.{attr}``)")
        lines.append("")
    return lines


# ---- the member tables -------------------------------------------------------------------------------------------
ISSUE_REF = re.compile(r"\s*\((?:[^()]*;\s*)?[Ii]ssues? \d+[^()]*\)|\b[Uu]ntil issue \d+,?\s*")


def _clean(text: str) -> str:
    return " ".join(ISSUE_REF.sub("", text).split())


def _field_comments(cls) -> dict[str, str]:
    """{field: text} from the class source: ``#:`` comments above a field and the comment at the end of its line."""
    try:
        src = inspect.getsource(cls)
    except (OSError, TypeError):
        return {}
    src = inspect.cleandoc("\n" + src) if src.startswith((" ", "\t")) else src
    try:
        tree = ast.parse(src)
    except SyntaxError:
        return {}
    comments = {}
    for tok in tokenize.generate_tokens(io.StringIO(src).readline):
        if tok.type == tokenize.COMMENT:
            comments[tok.start[0]] = (tok.line[: tok.start[1]].strip() == "", tok.string.lstrip("#").strip())
    out = {}
    body = tree.body[0].body if tree.body and isinstance(tree.body[0], ast.ClassDef) else []
    for node in body:
        if not (isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name)):
            continue
        above, ln = [], node.lineno - 1
        while ln in comments and comments[ln][0] and src.splitlines()[ln - 1].lstrip().startswith("#:"):
            above.insert(0, comments[ln][1].lstrip(":").strip())
            ln -= 1
        trailing = [comments[i][1] for i in range(node.lineno, node.end_lineno + 1)
                    if i in comments and not comments[i][0]]
        text = _clean(" ".join([*above, *trailing]))
        if text:
            out[node.target.id] = text
    return out


def _prose_descriptions(doc: str, names) -> dict[str, str]:
    """{field: text} where the class docstring's prose describes a field as ``name: text;`` or
    ``name (shape): text;`` (the house style of the result classes' docstrings): the text up to the next ``;``
    outside brackets, the sentence's end or the paragraph's end."""
    out = {}
    flat = " ".join(doc.split())
    for name in names:
        m = re.search(rf"(?<![\w.`]){re.escape(name)}`?(\s\([^()]*\))?: ", flat)
        if not m:
            continue
        depth, end = 0, len(flat)
        for i in range(m.end(), len(flat)):
            ch = flat[i]
            depth += ch in "([{"
            depth -= ch in ")]}"
            if depth < 0 or (depth == 0 and ch == ";"):
                end = i
                break
            if depth == 0 and ch == "." and re.match(r"\s+[A-Z`]", flat[i + 1:i + 4]):  # the sentence ends
                end = i
                break
        text = _clean(flat[m.end():end]).rstrip(".")
        if m.group(1):  # "times (K,): ..." -- the shape first
            text = f"{m.group(1).strip()} {text}"
        if text:
            out[name] = text
    return out


# what the fields every result shares mean (scipy's success/message; the provenance fields)
COMMON_FIELDS = {
    "success": "True if the computation did what was asked and passed its own accuracy checks.",
    "message": "Why it succeeded or failed, in one line.",
    "system": "The System studied (model, parameter values, precision).",
    "params": "The paper's rod's non-dimensional parameters (m, mu, gamma, delta, lam).",
    "wall_s": "Wall-clock time of the computation, in seconds.",
    "precision": "The floating-point precision of the integration.",
    "panel": "The paper's panel key the run started from, if any.",
    "max_abs_dH": "Max |Hbar - h| along the computation: how well the energy was conserved.",
    "casimir_drift": "The largest drift of the Casimirs along the computation (body frame).",
    "h": "The energy level Hbar = h.",
}


def _first_sentence(text: str) -> str:
    """Up to the first ". " or "; " outside brackets (without it)."""
    depth = 0
    for i, ch in enumerate(text):
        depth += ch in "([{"
        depth -= ch in ")]}"
        if depth == 0 and ch in ".;" and (i + 1 == len(text) or text[i + 1] == " "):
            return text[:i]
    return text.rstrip(".;")


def _returning_parameters(cls) -> dict[str, str]:
    """{parameter: "The `h` of poincare_section: <its first sentence>."} from the Parameters of the face's
    functions whose Returns name cls: a result's field that echoes an input (h, iterates, tol) says so."""
    from numpydoc.docscrape import NumpyDocString

    out = {}
    for n in _face_names():
        obj = getattr(magrod, n)
        if isinstance(obj, type) or cls.__name__ not in _returned_names(obj):
            continue
        for p in NumpyDocString(inspect.getdoc(obj) or "")["Parameters"]:
            first = _first_sentence(_clean(" ".join(p.desc)))
            for name in (x.strip() for x in p.name.split(",")):
                if first and name not in out:
                    out[name] = f"The ``{name}`` of `{n}`: {first}."
    return out


def _type_text(annotation) -> str:
    if isinstance(annotation, str):
        text = annotation
    elif isinstance(annotation, type):
        text = annotation.__name__
    else:
        text = str(annotation).replace("typing.", "")
    return {"np.ndarray": "ndarray", "numpy.ndarray": "ndarray", "object": ""}.get(text, text)


def _first_line(doc: str) -> str:
    para = re.split(r"\n\s*\n", (doc or "").strip(), maxsplit=1)[0]
    return _clean(para)


def _own_members(cls) -> dict:
    """{public name: attribute} defined by magrod classes in cls's MRO, the nearest definition winning (read from
    each class's namespace: an Enum's dir() hides its methods and properties)."""
    out = {}
    for k in reversed(cls.__mro__):
        if k.__module__.startswith("magrod"):
            out.update({n: a for n, a in vars(k).items() if not n.startswith("_")})
        else:
            for n in vars(k):
                out.pop(n, None)
    return out


def _public_methods(cls) -> list[str]:
    """Public methods defined by magrod classes in cls's MRO (not by object, Enum, str or a framework)."""
    return sorted(n for n, a in _own_members(cls).items()
                  if isinstance(a, (staticmethod, classmethod)) or inspect.isfunction(a))


def _properties(cls) -> list[str]:
    return sorted(n for n, a in _own_members(cls).items()
                  if isinstance(a, property) and "deprecated" not in (a.__doc__ or "").lower()[:40])


def class_sections(cls, doc_text: str) -> str | None:
    """The docstring of cls with its member sections filled in (None: nothing to add)."""
    from numpydoc.docscrape import NumpyDocString, Parameter

    from magrod.core.results import Result

    doc = NumpyDocString(doc_text)
    listed = {n.strip() for s in ("Parameters", "Attributes", "Other Parameters") for p in doc[s]
              for n in p.name.split(",")}
    changed = False
    if dataclasses.is_dataclass(cls):
        fields = [f for f in dataclasses.fields(cls) if not f.name.startswith("_")]
        comments = _field_comments(cls)
        echoed = _returning_parameters(cls)
        prose = _prose_descriptions("\n".join([*doc["Summary"], *doc["Extended Summary"]]),
                                    [f.name for f in fields])
        hints = {}
        for k in reversed(cls.__mro__):
            hints.update(getattr(k, "__annotations__", {}))
        rows = []
        for f in fields:
            if f.name in listed:
                continue
            desc = (comments.get(f.name) or prose.get(f.name) or COMMON_FIELDS.get(f.name)
                    or echoed.get(f.name, ""))
            if f.default is not dataclasses.MISSING and not isinstance(f.default, (dict, list)):
                default = f.default.value if hasattr(f.default, "value") else f.default
                desc = f"{desc}  Default {default!r}." if desc else f"Default {default!r}."
            rows.append(Parameter(f.name, _type_text(hints.get(f.name, f.type)), [desc] if desc else []))
        if rows:
            # a result holds its fields; an option class is constructed from them (unless its docstring already
            # says what the constructor takes)
            option = not issubclass(cls, Result) and cls.__dataclass_params__.init and not doc["Parameters"]
            section = "Parameters" if option else "Attributes"
            doc[section] = list(doc[section]) + rows
            listed |= {r.name for r in rows}
            changed = True
    props = [n for n in _properties(cls) if n not in listed]
    if props:
        doc["Attributes"] = list(doc["Attributes"]) + [
            Parameter(n, "", [_first_line(inspect.getdoc(getattr(cls, n)) or "")]) for n in props]
        changed = True
    methods = _public_methods(cls)
    if methods and not doc["Methods"]:
        doc["Methods"] = [Parameter(n, "", []) for n in methods]
        changed = True
    if not changed:
        return None
    return str(doc)


LITERAL = re.compile(r"(``.*?``|`[^`]*`)")
SECTION = re.compile(r"^\s*-{3,}\s*$")


def escape_bars(lines: list[str]) -> list[str]:
    """``|x|`` (an absolute value, a norm) is text in the docstrings, not a reST substitution reference: escape
    every bar outside inline literals, doctest examples and literal blocks."""
    out, in_examples, literal_indent = [], False, None
    for i, line in enumerate(lines):
        stripped = line.strip()
        if i + 1 < len(lines) and SECTION.match(lines[i + 1]) and stripped:
            in_examples = stripped == "Examples"
        indent = len(line) - len(line.lstrip())
        if literal_indent is not None and stripped and indent <= literal_indent:
            literal_indent = None
        if in_examples or literal_indent is not None or stripped.startswith((">>>", "...")) or "|" not in line:
            out.append(line)
        else:
            out.append("".join(p if LITERAL.fullmatch(p) else p.replace("|", "\\|") for p in LITERAL.split(line)))
        if stripped.endswith("::") and literal_indent is None:
            literal_indent = indent
    return out


def member_tables(app, what, name, obj, options, lines):
    module = getattr(obj, "__module__", None) or ""
    if not module.startswith("magrod") and not name.startswith("magrod"):
        return
    if what == "class" and inspect.isclass(obj):
        text = class_sections(obj, "\n".join(lines))
        if text is not None:
            lines[:] = text.splitlines()
    lines[:] = escape_bars(lines)


def _escape_property_summaries() -> None:
    """numpydoc lists a property under Attributes with the first sentence of the property's own docstring, read
    past autodoc-process-docstring: escape the bars of that sentence as escape_bars does for the rest."""
    from numpydoc.docscrape_sphinx import SphinxDocString

    if getattr(SphinxDocString._process_param, "_magrod", False):
        return
    original = SphinxDocString._process_param

    def process_param(self, param, desc, fake_autosummary):
        display, desc = original(self, param, desc, fake_autosummary)
        return display, escape_bars(list(desc))

    process_param._magrod = True
    SphinxDocString._process_param = process_param


def setup(app):
    _escape_property_summaries()
    # before numpydoc's mangle_docstrings (priority 500), which renders the sections this adds
    app.connect("autodoc-process-docstring", member_tables, priority=100)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
