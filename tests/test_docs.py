"""The documentation site builds with warnings as errors, its notebooks executed (myst-nb, a failing cell fails the
build), the API reference covers magrod.__all__ and the CLI reference every subcommand (both generated, not typed).
This is the README's docs command; it takes ~1-2 min on 2 cores (the four notebooks dominate)."""
from __future__ import annotations

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


def test_api_reference_covers_the_public_names(site):
    html = (site / "api.html").read_text()
    for name in magrod.__all__:
        assert f'id="mr-{name.lower().replace("_", "-")}"' in html, name
    # numpydoc rendered the sections of a function docstring
    assert "Parameters" in html and "Examples" in html and "Raises" in html


# what reST looks like when a page shows it instead of rendering it (autodoc output inside a MyST page)
RAW_REST = (".. py:", ":Parameters:", ":Returns:", "!! processed by numpydoc", ":module:", ".. autofunction",
            ".. autoclass")


def _raw_rest_in(html_text: str) -> list[str]:
    text = bs4.BeautifulSoup(html_text, "html.parser").get_text()
    return [m for m in RAW_REST if m in text]


def test_api_reference_renders_entries_not_raw_rest(site):
    """Every name of magrod.__all__ is a real Sphinx entry (<dl class="py function|class"> whose <dt> carries the
    object's dotted id), its numpydoc Parameters and Returns are definition lists, and no reST markup shows as
    text.  Seen to fail on the api.md page this replaced: 0 dl.py entries and all seven markers present."""
    html = (site / "api.html").read_text()
    assert not _raw_rest_in(html), _raw_rest_in(html)
    soup = bs4.BeautifulSoup(html, "html.parser")
    entries = {dt.get("id"): dt.parent for dl in soup.select("dl.py") for dt in dl.find_all("dt", recursive=False)
               if dt.get("id")}
    for name in magrod.__all__:
        obj = getattr(magrod, name)
        ident = f"{obj.__module__}.{obj.__qualname__}"
        assert ident in entries, f"no dl.py entry for mr.{name} ({ident})"
        dl = entries[ident]
        assert "py" in dl["class"] and ({"function", "class"} & set(dl["class"])), (name, dl["class"])
        fields = {dt.get_text(strip=True).rstrip(":"): dt.find_next_sibling("dd")
                  for fl in dl.select("dd > dl.field-list") for dt in fl.find_all("dt", recursive=False)}
        # the sections the docstring has (functions: at least Parameters and Returns) each render as a field whose
        # body is a definition list of names (<dt><strong>name</strong> : type), not a literal block
        doc = NumpyDocString(inspect.getdoc(obj) or "")
        want = {s for s in ("Parameters", "Returns", "Raises") if doc[s]}
        if not isinstance(obj, type):
            assert {"Parameters", "Returns"} <= want, (name, want)
        for section in sorted(want):
            assert section in fields, (name, section, sorted(fields))
            body = fields[section].find("dl")
            assert body is not None and body.find("dt") is not None, (name, section)
            assert not fields[section].find("pre"), (name, section)
        if "Parameters" in want:
            assert fields["Parameters"].find("dl").find("dt").find("strong"), name


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
            page.locator("dl.py.function").first.wait_for()
            n_entries = page.locator("dl.py").count()
            page.locator("dl.py.function").first.scroll_into_view_if_needed()
            page.screenshot(path=str(png))
        finally:
            b.close()
    assert n_entries >= len(magrod.__all__), n_entries
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
    """Following a link to an API entry leaves its signature clearly below the sticky header (in chromium, from the
    built file).  Seen to fail before _static/magrod.css (the signature's top at 79.8 px, under an 80 px header's
    edge)."""
    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    if not Path(chromium).exists():
        pytest.skip("needs Debian's chromium")
    sync_api = pytest.importorskip("playwright.sync_api")
    fn = magrod.poincare_section
    anchor = f"{fn.__module__}.{fn.__qualname__}"  # the signature's id
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=chromium, headless=True,
                              args=["--no-sandbox", "--disable-gpu", "--disable-background-networking"])
        try:
            page = b.new_page(viewport={"width": 1400, "height": 900})
            page.route("http*://**", lambda route: route.abort())
            page.goto((site / "api.html").as_uri() + f"#{anchor}")
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
    for name in ("splitting", "theorems", "proof", "fig4-level", "fig5-level", "remains"):
        soup = bs4.BeautifulSoup((site / "theory" / f"{name}.html").read_text(), "html.parser")
        art = soup.select_one("article")
        if name == "theorems":
            assert len(art.select("span.math")) >= 100
        for code in art.select("code, pre, span.math, div.math"):
            code.decompose()
        assert not re.search(r"\bW\^[us]\b", art.get_text()), name
        assert not re.search(r"\\(bar|lambda|mu|theta|psi|in|neq|Rightarrow)\b", art.get_text()), name


def test_api_page_opens_with_a_summary_table(site):
    """The API page opens with a table of every public name (linked to its entry) and its one-line summary, as
    scipy's references do.  Seen to fail before (no table: 24 entries one under the other, 38 000 px)."""
    soup = bs4.BeautifulSoup((site / "api.html").read_text(), "html.parser")
    table = soup.select_one("article table")
    assert table is not None
    rows = table.select("tbody tr")
    ids = {x["id"] for x in soup.select("[id]")}
    names = [r.select_one("a").get_text(strip=True) for r in rows]
    assert names == [f"mr.{n}" for n in magrod.__all__]
    assert all(r.select_one("a")["href"].lstrip("#") in ids for r in rows)
    assert all(len(r.select("td")[2].get_text(strip=True)) > 10 for r in rows)
