"""The documentation site builds with warnings as errors, its notebooks executed (myst-nb, a failing cell fails the
build), the API reference covers magrod.__all__ and the CLI reference every subcommand (both generated, not typed).
This is the README's docs command; it takes ~1-2 min on 2 cores (the four notebooks dominate)."""
from __future__ import annotations

import functools
import inspect
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import magrod

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"

pytest.importorskip("sphinx")
bs4 = pytest.importorskip("bs4")  # installed with pydata-sphinx-theme (the docs extra)
NumpyDocString = pytest.importorskip("numpydoc.docscrape").NumpyDocString
pytest.importorskip("myst_nb")


def _readme_docs_command() -> str:
    text = (ROOT / "README.md").read_text()
    cmds = [ln.strip() for b in re.findall(r"```bash\n(.*?)```", text, flags=re.S) for ln in b.splitlines()
            if "sphinx" in ln and not ln.lstrip().startswith("#")]
    assert len(cmds) == 1, cmds
    return cmds[0]


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    if not DOCS.joinpath("conf.py").exists():
        pytest.skip("needs the source tree")
    out = tmp_path_factory.mktemp("html")
    cmd = _readme_docs_command().split()
    assert cmd[:4] == ["python", "-m", "sphinx", "-W"] and cmd[-2:] == ["docs", "docs/_build/html"]
    r = subprocess.run([sys.executable, *cmd[1:-1], str(out)], cwd=ROOT, capture_output=True, text=True,
                       timeout=900)
    assert r.returncode == 0, (r.stdout[-3000:], r.stderr[-6000:])
    return out


# what reST looks like when a page shows it instead of rendering it (autodoc output inside a MyST page)
RAW_REST = (".. py:", ":Parameters:", ":Returns:", "!! processed by numpydoc", ":module:", ".. autofunction",
            ".. autoclass", ".. autosummary")


def _raw_rest_in(html_text: str) -> list[str]:
    text = bs4.BeautifulSoup(html_text, "html.parser").get_text()
    return [m for m in RAW_REST if m in text]


def _page(site, dotted: str) -> Path:
    return site / "api" / f"{dotted}.html"


@functools.lru_cache(maxsize=None)
def _soup(path: Path):
    """An API page parsed once for the several tests that read it (never modified by them)."""
    return bs4.BeautifulSoup(path.read_text(), "html.parser")


def _entry(site, dotted: str):
    """The <dl class="py ..."> of a documented object on its own page (its <dt> carries the dotted id)."""
    page = _page(site, dotted)
    assert page.exists(), f"no page for {dotted}"
    dt = _soup(page).find("dt", id=dotted)
    assert dt is not None, f"no entry {dotted} on its page"
    return dt.parent


def _fields(dl) -> dict:
    """{section: <dd>} of numpydoc's field list directly under an entry (Parameters, Returns, Attributes, ...)."""
    return {dt.get_text(strip=True).rstrip(":"): dt.find_next_sibling("dd")
            for fl in dl.find("dd", recursive=False).find_all("dl", class_="field-list", recursive=False)
            for dt in fl.find_all("dt", recursive=False)}


def _face_pages():
    """(public name, the dotted name its page documents): every name of magrod.__all__ as magrod.<name>."""
    return [(n, f"magrod.{n}") for n in magrod.__all__]


def _result_types() -> dict:
    """{dotted name: class} of every result type, found here independently of the docs' own list: each subclass of
    magrod.core.results.Result defined in a numerics package, and each class a face function's Returns names."""
    import importlib
    import pkgutil

    from magrod.core.results import Result

    classes = {}
    for pkg in ("core", "chaos", "orbits", "separatrix", "integrability", "proof", "paper", "store", "explorer"):
        base = importlib.import_module(f"magrod.{pkg}")
        for info in pkgutil.walk_packages(base.__path__, f"{base.__name__}."):
            mod = importlib.import_module(info.name)
            classes.update({f"{info.name}.{c.__qualname__}": c for c in vars(mod).values()
                            if inspect.isclass(c) and c.__module__ == info.name})
    out = {k: c for k, c in classes.items() if issubclass(c, Result) and c is not Result}
    face = {getattr(magrod, n) for n in magrod.__all__}
    for n in magrod.__all__:
        obj = getattr(magrod, n)
        if isinstance(obj, type):
            continue
        for p in NumpyDocString(inspect.getdoc(obj) or "")["Returns"]:
            for word in re.findall(r"\b[A-Z]\w+", p.type):
                out.update({k: c for k, c in classes.items() if c.__name__ == word and c not in face})
    return out


