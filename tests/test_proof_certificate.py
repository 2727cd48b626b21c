"""The computer-assisted proof end to end: `magrod prove` writes a certificate, `magrod prove --verify` (separate
code) re-checks it; tampered certificates are rejected; the integrable controls (lambdabar = 0, gamma = delta = 0)
and a mutated vector field fail to prove; bad input is exit 2 with one line naming the parameter.

Quick setting: one symmetric orbit (psi = pi) at the target; the full target (both orbits, ~1 min to prove and
~1 min to verify) is marked slow, and benchmarks/prove_target.py times it."""
from __future__ import annotations

import copy
import json
from fractions import Fraction

import pytest

from magrod.cli import main
from magrod.proof import ball, fields, verify
from magrod.proof.provers import transverse_homoclinic

TARGET = ("1.7", "0.04", "1", "1", "0.01")  # m, mu, gamma, delta, lam
ARGS = ["--m", "1.7", "--mu", "0.04", "--gamma", "1", "--delta", "1", "--lam", "0.01"]


@pytest.fixture(scope="module")
def certificate(tmp_path_factory):
    out = tmp_path_factory.mktemp("proof")
    code = main(["prove", *ARGS, "--targets", "pi", "--out", str(out), "--quiet"])
    assert code == 0
    path = out / "certificate.json"
    return path, json.loads(path.read_text())


def test_certificate_contents(certificate):
    _, cert = certificate
    assert cert["format"] == verify.FORMAT
    assert cert["params"] == {"m": "17/10", "mu": "1/25", "gamma": "1/1", "delta": "1/1", "lam": "1/100"}
    assert all(c["holds"] for c in cert["checks"]) and len(cert["checks"]) >= 20
    (c,) = cert["crossings"]
    d = ball.json_bounds(c["dtheta_dpsi"])
    # float reference (magrod.separatrix.splitting.tilted_curve, a = 4, b = 1, eps = 0.1): theta_u(psi) = c0 +
    # sum ck cos k psi + sk sin k psi with (s1..s4) = (-1.680e-3, -2.724e-4, -1.970e-5, -4.72e-7), so
    # dtheta_u/dpsi at psi = pi is -s1 + 2 s2 - 3 s3 + 4 s4 = 1.19e-3
    assert d[0] <= Fraction(119, 100000) <= d[1] and d[0] > 0
    # balls are exact decimal strings
    for b in (c["dtheta_dpsi"], c["newton"]):
        assert Fraction(b["mid"]) == Fraction(b["mid"]).limit_denominator(2**400) and Fraction(b["rad"]) > 0


