"""Figures for a paper: `--format png|pdf|svg` (figures.build(formats=...)), reproducible picture bytes, data files
that do not depend on the format, and a failed figure that leaves none of its files behind (REPORT.md marks its
claims as failed).  Figure 2 --quick is the cheapest real builder (~4 s)."""
from __future__ import annotations

import json
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from magrod.core.errors import ParameterError
from magrod.figures import FIGURES, build
from magrod.figures.common import figure_formats, parse_formats


@pytest.fixture(scope="module")
def fig2(tmp_path_factory):
    png = tmp_path_factory.mktemp("png")
    vec = tmp_path_factory.mktemp("vec")
    a = build("2", png, quick=True)
    b = build("2", vec, quick=True, formats=("pdf", "svg"))
    return png, vec, a, b


def test_formats_written_and_data_identical(fig2):
    png, vec, a, b = fig2
    assert sorted(p.name for p in png.iterdir()) == ["fig2.json", "fig2.npz", "fig2.png"]
    assert sorted(p.name for p in vec.iterdir()) == ["fig2.json", "fig2.npz", "fig2.pdf", "fig2.svg"]
    assert sorted(b) == sorted(str(p) for p in vec.iterdir())  # every file written is reported
    assert (png / "fig2.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (vec / "fig2.pdf").read_bytes()[:5] == b"%PDF-"
    root = ET.fromstring((vec / "fig2.svg").read_bytes())
    assert root.tag.endswith("svg")
    # the data file is the same bytes whatever the picture format; the sidecar differs only in timings
    assert (png / "fig2.npz").read_bytes() == (vec / "fig2.npz").read_bytes()
    ja, jb = (json.loads((d / "fig2.json").read_text()) for d in (png, vec))

    def drop_times(o):
        if isinstance(o, dict):
            return {k: drop_times(v) for k, v in o.items() if "wall" not in k and not k.endswith("_s")}
        return [drop_times(v) for v in o] if isinstance(o, list) else o

    assert drop_times(ja) == drop_times(jb)


def test_vector_pictures_are_reproducible(tmp_path):
    """The same figure saved twice gives the same PDF and SVG bytes (no dates; SVG ids from a fixed salt:
    matplotlib's default salt is a fresh uuid4 per save).  Seen to fail with the rc_context of the salt removed
    from figures.common.atomic_savefig (the clip-path ids differ)."""
    from matplotlib.figure import Figure

    from magrod.figures.common import atomic_savefig

    def draw(d):
        fig = Figure(figsize=(3, 2))
        ax = fig.add_subplot()
        ax.plot(np.linspace(0, 1, 50), np.linspace(0, 1, 50) ** 2, "o-")
        ax.set_title("x")
        d.mkdir()
        with figure_formats(("pdf", "svg")):
            return atomic_savefig(fig, d / "f.png")

    first, second = draw(tmp_path / "a"), draw(tmp_path / "b")
    assert first.name == "f.pdf" and second.name == "f.pdf"
    for name in ("f.pdf", "f.svg"):
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes(), name


@pytest.mark.parametrize("bad", ["jpg", "", "png,png", "png,,pdf", ["eps"]])
def test_bad_format_names_the_parameter(bad):
    with pytest.raises(ParameterError, match="format"):
        parse_formats(bad)


def test_format_parsing():
    assert parse_formats("PDF, svg") == ("pdf", "svg") and parse_formats(("png",)) == ("png",)


def test_a_failed_figure_leaves_none_of_its_files(tmp_path, monkeypatch):
    """A builder that wrote data, a sidecar and a picture and then failed: figures.build removes all three (also
    one that replaced a file of an earlier run) and re-raises.  Seen to fail with the cleanup in build() removed
    (the three files stayed)."""
    import magrod.figures as figures
    from matplotlib.figure import Figure

    from magrod.core.io import atomic_savez, atomic_write_json
    from magrod.figures.common import atomic_savefig

    (tmp_path / "boom.json").write_text("{}")  # from an earlier, successful run
    (tmp_path / "other.txt").write_text("not ours")

    def boom(out, *, quick=False, progress=False):
        atomic_savez(out / "boom.npz", x=np.arange(3))
        atomic_write_json(out / "boom.json", {"ok": True})
        atomic_savefig(Figure(figsize=(1, 1)), out / "boom.png")
        raise RuntimeError("the builder failed after writing")

    monkeypatch.setitem(FIGURES, "boom", ("magrod.figures.common", "boom", "test"))
    import magrod.figures.common as common

    monkeypatch.setattr(common, "boom", boom, raising=False)
    with pytest.raises(RuntimeError, match="builder failed"):
        figures.build("boom", tmp_path, formats=("png", "svg"))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["other.txt"]


def test_report_marks_the_claims_of_a_failed_figure(fig2):
    """REPORT.md's rows that rest on a failed figure say FAILED, never 'computed' from files that are left.  Seen
    to fail before mark_failed existed (the row of Figure 2 read as reproduced from the sidecar)."""
    from magrod.figures.report import claims, report_markdown

    png, _, _, _ = fig2
    rows = claims(png, True)
    mel = [r for r in rows if r["label"] == "fig:Mel_ext"]
    assert mel and mel[0]["verdict"] != "failed" and mel[0]["figures"] == ["2"]
    text = report_markdown(rows, {}, {"2": "RuntimeError: boom", "6": "ValueError: x"}, True, 1.0)
    def details(label):  # the claim's row in the table (its verdict word) and its details (the full text)
        k, row = next((k, ln) for k, ln in enumerate(text.splitlines()) if f"| {label} |" in ln and ln.startswith("| ["))
        anchor = row.split("](#")[1].split(")")[0]
        block = text.split(f'<a id="{anchor}"></a>')[1].split("<a id=")[0]
        return row, block

    row, block = details("fig:Mel_ext")
    assert "figure 2 FAILED: RuntimeError: boom" in block and row.rstrip().endswith("| failed |")
    assert "- Figure 2: FAILED" in text
    fig6, fig7 = details("fig:multimodal1")[1], details("fig:multimodal2")[1]
    table = next(details(r["label"])[1] for r in rows if r["label"].startswith("branch table"))
    assert "figure 6 FAILED" in fig6 and "FAILED" not in fig7 and "figure 6 FAILED" in table


def test_cli_format_options(tmp_path, capsys):
    """`magrod figure 2 --quick --format svg` writes fig2.svg (and the data); a bad --format on `figure` or
    `reproduce` is one line naming it, exit 2, before any directory is made."""
    from magrod import cli

    out = tmp_path / "svg"
    assert cli.main(["figure", "2", "--quick", "--format", "svg", "--out", str(out), "--json", "--quiet"]) == 0
    r = json.loads(capsys.readouterr().out)
    assert r["formats"] == ["svg"] and sorted(p.name for p in out.iterdir()) == ["fig2.json", "fig2.npz", "fig2.svg"]
    for argv in (["figure", "2", "--format", "gif"], ["reproduce", "--quick", "--format", "png,gif"]):
        bad = tmp_path / "never"
        assert cli.main([*argv, "--out", str(bad)]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "format" in err[0], err
        assert not bad.exists()
