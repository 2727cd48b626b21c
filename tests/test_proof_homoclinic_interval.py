"""Statement 5 on a lambdabar interval: the homoclinic proof with lambdabar the ball [lam - W, lam + W] in every
enclosure (fields.IntervalParams, transverse_homoclinic.interval_params; `magrod prove --lam-rad W`), the shipped certificate
homoclinic_target_interval.json (W = 1e-9 at the issue-21 target: the boundary circle centred on the moving saddle,
lambdabar a state of the flights, kernel/homoclinic.moving_arc), and its controls: a certificate claiming a wider
interval than its enclosures carry, or the point's theorem on an interval's data (or the reverse), is rejected; the
shifted saddle box is rejected; a mutated field and lambdabar = 0 fail to prove; bad --lam-rad is exit 2 naming it.

Before this, `magrod prove --lam-rad W` without --fixed-point/--horseshoe silently proved the point."""
from __future__ import annotations

import copy
import json
from fractions import Fraction
from importlib import resources

import pytest

from helpers import assert_rejected, verify_cli

from magrod.cli import main
from magrod.proof import ball, fields, theorem
from magrod.proof.provers import transverse_homoclinic

ARGS = ["--m", "1.7", "--mu", "0.04", "--gamma", "1", "--delta", "1", "--lam", "0.01"]
W = Fraction(1, 10**9)
WS = "1/1000000000"
NAME = "homoclinic_target_interval.json"


@pytest.fixture(scope="module")
def shipped():
    return json.loads(resources.files("magrod.proof").joinpath("certificates", NAME).read_text())


def test_interval_params_enclose_every_lambdabar_of_the_interval():
    p = transverse_homoclinic.validate_params("1.7", "0.04", "1", "1", "0.01")
    q = transverse_homoclinic.interval_params(p, W)
    lo, hi = ball.bounds(q.balls()[fields.PARAMS.index("lam")])
    assert lo <= p.lam - W and p.lam + W <= hi and hi - lo < 3 * W  # the interval, rounded outward, not more
    # the other parameters, the float search's centre and the certificate's parameters are the point's
    assert [str(x) for i, x in enumerate(q.balls()) if i != 4] == [str(x) for i, x in enumerate(p.balls()) if i != 4]
    assert q.floats() == p.floats() and q.as_json() == p.as_json()
    assert transverse_homoclinic.interval_params(p, 0) is p


@pytest.mark.parametrize("w, why", [("-1/10", "must be in [0, 1]"), ("abc", "exact number"),
                                    ("1/50", "mu > 2 (lambdabar + lam_rad)")])
def test_bad_lam_rad_is_exit_2_naming_it(w, why, tmp_path, capsys):
    out = tmp_path / "never"
    code = main(["prove", *ARGS, f"--lam-rad={w}", "--out", str(out), "--json"])
    cap = capsys.readouterr()
    err = cap.err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "lam_rad" in err[0] and why in err[0], err
    assert json.loads(cap.out)["parameter"] == "lam_rad" and not out.exists()


def test_the_shipped_interval_certificate_verifies_with_the_interval_theorem(shipped, tmp_path, capsys):
    assert shipped["settings"]["lam_rad"] == WS
    code, out, _ = verify_cli(shipped, tmp_path, capsys)
    want = theorem.homoclinic_theorem(shipped["params"], ["0", "pi"], WS)
    assert code == 0 and f"theorem: {want}" in out
    assert "every lambdabar in [9999999/1000000000, 10000001/1000000000]" in want
    # the point certificate's slopes lie inside the interval's (the interval contains the point)
    point = json.loads(resources.files("magrod.proof").joinpath("certificates", "homoclinic_target.json").read_text())
    for a, b in zip(point["crossings"], shipped["crossings"]):
        (plo, phi), (ilo, ihi) = ball.json_bounds(a["dtheta_dpsi"]), ball.json_bounds(b["dtheta_dpsi"])
        assert ilo <= plo and phi <= ihi and (ihi < 0 or ilo > 0)


def test_a_wider_interval_than_the_enclosures_carry_is_rejected(shipped, tmp_path, capsys):
    """lam_rad x 2 (x 10) in the settings with the matching, wider theorem text: the verifier recomputes every
    enclosure over the wider interval, and they no longer fit the certificate's balls (x 10: the saddle box is no
    longer a Krawczyk box; the saddle moves 6.8 lam_rad).  A verifier that dropped the interval would reject this one
    too (a recomputation at other input widths need not fit inside the stored balls); the control that tells the two
    apart is the relabelled point certificate below."""
    for w, check in (("1/500000000", "saddle K[0] recomputed"), ("1/100000000", "saddle Krawczyk")):
        bad = copy.deepcopy(shipped)
        bad["settings"]["lam_rad"] = w
        bad["theorem"] = theorem.homoclinic_theorem(bad["params"], ["0", "pi"], w)
        assert_rejected(bad, tmp_path, capsys, check)