def test_verify_accepts_the_certificate(certificate, capsys):
    path, _ = certificate
    assert main(["prove", "--verify", str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["ok"] and all(c["holds"] for c in out["checks"])


def _reject(cert, tmp_path, capsys):
    p = tmp_path / "tampered.json"
    p.write_text(json.dumps(cert))
    code = main(["prove", "--verify", str(p)])
    err = capsys.readouterr().err.strip().splitlines()
    return code, err


def test_tampered_input_is_rejected(certificate, tmp_path, capsys):
    _, cert = certificate
    bad = copy.deepcopy(cert)
    bad["params"]["lam"] = "101/10000"
    code, err = _reject(bad, tmp_path, capsys)
    assert code == 1 and len(err) == 1 and "rejected" in err[0], err


def test_shifted_saddle_ball_is_rejected(certificate, tmp_path, capsys):
    _, cert = certificate
    bad = copy.deepcopy(cert)
    k = bad["saddle"]["K"][0]
    k["mid"] = ball.decimal(Fraction(k["mid"]) + 4 * Fraction(k["rad"]))
    code, err = _reject(bad, tmp_path, capsys)
    assert code == 1 and len(err) == 1 and "saddle K[0] recomputed" in err[0], err


def test_a_ball_that_breaks_a_claim_is_rejected(certificate, tmp_path, capsys):
    _, cert = certificate
    bad = copy.deepcopy(cert)
    d = bad["crossings"][0]["dtheta_dpsi"]
    d["rad"] = ball.decimal(abs(Fraction(d["mid"])) * 2)  # now contains 0
    code, err = _reject(bad, tmp_path, capsys)
    assert code == 1 and len(err) == 1 and "claims" in err[0], err


@pytest.mark.slow
def test_shifted_crossing_ball_is_rejected(certificate, tmp_path, capsys):
    """A shift that keeps every claim true is caught only by the recomputation (replays the flight)."""
    _, cert = certificate
    bad = copy.deepcopy(cert)
    d = bad["crossings"][0]["dtheta_dpsi"]
    d["mid"] = ball.decimal(Fraction(d["mid"]) + Fraction(d["rad"]) / 2)
    code, err = _reject(bad, tmp_path, capsys)
    assert code == 1 and len(err) == 1 and "dtheta/dpsi recomputed" in err[0], err


def test_unreadable_and_non_json_certificates_are_bad_input(tmp_path, capsys):
    (tmp_path / "x.json").write_text("{not json")
    for arg in (str(tmp_path / "missing.json"), str(tmp_path / "x.json"), str(tmp_path)):
        code = main(["prove", "--verify", arg])
        err = capsys.readouterr().err.strip().splitlines()
        assert code == 2 and len(err) == 1 and "verify" in err[0], err
    (tmp_path / "y.json").write_text(json.dumps({"format": "something else"}))
    assert main(["prove", "--verify", str(tmp_path / "y.json")]) == 2


@pytest.mark.parametrize("change, name", [({"--mu": "0.02"}, "mu"), ({"--mu": "0.01"}, "mu"), ({"--m": "2.9"}, "m"),
                                          ({"--lam": "nan"}, "lam"), ({"--m": "inf"}, "m"),
                                          ({"--gamma": "-1"}, "gamma")])
def test_bad_input_is_exit_2_naming_the_parameter(change, name, tmp_path, capsys):
    args = list(ARGS)
    for k, v in change.items():
        args[args.index(k) + 1] = v
    out = tmp_path / "never"
    code = main(["prove", *args, "--out", str(out), "--json"])
    captured = capsys.readouterr()
    assert code == 2
    assert len(captured.err.strip().splitlines()) == 1
    assert json.loads(captured.out)["parameter"] == name
    assert not out.exists()


def test_lambda_zero_control_fails_to_prove(tmp_path, capsys):
    """lambdabar = 0: the system is integrable, W^u = W^s, so dtheta_u/dpsi = 0 exactly at psi = pi."""
    args = list(ARGS)
    args[args.index("--lam") + 1] = "0"
    out = tmp_path / "never"
    code = main(["prove", *args, "--targets", "pi", "--out", str(out), "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 1 and len(err) == 1 and "transversality not established" in err[0] and "contains 0" in err[0]
    assert not out.exists()


def test_mutated_field_fails_to_prove(tmp_path, capsys):
    out = tmp_path / "never"
    code = main(["prove", *ARGS, "--mutate", "0", "--out", str(out), "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 1 and len(err) == 1 and "not established" in err[0]
    assert not out.exists()


def test_mutated_body_field_fails_to_prove():
    """A sign flipped in the body field (the flight) instead of the chart field."""
    p = transverse_homoclinic.validate_params(*TARGET)
    res = transverse_homoclinic.prove(p, transverse_homoclinic.ProofSettings(targets=("pi",)), module=fields.mutated_module(0, "body_rhs"))
    assert not res.ok and res.certificate is None
    print("\nmutated body field:", res.reason)


@pytest.mark.slow
def test_gamma_delta_zero_control_fails_to_prove():
    """gamma = delta = 0: inextensible, unshearable, integrable for every lambdabar."""
    p = transverse_homoclinic.validate_params("1.7", "0.04", "0", "0", "0.01")
    res = transverse_homoclinic.prove(p, transverse_homoclinic.ProofSettings(targets=("0",)))
    assert not res.ok and "transversality not established" in res.reason and "contains 0" in res.reason


@pytest.mark.slow
def test_full_target_proof_and_verification(tmp_path):
    p = transverse_homoclinic.validate_params(*TARGET)
    res = transverse_homoclinic.prove(p)
    assert res.ok, res.reason
    v = verify.verify(json.loads(json.dumps(res.certificate)))
    assert v.ok, v.reason
    signs = {c["target"]: ball.json_bounds(c["dtheta_dpsi"]) for c in res.certificate["crossings"]}
    # float reference (see test_certificate_contents): dtheta_u/dpsi(0) = s1 + 2 s2 + 3 s3 + 4 s4 = -2.29e-3
    assert signs["0"][1] < 0 and signs["0"][0] <= Fraction(-229, 100000) <= signs["0"][1]
    assert signs["pi"][0] > 0