def test_every_public_name_and_result_type_has_a_page(site):
    """One page per name of magrod.__all__ (api/magrod.<name>.html, documenting magrod.<name>) and one per result
    type (api/<module>.<Class>.html), each a real Sphinx entry with no reST shown as text.  Seen to fail on the
    one-page reference (no api/ pages) and with PoincareResult dropped from the summary (its page missing)."""
    pages = [dotted for _, dotted in _face_pages()] + list(_result_types())
    assert len(pages) >= len(magrod.__all__) + 25
    missing = [d for d in pages if not _page(site, d).exists()]
    assert not missing, missing
    for dotted in pages:
        dl = _entry(site, dotted)
        assert "py" in dl["class"] and ({"function", "class", "exception"} & set(dl["class"])), dotted
        text = _soup(_page(site, dotted)).get_text()
        assert not [m for m in RAW_REST if m in text], dotted


def test_function_pages_have_parameters_and_returns(site):
    """Every public function's page renders numpydoc's Parameters and Returns (and Raises where the docstring has
    it) as definition lists of names, not literal blocks.  Seen to fail with the Returns section removed from
    gali's docstring."""
    for name, dotted in _face_pages():
        obj = getattr(magrod, name)
        doc = NumpyDocString(inspect.getdoc(obj) or "")
        want = {s for s in ("Parameters", "Returns", "Raises") if doc[s]}
        if not isinstance(obj, type):
            assert {"Parameters", "Returns"} <= want, (name, want)
        fields = _fields(_entry(site, dotted))
        for section in sorted(want):
            assert section in fields, (name, section, sorted(fields))
            body = fields[section].find("dl")
            assert body is not None and body.find("dt") is not None, (name, section)
            assert not fields[section].find("pre"), (name, section)
        if "Parameters" in want:
            assert fields["Parameters"].find("dl").find("dt").find("strong"), name


def _listed(dd) -> set:
    """The names of a Parameters/Attributes list ("theta0, ptheta0, psi0 : float" names three)."""
    return {n.strip() for dt in dd.find("dl").find_all("dt", recursive=False)
            for n in dt.find(["strong", "a"]).get_text("", strip=True).split(",")}


def test_result_type_pages_list_attributes_and_methods(site):
    """A result type's page lists every field and property under Attributes (name, type, what it is) and its
    methods -- to_dict, to_xarray, plot, save included -- under Methods, each linked to its entry on the page.
    Every entry says what it is.  Seen to fail without
    docs/_ext/magrod_api.py's member tables (LyapunovResult: no Attributes), with one field (casimir_drift) left
    out of the table, and on ChaosMap before its fields' comments (spec: no description)."""
    import dataclasses

    from magrod.core.results import Result

    for dotted, cls in _result_types().items():
        dl = _entry(site, dotted)
        fields = _fields(dl)
        if dataclasses.is_dataclass(cls):
            assert "Attributes" in fields or "Parameters" in fields, (dotted, sorted(fields))
            shown = set().union(*(_listed(fields[s]) for s in ("Attributes", "Parameters") if s in fields))
            want = {f.name for f in dataclasses.fields(cls) if not f.name.startswith("_")}
            assert want <= shown, (dotted, sorted(want - shown))
        for s in ("Attributes", "Parameters"):
            for dd in (fields[s].find("dl").find_all("dd", recursive=False) if s in fields else []):
                text = dd.get_text(strip=True)  # "Default 0.0." alone is no description
                assert len(text) > 5 and not text.startswith("Default"), (
                    dotted, dd.find_previous_sibling("dt").get_text())
        if issubclass(cls, Result):
            page = _soup(_page(site, dotted))
            methods = page.find("p", class_="rubric", string="Methods")
            assert methods is not None, dotted
            table = methods.find_next("table")
            links = {a.get_text(strip=True): a["href"] for a in table.select("a")}
            for m in ("to_dict", "to_xarray", "plot", "save"):
                assert m in links and links[m].endswith(f"#{dotted}.{m}"), (dotted, m, links)
            assert page.find(id=f"{dotted}.to_xarray") is not None, dotted


