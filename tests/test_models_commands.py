"""Every command takes --model.  The commands compute for any model, each through the library's one engine (the
numbers they print are the library's, with the result's accuracy evidence); a step that needs a structure the model
lacks names the model and the structure (exit 2, one line, one JSON object, nothing written).  The commands about the
paper itself (its figures, its claims, the proofs on its validated fields) say so before anything runs (a model file
is never loaded for them)."""
import json
import shutil
from pathlib import Path

import numpy as np
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
    rc = cli.main(["figure", "2", "--model", str(f), "--json"])
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


# ---- the orbit wing's commands on another model: the library's numbers, with their evidence -------------------------
ANISO = ["--model", "anisotropic", "--model-params", "B1=1,B2=1.02,C=1.5"]
MODEL_FILE = Path(__file__).parent / "model_files" / "gyro_rod.py"


def _run(argv, capsys):
    rc = cli.main([*argv, "--json"])
    cap = capsys.readouterr()
    return rc, json.loads(cap.out), [ln for ln in cap.err.splitlines() if ln.strip()]


@pytest.fixture(scope="module")
def aniso():
    import magrod as mr

    return mr.System("anisotropic", B1=1, B2=1.02, C=1.5)


def test_homoclinic_and_rod_of_another_model(aniso, tmp_path, capsys):
    """`homoclinic --model` is mr.homoclinic_orbit's orbit (the same launch angle and half time, bit for bit) with
    its evidence; its orbit file records the model and parameters, and `rod --from` it is mr.rod_shape's rod of the
    same orbit.  A different model or parameter value for the file is refused by name, writing nothing."""
    import magrod as mr

    rc, d, _ = _run(["homoclinic", *ANISO, "--out", str(tmp_path / "h")], capsys)
    o = mr.homoclinic_orbit(aniso)
    assert rc == 0 and d["ok"] and d["model"] == "anisotropic" and d["params"] == aniso.params, d
    assert (d["alpha"], d["T"]) == (o.alpha, o.T) and d["accuracy"] == o.accuracy and d["accuracy"]["passed"]
    assert d["saddle"]["kind"] == "saddle-focus" and d["saddle"]["H"] == o.equilibrium.H
    npz = tmp_path / "h" / "homoclinic_orbit.npz"
    assert str(npz) in d["orbit_files"]
    side = json.loads((tmp_path / "h" / "homoclinic_orbit.json").read_text())
    assert side["model"] == "anisotropic" and side["params"] == aniso.params
    rc, r, _ = _run(["rod", "--from", str(npz), "--out", str(tmp_path / "r"), "--points", "200"], capsys)
    ref = mr.rod_shape(aniso, o, n=200)
    assert rc == 0 and r["model"] == "anisotropic" and r["params"] == aniso.params, r
    assert (r["length"], r["end_to_end"]) == (ref.length, ref.end_to_end)
    assert r["accuracy"]["orthonormality"] <= 1e-12 and r["accuracy"]["field_consistency"] <= 1e-12
    assert r["accuracy"]["orbit"]["passed"] and r["accuracy"]["launch_point_gap"] <= 1e-15
    # the file belongs to its model and parameters
    for extra, param in ((["--model-params", "B2=1.03"], "B2"), (["--model", "curved"], "model")):
        rc, e, lines = _run(["rod", "--from", str(npz), "--out", str(tmp_path / "bad"), *extra], capsys)
        assert rc == 2 and e["parameter"] == param and len(lines) == 1, e
        assert not (tmp_path / "bad").exists()
    # the orbit is re-shot from the file's unknowns, not trusted: a launch point the model does not reproduce (an
    # edited model file, a tampered orbit file) is refused
    with np.load(npz) as z:
        arrays = dict(z)
    arrays["x0"] = arrays["x0"] + 1e-9
    np.savez(tmp_path / "tampered.npz", **arrays)
    rc, e, _ = _run(["rod", "--from", str(tmp_path / "tampered.npz"), "--out", str(tmp_path / "bad")], capsys)
    assert rc == 2 and e["parameter"] == "from" and "not reproduced" in e["error"], e


def test_multipulse_of_another_model(tmp_path, capsys):
    """`multipulse --model`: the orbits of mr.multipulse_orbits (pulses, alpha, T), each with its evidence and its orbit
    file; the paper's scan options are refused by name."""
    import magrod as mr

    s = mr.System("anisotropic", B1=1, B2=1.2, C=1.5)
    rc, d, _ = _run(["multipulse", "--model", "anisotropic", "--model-params", "B1=1,B2=1.2,C=1.5", "--pulses", "2",
                     "--samples", "48", "--out", str(tmp_path)], capsys)
    found = mr.multipulse_orbits(s, 2, samples=48)
    assert rc == 0 and d["ok"] and d["pulses"] == found.pulses and 2 in d["pulses"], d
    assert [(o["alpha"], o["T"]) for o in d["orbits"]] == [(o.alpha, o.T) for o in found]
    assert all(o["accuracy"]["passed"] and len(o["orbit_files"]) == 2 for o in d["orbits"])
    rc, e, lines = _run(["multipulse", *ANISO, "--free", "lam", "--out", str(tmp_path / "x")], capsys)
    assert rc == 2 and e["parameter"] == "free" and "'anisotropic'" in lines[0] and not (tmp_path / "x").exists()


