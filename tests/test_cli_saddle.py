"""`magrod saddle` (the worked example of docs/architecture.md, "Adding a subcommand"): a thin client of
`mr.saddle`: the command's numbers are the library's, bit for bit, and at lambdabar = 0 the straight rod's level and
rate are the closed forms of generated/scalars.py (eq:eq_oscillator, report entry saddle_rate)."""
import json

import pytest

import magrod as mr
from magrod import cli
from magrod.generated import scalars


def _run(argv, capsys):
    rc = cli.main(["saddle", *argv, "--json"])
    return rc, json.loads(capsys.readouterr().out)


def test_the_command_prints_the_library_result(capsys):
    rc, d = _run(["--panel", "4a"], capsys)
    s = mr.saddle(mr.panel("4a").params)
    assert rc == 0 and d["ok"] and d["kind"] == "periodic"
    assert d["H"] == s.H and d["T"] == s.T and d["accuracy"]["passed"]


def test_the_straight_rod_at_lambdabar_zero_is_the_closed_form(capsys):
    rc, d = _run(["--m", "1.7", "--mu", "0", "--gamma", "1", "--delta", "1", "--lam", "0"], capsys)
    assert rc == 0 and d["kind"] == "equilibrium"
    assert d["H"] == pytest.approx(scalars.homoclinic_energy(1.7, 1.0), rel=1e-14)
    assert d["unstable_eigenvalue"][0] == pytest.approx(scalars.saddle_rate(1.7, 1.0), rel=1e-12)


def test_without_a_panel_the_rod_is_fig_4a_with_the_values_given(capsys):
    """One default panel for every command that takes one (4a): `saddle --m 1.8` is Fig 4(a)'s rod with m = 1.8."""
    rc, d = _run(["--m", "1.8"], capsys)
    ref = mr.saddle(mr.panel("4a").params.replace(m=1.8)).to_dict()
    assert rc == 0 and d["params"] == ref["params"] and d["H"] == ref["H"]


@pytest.mark.parametrize("argv, name", [(["--m", "1.7", "--mu", "nan"], "mu"), (["--panel", "9z"], "panel"),
                                        (["--panel", "4a", "--mu", "0.1"], "mu"), (["--panel", "4a", "--m", "x"], "m")])
def test_bad_input_names_the_parameter(argv, name, capsys):
    rc, d = _run(argv, capsys)
    assert rc == 2 and d["parameter"] == name