OPTION_CLASSES = ("System", "RodParams", "SectionOptions", "SectionStart", "Precision", "ParameterError")


def test_every_documented_class_describes_every_field():
    """Every class the API reference documents (the face's, the option classes, every result type) describes each
    entry of its Parameters/Attributes tables, as docs/_ext/magrod_api.py builds them from the docstring and the
    fields' source comments: no empty entry, none that is only "Default x.".  Read from the code, without building
    the site (the site tests check the rendered pages).  Seen to fail with GenericTerm.formula's comment removed."""
    sys.path.insert(0, str(DOCS / "_ext"))
    try:
        import magrod_api
    finally:
        sys.path.remove(str(DOCS / "_ext"))
    import importlib

    bare = []
    for full in sorted(magrod_api.documented_classes().values()):
        mod, _, name = full.rpartition(".")
        cls = getattr(importlib.import_module(mod), name, None)
        if not isinstance(cls, type):
            continue
        text = magrod_api.class_sections(cls, inspect.getdoc(cls) or "")
        if not text:
            continue
        doc = NumpyDocString(text)
        for section in ("Parameters", "Attributes"):
            for p in doc[section]:
                desc = " ".join(p.desc).strip()
                if len(desc) <= 5 or desc.startswith("Default"):
                    bare.append(f"{full}.{p.name}")
    assert not bare, f"{len(bare)} entries say nothing: {bare}"


def test_parameter_and_option_classes_have_parameter_tables(site):
    """The parameter and option classes of the face (and MapSpec beside them) say what they take and hold in
    Parameters/Attributes tables, every field described.  Seen to fail with RodParams' docstring as it was (prose
    and Examples only: its table from the fields alone has no descriptions) and without the member tables
    (MapSpec: none)."""
    import dataclasses

    from magrod.chaos.maps import MapSpec

    for name, dotted, cls in [*((n, f"magrod.{n}", getattr(magrod, n)) for n in OPTION_CLASSES),
                              ("MapSpec", "magrod.chaos.maps.MapSpec", MapSpec)]:
        fields = _fields(_entry(site, dotted))
        tables = [fields[s] for s in ("Parameters", "Attributes") if s in fields]
        assert tables, (name, sorted(fields))
        if dataclasses.is_dataclass(cls):
            shown = set().union(*(_listed(t) for t in tables))
            assert {f.name for f in dataclasses.fields(cls)} <= shown, name
        if name in OPTION_CLASSES or name == "MapSpec":  # written by hand: every entry says what it is
            for t in tables:
                for dd in t.find("dl").find_all("dd", recursive=False):
                    text = dd.get_text(strip=True)  # "Default 0.0." alone is no description
                    assert len(text) > 5 and not text.startswith("Default"), (name, dd)


def test_a_function_returns_links_to_its_result_type(site):
    """The type in a function's Returns section is a link to the page of the result type (numpydoc's typed
    references): mr.poincare_section -> PoincareResult, mr.saddle -> StraightRod, PeriodicSaddle, Equilibrium.
    Seen to fail with numpydoc's typed references off (the type plain text: ChaosMap of chaos_map unlinked)."""
    types = {c.__name__: d for d, c in _result_types().items()}
    types.update({n: f"magrod.{n}" for n in magrod.__all__ if isinstance(getattr(magrod, n), type)})
    checked = 0
    for name, dotted in _face_pages():
        obj = getattr(magrod, name)
        if isinstance(obj, type):
            continue
        returns = _fields(_entry(site, dotted))["Returns"]
        links = {a.get_text(strip=True): a.get("href", "") for a in returns.select("a")}
        assert links, (name, "Returns links to no type")
        for p in NumpyDocString(inspect.getdoc(obj) or "")["Returns"]:
            for word in re.findall(r"\b[A-Z]\w+", p.type):
                if word in types:
                    assert word in links, (name, word, links)
                    target = links[word].split("#")
                    assert target[1] == types[word] and (_page(site, dotted).parent / target[0]).exists(), \
                        (name, word, links[word])
                    checked += 1
    assert checked >= 20, checked


