"""Every command takes --model (issue 26, item 3).  check, poincare, chaosmap, landscape and models compute for any
model; the others compute for the paper's rod only and say so, by name and with the reason, before anything runs
(exit 2, one line, one JSON object, nothing written; a model file is never loaded for them)."""
import json

import pytest

from magrod import cli

REQUIRED = {"homoclinic": ["--m", "1.7", "--gamma", "1"], "melnikov": ["--m", "1.7"], "figure": ["2"],
            "rod": ["--from", "x.npz"], "orbitdiagram": ["--parameter", "lam", "--values", "0.135,0.15"]}


@pytest.mark.parametrize("command", sorted(cli.PAPER_ONLY))
def test_a_paper_only_command_names_the_model_and_the_reason(command, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    rc = cli.main([command, *REQUIRED.get(command, []), "--model", "kirchhoff", "--json"])
    cap = capsys.readouterr()
    obj = json.loads(cap.out)
    lines = [ln for ln in cap.err.splitlines() if ln.strip()]
    assert rc == 2 and obj["parameter"] == "model" and len(lines) == 1, (obj, lines)
    structure, why = cli.PAPER_ONLY[command]  # the structure the model lacks, and why: named
    assert "'kirchhoff' has none" in lines[0] and structure in lines[0] and why in lines[0]
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_a_model_file_is_not_loaded_by_a_paper_only_command(tmp_path, capsys):
    f = tmp_path / "my_rod.py"
    f.write_text("raise SystemExit('this file must not run')\n")
    rc = cli.main(["splitting", "--model", str(f), "--json"])
    assert rc == 2 and json.loads(capsys.readouterr().out)["parameter"] == "model"


@pytest.mark.parametrize("command", sorted(cli.PAPER_ONLY))
def test_an_unknown_model_is_named_unknown_by_every_command(command, tmp_path, capsys, monkeypatch):
    """Before, a paper-only command gave the same message for --model nosuch as for --model kirchhoff."""
    monkeypatch.chdir(tmp_path)
    rc = cli.main([command, *REQUIRED.get(command, []), "--model", "nosuch", "--json"])
    obj = json.loads(capsys.readouterr().out)
    assert rc == 2 and obj["parameter"] == "model" and "unknown model 'nosuch'" in obj["error"], obj
    assert list(tmp_path.iterdir()) == []


def test_the_paper_rod_by_name_is_the_default(capsys):
    rc = cli.main(["homoclinic", "--m", "1.7", "--gamma", "1", "--model", cli.DEFAULT_MODEL, "--json"])
    assert rc == 0 and json.loads(capsys.readouterr().out)["m"] == 1.7


# a command of the orbit wing run on another model, the extra options of its run, the library function it calls and
# how its output compares with the library's result
MODEL_RUNS = {
    "saddle": ([], "saddle", lambda d, ref: d["kind"] == ref.kind == "saddle-focus" and d["H"] == float(ref.H)
               and d["accuracy"]["passed"]),
    "spectrum": (["--t-max", "50"], "lyapunov_spectrum", lambda d, ref: d["exponents"] == ref.exponents.tolist()
                 and d["model"] == "anisotropic" and abs(sum(d["exponents"])) < 1e-6),
}


@pytest.mark.parametrize("command", sorted(MODEL_RUNS))
def test_an_orbit_command_runs_another_model(command, capsys):
    """`magrod saddle --model anisotropic` and `magrod spectrum --model ...`: the numbers are the library's."""
    import magrod as mr

    extra, fn_name, agrees = MODEL_RUNS[command]
    assert cli.routes_models(command)
    argv = [command, "--model", "anisotropic", "--model-params", "B1=1,B2=1.02,C=1.5", *extra, "--json"]
    rc = cli.main(argv)
    d = json.loads(capsys.readouterr().out)
    system = mr.System("anisotropic", B1=1, B2=1.02, C=1.5)
    fn = getattr(mr, fn_name)
    ref = fn(system, t_max=50.0) if command == "spectrum" else fn(system)
    assert rc == 0 and agrees(d, ref), d
