"""The documentation site builds with warnings as errors, its notebooks executed (myst-nb, a failing cell fails the
build), the API reference covers magrod.__all__ and the CLI reference every subcommand (both generated, not typed).
This is the README's docs command; it takes ~1-2 min on 2 cores (the four notebooks dominate)."""
from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

import magrod

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"

pytest.importorskip("sphinx")
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
    assert (site / "errata.html").exists() and (site / "nonintegrability.html").exists()
    assert (site / "architecture.html").exists()


def test_no_unfilled_placeholders_in_the_prose():
    """A template marker such as @@BOXES@@ left in a document is a result that was promised and never written."""
    pages = [*DOCS.rglob("*.md"), ROOT / "README.md", ROOT / "benchmarks" / "README.md"]
    marker = re.compile(r"@@[A-Z_]+@@|\bTODO\b|\bTBD\b")
    found = [f"{p.relative_to(ROOT)}:{i}" for p in pages for i, line in enumerate(p.read_text().splitlines(), 1)
             if marker.search(line)]
    assert not found, found