def test_the_reference_names_no_internal_work_items(site):
    """The reference pages say what a thing is: no "issue N" (a reader has no tracker).  Seen to fail on the first
    build of the result pages (4 hits, from result docstrings and field comments)."""
    issue = re.compile(r"\b[Ii]ssues?[ -]?#?\d+")
    bad = {}
    for page in [site / "api.html", *sorted((site / "api").glob("*.html"))]:
        text = _soup(page).select_one("article").get_text(" ")
        hits = [" ".join(text[max(0, m.start() - 40):m.end() + 10].split()) for m in issue.finditer(text)]
        if hits:
            bad[page.name] = hits
    assert not bad, bad


EN_DASH_OPTION = re.compile(r"(?<![\w)\]])[\u2013\u2014][a-z]")  # "–json": smart quotes ate a "--"


def test_no_en_dash_option_names_anywhere(site):
    """Options are written with two hyphens on every page ("--json"), never with an en or em dash, which a shell
    rejects when pasted.  Seen to fail with Sphinx's default smartquotes_action (31 "–json" on the CLI page)."""
    bad = {}
    for page in sorted(site.rglob("*.html")):
        text = bs4.BeautifulSoup(page.read_text(), "html.parser").get_text()
        hits = sorted(set(m.group(0) + text[m.end():m.end() + 12].split()[0] if text[m.end():m.end() + 1].strip()
                          else m.group(0) for m in EN_DASH_OPTION.finditer(text)))
        if hits:
            bad[str(page.relative_to(site))] = hits[:10]
    assert not bad, bad
    assert "--json" in (site / "cli.html").read_text()


def test_no_raw_rest_on_any_page(site):
    bad = {str(p.relative_to(site)): _raw_rest_in(p.read_text()) for p in site.rglob("*.html")
           if not p.name.startswith(("genindex", "search", "py-modindex"))}
    bad = {k: v for k, v in bad.items() if v}
    assert not bad, bad


def test_screenshot_of_the_api_page(site):
    """A picture of the rendered reference (test-artifacts/api-page.png, $MAGROD_ARTIFACTS), taken in Debian's
    chromium headless from the built file (file://, no server, nothing fetched)."""
    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    if not Path(chromium).exists():
        pytest.skip("needs Debian's chromium")
    sync_api = pytest.importorskip("playwright.sync_api")
    out = Path(os.environ.get("MAGROD_ARTIFACTS", "test-artifacts"))
    out.mkdir(parents=True, exist_ok=True)
    png = out / "api-page.png"
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=chromium, headless=True,
                              args=["--no-sandbox", "--disable-gpu", "--disable-background-networking"])
        try:
            page = b.new_page(viewport={"width": 1300, "height": 1600})
            page.route("http*://**", lambda route: route.abort())  # loopback only: no fonts or scripts from outside
            page.goto((site / "api.html").as_uri())
            page.locator("table.autosummary").first.wait_for()
            n_rows = page.locator("table.autosummary tr").count()
            page.screenshot(path=str(png))
            page.goto(_page(site, "magrod.poincare_section").as_uri())
            page.locator("dl.py.function").first.wait_for()
            page.screenshot(path=str(out / "api-poincare_section.png"))
        finally:
            b.close()
    assert n_rows >= len(magrod.__all__), n_rows
    assert png.stat().st_size > 10_000


NAV_PARTS = ["Tutorials", "How-to", "API", "CLI", "Theory"]