def test_continue_of_another_model(aniso, tmp_path, capsys):
    """`continue --model --free B2`: mr.continue_branch's branch of the homoclinic orbit (every point), with its
    residuals; --equilibria continues the straight rod."""
    import magrod as mr

    rc, d, _ = _run(["continue", *ANISO, "--free", "B2", "--steps", "2", "--ds", "0.02", "--out", str(tmp_path)],
                    capsys)
    br = mr.continue_branch(aniso, mr.homoclinic_orbit(aniso), parameter="B2", steps=2, ds=0.02)
    assert rc == 0 and d["ok"] and d["points"] == br.points == 3, d
    assert d["last"] == dict(zip(br.names, map(float, br.u[-1]))) and d["first"]["B2"] == 1.02
    assert d["accuracy"] == br.accuracy and d["max_residual"] <= 1e-9 and d["start_accuracy"]["passed"]
    assert np.array_equal(np.load(tmp_path / "branch_N1_B2.npz")["u"], br.u)
    rc, e, _ = _run(["continue", *ANISO, "--free", "C", "--equilibria", "--steps", "2", "--out", str(tmp_path)],
                    capsys)
    ref = mr.continue_branch(aniso, mr.saddle(aniso), parameter="C", steps=2)
    assert rc == 0 and e["kind"] == "equilibrium branch" and e["last"] == dict(zip(ref.names, map(float, ref.u[-1])))


def test_orbitdiagram_of_another_model(aniso, tmp_path, capsys):
    """`orbitdiagram --model --parameter B2`: mr.orbit_diagram's points (in the .npz it writes) and conservation
    budget; a start of the paper's chart is refused by name."""
    import magrod as mr

    rc, d, _ = _run(["orbitdiagram", *ANISO, "--parameter", "B2", "--values", "1,1.1", "--iterates", "20", "--out",
                     str(tmp_path)], capsys)
    od = mr.orbit_diagram(aniso, "B2", [1.0, 1.1], iterates=20)
    assert rc == 0 and d["ok"] and d["points"] == od.points.shape[0] == 40 and d["coordinate"] == "m2", d
    assert d["accuracy"] == od.accuracy and d["accuracy"]["passed"] and d["max_abs_dH"] == od.worst_dH
    assert np.array_equal(np.load(d["output"]["npz"])["points"], od.points)
    rc, e, _ = _run(["orbitdiagram", *ANISO, "--parameter", "B2", "--values", "1,1.1", "--theta0", "1"], capsys)
    assert rc == 2 and e["parameter"] == "theta0"


def test_splitting_and_melnikov_of_another_model(aniso, capsys):
    """`splitting --model` is mr.splitting's Mel'nikov measurement; `melnikov --model` is the Mel'nikov function
    along the computed orbit, whose sin 2 phi0 coefficient is the closed form of model_splitting (per unit B2)."""
    import magrod as mr
    from magrod.separatrix import melnikov_along_orbit
    from magrod.separatrix.model_splitting import melnikov_unit

    rc, d, _ = _run(["splitting", *ANISO, "--eps", "0.02,0.01"], capsys)
    spl = mr.splitting(aniso, eps=[0.02, 0.01])
    assert rc == 0 and d["ok"] and d["measure"] == spl.measure.tolist() and d["accuracy"]["passed"], d
    assert d["perturbation"] == "B2 = B1 (1 + eps)"
    rc, m, _ = _run(["melnikov", *ANISO, "--parameter", "B2", "--value0", "1"], capsys)
    ref = melnikov_along_orbit(aniso, "B2", 1.0)
    assert rc == 0 and m["ok"] and m["coefficients"] == ref.coefficients.tolist() and m["harmonic"] == 2, m
    c = melnikov_unit("anisotropic", {"B1": 1.0, "C": 1.5}, 1.0, 1.0)
    assert abs(m["sin_coefficient"] - c) <= 2e-6 * abs(c) and m["accuracy"]["passed"]


@pytest.mark.parametrize("argv, structure", [
    (["splitting", "--model", "kirchhoff"], "a small parameter"),  # integrable: no small parameter
    (["melnikov", "--model", "magnetic", "--parameter", "lam", "--value0", "0"], "a saddle"),  # degenerate at lam = 0
])
def test_a_missing_structure_is_named(argv, structure, tmp_path, capsys, monkeypatch):
    """exit 2, one stderr line naming the model and the structure, one JSON object with it, nothing written."""
    monkeypatch.chdir(tmp_path)
    rc, e, lines = _run(argv, capsys)
    model = argv[argv.index("--model") + 1]
    assert rc == 2 and e["parameter"] == "model" and e["structure"] == structure, e
    assert len(lines) == 1 and repr(model) in lines[0] and structure in lines[0]
    assert list(tmp_path.iterdir()) == []


def test_a_model_file_runs_the_orbit_commands(tmp_path, capsys, monkeypatch):
    """A model file outside the registry (a gyrostat rod): `homoclinic --model FILE` is mr.homoclinic_orbit's orbit,
    and `rod --from` its orbit file rebuilds the file's model."""
    import magrod as mr
    from magrod.core import models

    monkeypatch.setenv(models.CACHE_ENV, str(tmp_path / "cache"))
    f = tmp_path / "gyro_rod.py"
    shutil.copy(MODEL_FILE, f)
    rc, d, _ = _run(["homoclinic", "--model", str(f), "--model-params", "K=0.2", "--out", str(tmp_path / "h")], capsys)
    s = mr.System(str(f), K=0.2)
    o = mr.homoclinic_orbit(s)
    assert rc == 0 and d["ok"] and d["model"] == s.model and (d["alpha"], d["T"]) == (o.alpha, o.T), d
    rc, r, _ = _run(["rod", "--from", str(tmp_path / "h" / "homoclinic_orbit.npz"), "--out", str(tmp_path / "r"),
                     "--points", "100"], capsys)
    assert rc == 0 and r["model"] == s.model and r["params"]["K"] == 0.2 and r["accuracy"]["orthonormality"] <= 1e-12
