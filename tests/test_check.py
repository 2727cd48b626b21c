"""`magrod check` CLI contract, the custom-model integrability check, and the no-SymPy-in-numerics rule."""
import json
import subprocess
import tempfile
import sys


from helpers import run_cli
from magrod import cli



def test_check_json_is_one_object():
    r = run_cli("check", "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)  # exactly one JSON object on stdout
    assert out["ok"] is True
    keys = {x["key"] for x in out["results"]}
    assert {"casimirs", "involution", "poisson_map", "I2bar_conservation"} <= keys
    assert "melnikov_vanishes" in out["disagreements_with_paper"]


def test_check_text_mentions_regimes(capsys):
    assert cli.main(["check"]) == 0
    text = capsys.readouterr().out
    assert "isotropic, inextensible/unshearable: all brackets vanish" in text


def test_check_custom_substitution(capsys):
    # inextensible, unshearable, isotropic: H, I1, I2 in involution (eq:int2)
    assert cli.main(["check", "--json", "--subs", "B2=B1,c_J=0,c_H=0,c_K=0"]) == 0
    out = json.loads(capsys.readouterr().out)
    table = list(out["results"][0]["details"]["tables"].values())[0]
    assert table["{H,I2}"] == "0" and table["{H,I1}"] == "0"
    # extensible (c_K != 0): I2 is lost
    assert cli.main(["check", "--json", "--subs", "B2=B1,c_J=c_H"]) == 0
    out = json.loads(capsys.readouterr().out)
    table = list(out["results"][0]["details"]["tables"].values())[0]
    assert table["{H,I2}"] != "0"


def test_check_bad_substitution_exit_2(capsys):
    assert cli.main(["check", "--subs", "nonsense=1"]) == 2
    err = capsys.readouterr().err
    assert "subs" in err and "Traceback" not in err


def test_numerics_do_not_import_sympy():
    """No module of the runtime library imports SymPy or derive/ (checked on the source: heyoka itself imports
    SymPy when it happens to be installed, so sys.modules cannot tell).  Only `magrod check --rederive/--subs`
    reaches into magrod.derive, lazily inside a function."""
    import ast
    from pathlib import Path

    import magrod

    offenders, scanned = [], 0
    root = Path(magrod.__file__).parent
    for path in root.rglob("*.py"):
        if path.relative_to(root).parts[0] == "derive":  # installed as magrod.derive: the SymPy side itself
            continue
        scanned += 1
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            names = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = [("." * node.level) + (node.module or "")]
            for n in names:
                if n.split(".")[0] in ("sympy", "mpmath") or "derive" in n:
                    if not (path.relative_to(root).parts[0] == "integrability" and "derive" in n):
                        offenders.append(f"{path.name}: {n}")
    assert scanned >= 20 and not offenders, (scanned, offenders)


def test_check_imports_neither_heyoka_nor_matplotlib():
    """`python -X importtime -m magrod.cli check --json` lists no heyoka or matplotlib module, and after a full
    `magrod check --json` in a fresh interpreter neither is in sys.modules: the CLI wing imports subcommand
    modules lazily and the integrability report is read from generated/report.json."""
    r = subprocess.run([sys.executable, "-X", "importtime", "-m", "magrod.cli", "check", "--json"],
                       capture_output=True, text=True, cwd=tempfile.gettempdir(), timeout=600)
    assert r.returncode == 0, r.stderr[-2000:]
    imported = {line.split("|")[-1].strip() for line in r.stderr.splitlines() if line.startswith("import time:")}
    assert "json" in imported  # the listing is real
    assert not {m for m in imported if m.split(".")[0] in ("heyoka", "matplotlib", "sympy")}
    code = ("import contextlib, io, json, sys\n"
            "from magrod.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            "    rc = main(['check', '--json'])\n"
            "print(json.dumps({'rc': rc, 'modules': sorted(sys.modules)}))\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tempfile.gettempdir(),
                       timeout=600)
    out = json.loads(r.stdout)
    assert out["rc"] == 0 and "magrod.cli.check" in out["modules"] and "magrod.integrability.report" in out["modules"]
    assert not [m for m in out["modules"] if m.split(".")[0] in ("heyoka", "matplotlib", "sympy")]