def test_short_top_bar_and_a_sidebar_on_every_page(site):
    """The top bar holds the five parts and nothing else (no notebook titles, no "More" menu); every page's left
    sidebar holds the site's navigation (it was empty on every page).  Seen to fail before _templates/site-nav.html
    and the five-part root toctree (the bar held 13 entries in three rows, the sidebar 0 links)."""
    pages = sorted(p for p in site.rglob("*.html") if p.name not in ("genindex.html", "search.html")
                   and "_static" not in p.parts and "_modules" not in p.parts)
    assert len(pages) >= 10
    for p in pages:
        soup = bs4.BeautifulSoup(p.read_text(), "html.parser")
        bar = soup.select_one(".navbar-header-items .bd-navbar-elements")
        assert bar is not None, p.name
        assert [a.get_text(strip=True) for a in bar.select("li a")] == NAV_PARTS, p.name
        assert not bar.select(".dropdown"), p.name
        side = soup.select(".bd-sidebar-primary nav.bd-docs-nav a")
        assert len(side) >= 10, (p.name, len(side))


def test_an_anchor_is_not_hidden_by_the_header(site):
    """Following a link to an API entry (a method deep in a result type's page) leaves its signature clearly below
    the sticky header (in chromium, from the built file).  Seen to fail before _static/magrod.css (the signature's
    top at 79.8 px, under an 80 px header's edge)."""
    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    if not Path(chromium).exists():
        pytest.skip("needs Debian's chromium")
    sync_api = pytest.importorskip("playwright.sync_api")
    from magrod.chaos.section import PoincareResult

    owner = f"{PoincareResult.__module__}.PoincareResult"
    anchor = f"{owner}.to_xarray"  # the signature's id
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=chromium, headless=True,
                              args=["--no-sandbox", "--disable-gpu", "--disable-background-networking"])
        try:
            page = b.new_page(viewport={"width": 1400, "height": 900})
            page.route("http*://**", lambda route: route.abort())
            page.goto(_page(site, owner).as_uri() + f"#{anchor}")
            page.locator(f"[id='{anchor}']").first.wait_for()
            page.wait_for_timeout(300)  # the browser's scroll to the fragment
            header = page.evaluate("() => document.querySelector('header.bd-header').getBoundingClientRect().bottom")
            target = page.evaluate("(a) => document.getElementById(a).getBoundingClientRect().top", anchor)
        finally:
            b.close()
    assert target >= header + 8, (target, header)


def test_cli_reference_lists_every_subcommand(site):
    from magrod.cli import SUBCOMMANDS

    html = (site / "cli.html").read_text()
    for name in SUBCOMMANDS:
        assert f'id="magrod-{name}"' in html, name  # a section per subcommand, from the parser
    assert "--allow-remote" in html  # options come from the parsers


def test_notebooks_rendered_from_executed_cells(site):
    for nb, needle in (("quickstart", "points equal to poincare_section: True"), ("chaos", "single orbit"),
                       ("homoclinic", "figure6_N2.npz"), ("splitting", "log-log slope"),
                       ("your_own_rod", "re-checked exactly")):
        html = (site / "notebooks" / f"{nb}.html").read_text()
        assert needle in html, nb
        assert "Traceback" not in html, nb
    assert (site / "errata.html").exists() and (site / "theory" / "theorems.html").exists()
    assert (site / "architecture.html").exists()


def test_the_paper_is_cited_by_reference_not_by_a_path():
    """A user has the repository, not the authors' workspace: the README and the docs cite the paper by its
    reference (arXiv:0905.1309), never by a path outside the repository.  Seen to fail on the README's
    `../shared/paper/...` before."""
    pages = [*DOCS.rglob("*.md"), ROOT / "README.md"]
    bad = [f"{p.relative_to(ROOT)}:{i}" for p in pages for i, line in enumerate(p.read_text().splitlines(), 1)
           if "../shared" in line or "/work/shared" in line]
    assert not bad, bad
    assert "arXiv:0905.1309" in (ROOT / "README.md").read_text()


def test_no_unfilled_placeholders_in_the_prose():
    """A template marker such as @@BOXES@@ left in a document is a result that was promised and never written."""
    pages = [*DOCS.rglob("*.md"), ROOT / "README.md", ROOT / "benchmarks" / "README.md"]
    marker = re.compile(r"@@[A-Z_]+@@|\bTODO\b|\bTBD\b")
    found = [f"{p.relative_to(ROOT)}:{i}" for p in pages for i, line in enumerate(p.read_text().splitlines(), 1)
             if marker.search(line)]
    assert not found, found