def test_an_interval_widened_beyond_its_balls_slack_is_rejected(shipped, tmp_path, capsys):
    """lam_rad x (1 + 2^-10), the smallest widening the stored balls (transverse_homoclinic.stored: the prover's enclosures widened
    by 2^-10 of their radius) do not absorb, with its theorem text: rejected before any flight.  A widening by one
    ulp of the radius verifies, rightly (every enclosure recomputed on the widened interval still lies in its ball:
    research/README.md, "Interval theorems").  The first check to see it is the manifold's C^0 bound rho_eff =
    min(rho, S + L (r + U)), stored exactly, which grows with the saddle's motion over the interval (U, S)."""
    w = W * (1 + Fraction(1, 2**10))
    bad = copy.deepcopy(shipped)
    bad["settings"]["lam_rad"] = f"{w.numerator}/{w.denominator}"
    bad["theorem"] = theorem.homoclinic_theorem(bad["params"], ["0", "pi"], bad["settings"]["lam_rad"])
    assert_rejected(bad, tmp_path, capsys, "manifold rho_eff")


def test_the_point_certificate_relabelled_as_an_interval_is_rejected(tmp_path, capsys):
    """The point's certificate with lam_rad and the interval's theorem added: its enclosures are the point's, and the
    verifier, recomputing with lambdabar as the interval's ball, finds the point's saddle box (radius 1e-25) no
    Krawczyk box for a saddle that moves 6.8 lam_rad.  (A verifier that dropped the interval from its balls would
    recompute the stored enclosures exactly and accept: seen with IntervalParams.balls returning the point's.)"""
    c = json.loads(resources.files("magrod.proof").joinpath("certificates", "homoclinic_target.json").read_text())
    c["settings"]["lam_rad"] = WS
    c["theorem"] = theorem.homoclinic_theorem(c["params"], ["0", "pi"], WS)
    assert_rejected(c, tmp_path, capsys, "saddle Krawczyk")


def test_the_point_theorem_on_interval_data_and_the_reverse_are_rejected(shipped, tmp_path, capsys):
    bad = copy.deepcopy(shipped)
    bad["theorem"] = theorem.homoclinic_theorem(bad["params"], ["0", "pi"])
    assert_rejected(bad, tmp_path, capsys, "theorem text")
    bad = copy.deepcopy(shipped)
    del bad["settings"]["lam_rad"]  # the point's data, but the interval's theorem: it claims more
    assert_rejected(bad, tmp_path, capsys, "theorem text")
    bad = copy.deepcopy(shipped)
    bad["settings"]["lam_rad"] = "-" + WS
    code, _, err = verify_cli(bad, tmp_path, capsys)
    assert code == 2 and len(err) == 1 and "lam_rad" in err[0], err


def test_the_shifted_saddle_box_is_rejected(shipped, tmp_path, capsys):
    bad = copy.deepcopy(shipped)
    k = bad["saddle"]["K"][0]
    k["mid"] = ball.decimal(Fraction(k["mid"]) + 4 * Fraction(k["rad"]))
    assert_rejected(bad, tmp_path, capsys, "saddle K[0] recomputed")


