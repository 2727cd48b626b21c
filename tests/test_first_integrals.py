"""magrod.integrability.first_integrals and `magrod check --integrals` (issue 20, item 4).

References: the involution table of derive/poisson.py (which integrals are in involution with H in each regime),
the known algebra (products of C1-C3, H, I1 counted by rank), and a mutated vector field that the independent
re-check must reject."""
import json
from fractions import Fraction

import pytest

pytest.importorskip("flint")

from helpers import run_cli
from magrod.core.errors import ParameterError  # noqa: E402
from magrod.integrability import first_integrals as F  # noqa: E402



def test_cli_degree_4_json_with_controls():
    """The contract of the issue: finishes within 60 s (a guard, not a benchmark: measured ~5 s on one core, see
    benchmarks/first_integrals.py), one JSON object, the controls as stated."""
    r = run_cli("check", "--integrals", "--degree", "4", "--json", timeout=60)
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["ok"] is True and out["degree"] == 4 and out["seed"] == F.DEFAULT_SEED
    assert set(out["controls_ok"]) == set(F.CONTROLS) and all(out["controls_ok"].values())
    main = out["main"]
    assert main["certified"] and main["kernel_dims"] == main["algebra_dims"] == [1, 2, 7, 12, 27]
    assert main["values"]["B1"] == main["values"]["B2"] and main["values"]["lambda"] != "0"  # printed parameters
    c = out["controls"]
    assert c["lambda = 0"]["candidates_found"] == ["I2"] and c["lambda = 0"]["new_integrals"] > 0
    assert c["inextensible, unshearable"]["candidates_found"] == ["I2"]
    assert "I1" not in c["anisotropic"]["known"]
    assert "No polynomial first integral of degree <= 4" in out["statement"]


@pytest.mark.parametrize("degree", ["0", "13", "-1", "2.5"])
def test_cli_bad_degree_exit_2_one_line(degree):
    r = run_cli("check", "--integrals", "--degree", degree)
    assert r.returncode == 2 and r.stdout == ""
    assert len(r.stderr.strip().splitlines()) == 1 and "degree" in r.stderr and "Traceback" not in r.stderr


@pytest.mark.parametrize("subs", ["nonsense=1", "B1=0", "c_K=-1", "B2=", "lambda=1/0"])
def test_cli_bad_subs_exit_2_one_line(subs):
    r = run_cli("check", "--integrals", "--degree", "2", "--subs", subs, "--json")
    assert r.returncode == 2, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1 and "subs" in r.stderr
    assert json.loads(r.stdout)["ok"] is False


def test_lambda_zero_finds_n_dot_m():
    r = F.search("B2=B1,c_J=c_H,lambda=0", 3)
    assert r.certified and r.candidates_found == ["I2"]
    vals, _ = F.parameter_values("B2=B1,c_J=c_H,lambda=0", F.DEFAULT_SEED)
    i2 = F._poly("I2", vals)
    nm = {tuple(1 if k in (i, i + 3) else 0 for k in range(9)): Fraction(1) for i in range(3)}  # m_i n_i
    assert i2 == nm  # at lambda = 0, I2 = n.m
    # the check can fail: without n.m the known algebra is too small
    assert r.kernel_dims[2] == r.algebra_dims[2] + 1


def test_anisotropic_loses_m3_and_inextensible_finds_i2():
    a = F.search("c_J=c_H", 3)
    assert a.certified and "I1" not in a.known and a.kernel_dims[1] == 1  # only the constants in degree <= 1
    b = F.search("B2=B1,c_H=0,c_J=0,c_K=0", 3)
    assert b.certified and b.candidates_found == ["I2"]


def test_extensible_magnetic_rod_nothing_new_and_seed_independent():
    r1 = F.search(F.MAIN, 4, seed=1)
    r2 = F.search(F.MAIN, 4, seed=2)
    assert r1.values != r2.values
    assert r1.certified and r2.certified and r1.kernel_dims == r2.kernel_dims and r1.new_integrals == 0


def test_recheck_rejects_a_mutated_field():
    vals, _ = F.parameter_values(F.MAIN, 3)
    X = F.vector_field(vals)
    assert F.recheck_columns(vals, X, 2, F.PRIME, 3) > 0
    bad = [dict(x) for x in X]
    k = next(iter(bad[0]))
    bad[0][k] = -bad[0][k]  # one sign flipped in m1'
    with pytest.raises(AssertionError, match="disagrees"):
        F.recheck_columns(vals, bad, 2, F.PRIME, 3)


@pytest.mark.parametrize("degree", [0, 13, -1, 2.5, "x", None, True])
def test_bad_degree_names_the_parameter(degree):
    with pytest.raises(ParameterError) as ei:
        F.search(F.MAIN, degree)
    assert ei.value.name == "degree"