def test_theory_pages_show_the_whole_source_once_in_readable_parts():
    """docs/nonintegrability.md (23 600 words) is shown as pages a reader can finish: each theory/*.md page includes
    one part (between two part markers), the parts follow each other from the first marker to the last (nothing
    left out, nothing twice), and no part exceeds 8000 words.  No docs build needed.  Seen to fail before the
    split (no markers, one page)."""
    src = (DOCS / "nonintegrability.md").read_text()
    markers = re.findall(r"<!-- part: ([\w-]+) -->", src)
    assert markers[0] == "splitting" and markers[-1] == "end" and len(markers) == len(set(markers))
    spans = {}
    for page in sorted((DOCS / "theory").glob("*.md")):
        m = re.search(r"```\{include\} \.\./nonintegrability\.md\n:start-after: <!-- part: ([\w-]+) -->\n"
                      r":end-before: <!-- part: ([\w-]+) -->\n```", page.read_text())
        assert m, page.name
        spans[m.group(1)] = m.group(2)
    assert [spans.get(a) for a in markers[:-1]] == markers[1:], spans
    for a, b in zip(markers, markers[1:]):
        words = len(src.split(f"<!-- part: {a} -->")[1].split(f"<!-- part: {b} -->")[0].split())
        assert words <= 8000, (a, words)
    toc = (DOCS / "theory.md").read_text()
    assert all(f"theory/{p.stem}" in toc for p in (DOCS / "theory").glob("*.md"))


def test_mathematics_is_rendered_as_mathematics(site):
    """The manifolds' names and exponentials are typeset ($W^u$ through myst's dollar math and MathJax), not shown
    as ASCII: the splitting page has math elements, and no prose of the theory pages outside code says W^u or W^s.
    Seen to fail before the conversion (112 ASCII occurrences, no math element).  The statements' own text
    (theory/theorems, rendered from magrod/proof/statements.py) too: its math elements are MathJax's, and no
    TeX escape leaked into its prose."""
    soup = bs4.BeautifulSoup((site / "theory" / "splitting.html").read_text(), "html.parser")
    assert len(soup.select("span.math")) >= 10
    for name in ("splitting", "theorems", "proof", "fig4-level", "fig4-intervals", "fig5-level", "remains"):
        soup = bs4.BeautifulSoup((site / "theory" / f"{name}.html").read_text(), "html.parser")
        art = soup.select_one("article")
        if name == "theorems":
            assert len(art.select("span.math")) >= 100
        for code in art.select("code, pre, span.math, div.math"):
            code.decompose()
        assert not re.search(r"\bW\^[us]\b", art.get_text()), name
        assert not re.search(r"\\(bar|lambda|mu|theta|psi|in|neq|Rightarrow)\b", art.get_text()), name


TOPICS = ("Systems and parameters", "Sections and chaos", "Orbits", "Splitting", "Integrability", "Proofs",
          "Explorer", "Result types")


def test_api_page_opens_with_summary_tables_by_topic(site):
    """The API page is summary tables by topic (as scipy's references), each row a name linked to its page and the
    first line of its docstring; every public name and every result type is in one.  Seen to fail before (one
    page of 24 entries, 38 000 px, no page per name) and with a name dropped from the topics."""
    soup = bs4.BeautifulSoup((site / "api.html").read_text(), "html.parser")
    heads = [h.get_text(strip=True).rstrip("#") for h in soup.select("article section > h2")]
    assert "Other names" not in heads, "a public name has no topic: add it to TOPICS in docs/_ext/magrod_api.py"
    assert heads == [*TOPICS, "The second tier"], heads
    rows = soup.select("article table.autosummary tr")
    linked = {}
    for r in rows:
        a = r.select_one("a")
        assert a is not None and len(r.select("td")[1].get_text(strip=True)) > 10, r
        page, _, anchor = a["href"].partition("#")
        assert (site / page).exists(), page
        linked[anchor] = page
    for _, dotted in _face_pages():
        assert dotted in linked, dotted
    for dotted in _result_types():
        assert dotted in linked, dotted