def test_the_mutated_field_fails_to_prove_on_the_interval(tmp_path, capsys):
    out = tmp_path / "never"
    code = main(["prove", *ARGS, "--lam-rad", WS, "--mutate", "0", "--out", str(out), "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 1 and len(err) == 1 and "not established" in err[0] and not out.exists(), err


def test_the_cli_proves_the_interval_and_says_for_which_lambdabar(tmp_path, capsys):
    """`magrod prove --lam-rad W` (the homoclinic proof; before issue 27's last stop it ignored --lam-rad): psi = pi
    only, W = 1e-10 (~5 s); the written certificate verifies with the interval's theorem."""
    out = tmp_path / "c"
    assert main(["prove", *ARGS, "--lam-rad", "1/10000000000", "--targets", "pi", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    w = Fraction(1, 10**10)
    assert f"for every lambdabar in [{Fraction(1, 100) - w}, {Fraction(1, 100) + w}]" in text
    c = json.loads((out / "certificate.json").read_text())
    assert c["settings"]["lam_rad"] == "1/10000000000"
    code, vout, _ = verify_cli(c, tmp_path, capsys)
    assert code == 0 and theorem.homoclinic_theorem(c["params"], ["pi"], "1/10000000000") in vout


def test_the_lambda_zero_interval_fails_to_prove(tmp_path, capsys):
    """lambdabar in [-1e-9, 1e-9] contains the integrable lambdabar = 0 (W^u = W^s): dtheta_u/dpsi contains 0."""
    args = list(ARGS)
    args[args.index("--lam") + 1] = "0"
    out = tmp_path / "never"
    code = main(["prove", *args, "--lam-rad", WS, "--targets", "pi", "--out", str(out), "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 1 and len(err) == 1 and "transversality not established" in err[0] and "contains 0" in err[0], err
    assert not out.exists()


def test_the_lambda_columns_of_the_body_flight_are_the_derivatives():
    """fields.body_lam_state_field, lift_lam_derivative and lam_state_event_gradient (forward-mode _Dual): their
    lambdabar entries agree with central differences (float, step 1e-7: truncation ~1e-14, rounding ~1e-9), and the
    radicand's with its closed form d/dlambdabar (mu - 2 lambdabar m.e3) = -2 m.e3."""
    import numpy as np
    from flint import arb

    p = fields.ExactParams.from_values(m=Fraction(17, 10), mu=Fraction(1, 25), gamma=1, delta=1, lam=Fraction(1, 100))
    F = fields.body_lam_state_field(p)
    x0 = np.array([0.3, -0.2, 1.0, 0.1, 0.2, 0.9, -0.3, 0.4, 0.866, 0.01])

    def balls(x):
        return [arb(float(v)) for v in x]

    J = F.jacobian(balls(x0), None)
    d = np.zeros(10)
    d[9] = 1e-7

    def f(x):
        return np.array([float(v.mid()) for v in F.rhs(balls(x), None)])

    fd = (f(x0 + d) - f(x0 - d)) / 2e-7
    assert np.abs(fd[:9]).max() > 1e-3  # the body field depends on lambdabar: the comparison has content
    assert np.allclose([float(J[10 * i + 9].mid()) for i in range(10)], fd, atol=1e-7)
    grad = fields.lam_state_event_gradient(p, balls(x0), "rad")
    assert float(grad[9].mid()) == pytest.approx(-2 * float(x0[:3] @ x0[6:9]), rel=1e-12)
    assert all(float(v.mid()) == 0 for v in fields.lam_state_event_gradient(p, balls(x0), "Gs")[9:])
    q0 = np.array([0.14, 0.3, 0.1, 0.99])
    dl = fields.lift_lam_derivative(p, balls(q0))

    def lift(lam):
        pl = fields.ExactParams(p.m, p.mu, p.gamma, p.delta, Fraction(lam))
        return np.array([float(v.mid()) for v in fields.lift(pl, balls(q0))])

    fd = (lift(0.01 + 1e-7) - lift(0.01 - 1e-7)) / 2e-7
    assert np.abs(fd).max() > 1e-3 and np.allclose([float(v.mid()) for v in dl], fd, atol=1e-7)


def test_the_saddle_moves_as_the_certificate_says(shipped):
    """kernel/homoclinic.saddle_motion, on which the circle about the moving saddle rests: x*(lambdabar) in K0 +
    B (lambdabar - lam).  Checked against the zero itself, enclosed by a separate Krawczyk at lambdabar = lam +- W/2
    (point parameters, a 1e-14 box about the affine prediction: its error is ~x*'' W^2): inside the affine enclosure.  The slope with its
    sign flipped misses it (so the comparison can fail)."""
    from magrod.generated import validated as gen
    from magrod.proof.kernel import homoclinic as hk

    p = fields.ExactParams(**{k: Fraction(v) for k, v in shipped["params"].items()})
    pi = fields.IntervalParams(p.m, p.mu, p.gamma, p.delta, p.lam, lam_rad=W)
    with ball.workprec(128):
        xhat = [ball.q(Fraction(v)) for v in shipped["saddle"]["xhat"]]
        K = [ball.from_json(v) for v in shipped["saddle"]["K"]]
        K0, B, ok = hk.saddle_motion(pi, gen, xhat, K, Fraction(1, 10**25))
        assert ok
        for h in (W / 2, -W / 2):
            ph = fields.ExactParams(p.m, p.mu, p.gamma, p.delta, p.lam + h)
            guess = [ball.fraction(k.mid()) + ball.fraction(b.mid()) * h for k, b in zip(K0, B)]
            X = [ball.interval(g - Fraction(1, 10**14), g + Fraction(1, 10**14)) for g in guess]
            Z = hk.krawczyk(fields.chart_field(ph), [ball.q(g) for g in guess], X)
            assert all(hk.inside(z, x) for z, x in zip(Z, X))  # the zero at lam + h
            hq = ball.q(h)
            assert all(ball.subset(z, k + b * hq) for z, k, b in zip(Z, K0, B)), h
            assert not all(ball.subset(z, k - b * hq) for z, k, b in zip(Z, K0, B))


def test_a_moved_saddle_slope_is_rejected(shipped, tmp_path, capsys):
    """The slope dx*/dlambdabar the moving circle is built on, moved by 4 of its radii: recomputed and rejected
    before any flight; so is a moved anchor K0."""
    for key in ("slope", "K0"):
        bad = copy.deepcopy(shipped)
        k = bad["saddle"][key][0]
        k["mid"] = ball.decimal(Fraction(k["mid"]) + 4 * Fraction(k["rad"]))
        assert_rejected(bad, tmp_path, capsys, f"saddle {key}[0] recomputed")


def test_a_block_too_small_for_the_moving_circle_is_rejected(shipped, tmp_path, capsys):
    """r_block between r and r + |u*|: the block's own conditions still hold, but the circle about the moving saddle
    leaves it, where the graph (and the bound |s - s*| <= L r) is not established."""
    bad = copy.deepcopy(shipped)
    rb = Fraction(bad["manifold"]["r"]) + Fraction(bad["manifold"]["bounds"]["U"]) / 2
    bad["manifold"]["r_block"] = f"{rb.numerator}/{rb.denominator}"
    assert_rejected(bad, tmp_path, capsys, "moving circle inside the block")
