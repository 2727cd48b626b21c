"""The same answers on every machine (issue 24).

Two things that differ between machines must not decide a result:

1. **What LAPACK returns.**  `eig` gives eigenpairs in an order of its own and each eigenvector up to a unit
   factor, which it fixes by making the largest component real -- a tie broken by rounding when the S^1
   symmetry makes two components equal in modulus (on an AVX-512 machine that choice made the periodic saddle's
   start guess useless).  The `scrambled_eig` fixture replaces numpy's (and scipy's) eig/eigvals by versions
   that permute the eigenpairs and multiply every complex eigenvector by a random unit phase (every real one
   by a random sign), and the saddle, orbit, fold and splitting computations must give the same answers to
   their quoted digits.
2. **The SIMD batch width.**  `MAGROD_BATCH_WIDTH` forces heyoka's batch width (magrod.core.systems.batch_width);
   the batch paths (sections, indicators, maps, portraits) run at widths 1, 2, 4 and 8 and must agree as the
   issue-18 tests define agreement (tests/test_batch.py): section points against the scalar path within the
   float64 / long double distance, conservation on every lane, and the same verdicts.

References are independent computations in the same run (the unscrambled eig, the scalar path, another
precision), never numbers from one machine.
"""
import math

import numpy as np
import pytest
import scipy.linalg

from magrod.chaos import indicators as I
from magrod.chaos import maps
from magrod.chaos.section import poincare_section, poincare_sections
from magrod.core import eigen, systems
from magrod.core.errors import ParameterError
from magrod.core.params import RodParams
from magrod.orbits import multipulse
from magrod.orbits import periodic as PER
from magrod.orbits import periodic_multipulse as hp
from magrod.orbits.equilibrium import straight_rod
from magrod.proof.provers import horseshoe_design, transverse_homoclinic
from magrod.separatrix import splitting as S

README = RodParams(1.7, 0.4, 3, 3, 0.135)  # the README's library example: the periodic saddle of Fig 4(a)
FIG6 = RodParams(1.7, 0.002, 1.0, 1.0, 0.001)  # mu = 2 lam: the straight rod
GENERIC = RodParams(1.7, 0.0021, 1.0, 1.0, 0.001)  # mu > 2 lam: the periodic saddle near the straight rod
TILTED = RodParams(1.7, 0.0401, 1.0, 1.0, 0.01)  # the proof point's tilted saddle (issue 21)
LAM_STAR_FIG6_N2 = 0.00126208079543  # docs/errata.md table (as tests/test_continuation.py)
SEEDS = (0, 1, 2)


# ----------------------------------------------------------------------------------------------------------
# the harness
# ----------------------------------------------------------------------------------------------------------
def _scramble(w, V, rng):
    """Permute the eigenpairs; complex eigenvectors times a random unit phase, real ones times a random sign
    (what another LAPACK, BLAS kernel or CPU may return: every choice is an equally valid eigen-decomposition)."""
    w = np.asarray(w)
    perm = rng.permutation(w.size)
    w = w[perm]
    if V is None:
        return w
    V = np.array(V)[:, perm]
    if np.iscomplexobj(V):
        real = np.abs(w.imag) == 0
        f = np.where(real, rng.choice([-1.0, 1.0], w.size), np.exp(2j * np.pi * rng.random(w.size)))
        V = V * f
    else:
        V = V * rng.choice([-1.0, 1.0], w.size)
    return w, V


@pytest.fixture
def scrambled_eig(monkeypatch):
    """scrambled_eig(seed): from now on in this test, numpy's and scipy's eig/eigvals return scrambled results."""
    np_eig, np_eigvals, sp_eig, sp_eigvals = np.linalg.eig, np.linalg.eigvals, scipy.linalg.eig, scipy.linalg.eigvals

    def apply(seed):
        rng = np.random.default_rng(seed)

        def eig(a):
            return _scramble(*np_eig(a), rng)

        def eigvals(a):
            return _scramble(np_eigvals(a), None, rng)

        def sp_eig_(a, *args, **kw):
            out = sp_eig(a, *args, **kw)
            if isinstance(out, tuple) and len(out) == 2:
                return _scramble(*out, rng)
            return out

        def sp_eigvals_(a, *args, **kw):
            return _scramble(sp_eigvals(a, *args, **kw), None, rng)

        monkeypatch.setattr(np.linalg, "eig", eig)
        monkeypatch.setattr(np.linalg, "eigvals", eigvals)
        monkeypatch.setattr(scipy.linalg, "eig", sp_eig_)
        monkeypatch.setattr(scipy.linalg, "eigvals", sp_eigvals_)
        systems.clear_caches()  # nothing computed before the scrambling may be reused
        return rng

    yield apply
    systems.clear_caches()


def test_the_harness_scrambles():
    """The fixture itself: a permutation and phases do change LAPACK's answer (else the tests below prove
    nothing), and leave it a valid eigen-decomposition."""
    A = np.array([[0.0, -2.0, 0.0], [2.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    w0, V0 = np.linalg.eig(A)
    w, V = _scramble(w0, V0, np.random.default_rng(3))
    assert not (np.array_equal(w, w0) and np.array_equal(V, V0))
    np.testing.assert_allclose(A @ V, V * w, atol=1e-14)


# ----------------------------------------------------------------------------------------------------------
# eigenvector rules
# ----------------------------------------------------------------------------------------------------------
def test_fix_phase_and_order_do_not_see_the_phase_or_the_order():
    rng = np.random.default_rng(11)
    v = rng.normal(size=6) + 1j * rng.normal(size=6)
    ref = eigen.fix_phase(v, prefer=(2,))
    for phi in np.linspace(0, 2 * np.pi, 13):
        np.testing.assert_allclose(eigen.fix_phase(np.exp(1j * phi) * v * 3.0, prefer=(2,)), ref, atol=1e-15)
    assert abs(ref[2].imag) <= 1e-16 and ref[2].real > 0
    w = np.array([1 + 2j, 1 - 2j, -1 + 2j, -1 - 2j, 0.0, 3.0])
    for _ in range(5):
        p = rng.permutation(w.size)
        np.testing.assert_array_equal(w[p][eigen.order(w[p])], [3.0, 1 + 2j, 1 - 2j, 0.0, -1 + 2j, -1 - 2j])


def test_periodic_saddle_guess_for_every_phase_of_the_centre_eigenvector(monkeypatch):
    """The failure of issue 24, on any machine: the centre eigenvector at the straight rod returned with each
    phase in turn.  Before the fix the guess was Re(v) as LAPACK phased it; at phase 0 and pi of the table in
    the issue (e32 real) that is the useless e31 = 0 direction, and Gauss-Newton ended at residual 1.5e-4."""
    np_eig = np.linalg.eig
    x_ref, w_ref, d_ref = PER._straight_rod_centre(README)
    j31, j32 = systems.state_index("body", "e31"), systems.state_index("body", "e32")
    assert abs(d_ref[j32]) <= 4 * np.finfo(float).eps and d_ref[j31] > 0  # on the slice e32 = 0 (to rounding)
    ref = PER.relative_equilibrium(README)
    for phi in np.linspace(0, 2 * np.pi, 12, endpoint=False):
        def eig(a, phi=phi):
            w, V = np_eig(a)
            k = int(np.argmax(np.where(np.abs(w.real) < 1e-8, w.imag, -np.inf)))
            # the phase that makes e32 real: what the AVX-512 machine's LAPACK returned at phi = 0
            V[:, k] *= np.exp(1j * (phi - np.angle(V[j32, k])))
            return w, V

        monkeypatch.setattr(np.linalg, "eig", eig)
        x, w, d = PER._straight_rod_centre(README)
        np.testing.assert_allclose(d, d_ref, atol=1e-14, err_msg=f"phase {phi}")
        x0, omega, res = PER.relative_equilibrium(README)
        assert res <= 1e-13, (phi, res)
        np.testing.assert_allclose(x0, ref[0], atol=1e-13)
        assert omega == pytest.approx(ref[1], rel=1e-13)


# ----------------------------------------------------------------------------------------------------------
# saddles, orbits, folds and splitting numbers under scrambled eig
# ----------------------------------------------------------------------------------------------------------
def _saddle_numbers():
    ps = PER.periodic_saddle(README)
    sr = straight_rod(FIG6)
    ts = S.splitting_saddle(TILTED, "long double")
    return {"periodic": ps, "straight": sr, "tilted": ts}


@pytest.fixture(scope="module")
def reference_saddles():
    systems.clear_caches()
    return _saddle_numbers()


@pytest.mark.parametrize("seed", SEEDS)
def test_saddles_do_not_depend_on_lapack(scrambled_eig, reference_saddles, seed):
    scrambled_eig(seed)
    got = _saddle_numbers()
    a, b = reference_saddles["periodic"], got["periodic"]
    np.testing.assert_allclose(b.x, a.x, atol=1e-13)
    assert b.T == pytest.approx(a.T, rel=1e-12) and b.H == pytest.approx(a.H, rel=1e-12)
    # the unstable multiplier |Lambda| ~ 3e4: eigenvalues of a non-normal monodromy to ~1e-9 relative
    assert abs(b.unstable_multiplier / a.unstable_multiplier - 1) <= 1e-8
    np.testing.assert_allclose(b.unstable_vector, a.unstable_vector, atol=1e-7)
    np.testing.assert_allclose(np.abs(b.quartet), np.abs(a.quartet), rtol=1e-7)
    # the zero exponents belong to a defective (Jordan) block of the flow and Casimir directions: rounding
    # splits them like sqrt(eps) ~ 1e-8, so they agree to that and the hyperbolic ones to 1e-10
    np.testing.assert_allclose(b.exponents, a.exponents, atol=1e3 * math.sqrt(np.finfo(float).eps))
    np.testing.assert_allclose(b.exponents[:2], a.exponents[:2], atol=1e-10)
    a, b = reference_saddles["straight"], got["straight"]
    assert abs(b.unstable_eigenvalue - a.unstable_eigenvalue) <= 1e-12
    np.testing.assert_allclose(b.unstable_vector, a.unstable_vector, atol=1e-12)
    np.testing.assert_allclose(b.eigenvalues, a.eigenvalues, atol=1e-12)
    a, b = reference_saddles["tilted"], got["tilted"]
    np.testing.assert_allclose(np.asarray(b.q, float), np.asarray(a.q, float), atol=1e-15)
    assert abs(b.chart_eigenvalue - a.chart_eigenvalue) <= 1e-12
    np.testing.assert_allclose(b.chart_vector, a.chart_vector, atol=1e-12)


@pytest.mark.parametrize("seed", SEEDS)
def test_the_horseshoe_designs_unstable_direction_does_not_see_lapack(scrambled_eig, seed):
    """horseshoe_design.unstable_eigen (the float designs' e_u of DP and DP^p) against the closed form of a 2 x 2 saddle
    (mu = tr/2 + sign(tr) sqrt(tr^2/4 - det), e_u parallel to (b, mu - a)), with LAPACK's pairs permuted and signed
    and, separately, multiplied by complex unit phases."""
    D = np.array([[-3.80106855684721, 1.25530845830605], [2.4, -0.55]])
    tr, det = np.trace(D), np.linalg.det(D)
    mu = tr / 2 + math.copysign(math.sqrt(tr * tr / 4 - det), tr)
    ref = np.array([D[0, 1], mu - D[0, 0]])
    ref = ref / np.linalg.norm(ref) * math.copysign(1.0, ref[0])
    scrambled_eig(seed)
    for phi in (0.0, 0.5, math.pi / 2, 2.0, math.pi):
        got_mu, got = horseshoe_design.unstable_eigen(D) if phi == 0.0 else _phased(horseshoe_design, D, phi)
        assert abs(got_mu - mu) <= 1e-13 * abs(mu)
        np.testing.assert_allclose(got, ref, atol=1e-14)


def _phased(design, D, phi):
    eig = np.linalg.eig
    try:
        np.linalg.eig = lambda a: (lambda w, V: (w, V * np.exp(1j * phi)))(*eig(a))
        return design.unstable_eigen(D)
    finally:
        np.linalg.eig = eig


def test_the_proof_basis_does_not_see_the_phase():
    """The computer-assisted proof's real basis of the unstable plane (magrod.proof.provers.transverse_homoclinic._real_basis): the
    same for every unit factor of the eigenvector, sign included, so the certificate is the same everywhere."""
    rng = np.random.default_rng(5)
    v = rng.normal(size=4) + 1j * rng.normal(size=4)
    ref = transverse_homoclinic._real_basis(v)
    for phi in np.linspace(0, 2 * np.pi, 9):
        got = transverse_homoclinic._real_basis(np.exp(1j * phi) * v)
        np.testing.assert_allclose(got[0], ref[0], atol=1e-14)
        np.testing.assert_allclose(got[1], ref[1], atol=1e-14)


def _orbit_numbers():
    prim = hp.find(GENERIC, 1, samples=91)
    two = multipulse.shoot(RodParams(1.7, 2 * LAM_STAR_FIG6_N2, 1.0, 1.0, LAM_STAR_FIG6_N2), 2)
    sp = S.first_crossing(S.scaled_params(1.7, 1.0, 1.0, 2.0, 1.0, 0.05), "long double")
    return prim, two, sp


@pytest.fixture(scope="module")
def reference_orbits():
    systems.clear_caches()
    return _orbit_numbers()


@pytest.mark.parametrize("seed", SEEDS[:2])
def test_orbits_and_splitting_do_not_depend_on_lapack(scrambled_eig, reference_orbits, seed):
    """Primary homoclinic orbits of the periodic saddle (launch angle and T are unknowns of the shooting), the
    Fig 6 two-pulse orbit at lam* (codimension one: lam is the unknown) and the splitting measure psi of the
    first turning point: the quoted digits (residuals <= 1e-10; lam* to 1e-9, docs/errata.md)."""
    scrambled_eig(seed)
    prim, two, sp = _orbit_numbers()
    rprim, rtwo, rsp = reference_orbits
    assert len(prim) == len(rprim) == 2
    for a, b in zip(sorted(rprim, key=lambda r: r.T), sorted(prim, key=lambda r: r.T)):
        assert b.success and b.residual <= 1e-10
        assert b.T == pytest.approx(a.T, rel=1e-9)
        assert abs(math.remainder(b.angle - a.angle, 2 * math.pi)) <= 1e-8
    assert two.success and two.residual <= 1e-10
    assert two.params.lam == pytest.approx(rtwo.params.lam, rel=1e-9)
    assert abs(sp.psi - rsp.psi) <= 1e-12 and abs(sp.d - rsp.d) <= 1e-12 * max(1.0, abs(rsp.d))


def test_a_fold_does_not_depend_on_lapack(scrambled_eig):
    """The two-pulse branch of the periodic saddle folds in mu (tests/test_continuation.py): located at the same
    mu under a scrambled eig (the fold's mu to 1e-9 relative, the test's own reproduction bound)."""
    from magrod.orbits import continuation as C

    def fold():
        F, _ = C.periodic_problem(GENERIC, "mu", 2)
        scale, mu0, tol = np.array([40.0, 1.0, 1e-4]), 4.8625e-3, 2e-12  # tests/test_continuation.py's fold
        u0, _ = C.point_at(F, [42.9, 20.07, mu0], 2, mu0, scale=scale, tol=tol)
        br = C.pseudo_arclength(F, u0, scale=scale, ds=0.05, ds_max=0.05, steps=3, par=2, direction=-1, tol=tol)
        assert br.success and len(br.folds) == 1, br
        return br.folds[0]["u"]

    systems.clear_caches()
    ref = fold()
    scrambled_eig(4)
    got = fold()
    assert got[2] == pytest.approx(ref[2], rel=1e-9)


# ----------------------------------------------------------------------------------------------------------
# the batch paths at forced widths
# ----------------------------------------------------------------------------------------------------------
WIDTHS = (1, 2, 4, 8)
KEYS = ("4a", "4b", "4d", "5a", "5c")


@pytest.fixture
def width(monkeypatch):
    def set_(b):
        monkeypatch.setenv(systems.BATCH_WIDTH_ENV, str(b))
        assert systems.batch_width() == b
    return set_


def test_batch_width_setting_is_validated(monkeypatch):
    for bad in ("0", "-3", "65", "four", "2.5"):
        monkeypatch.setenv(systems.BATCH_WIDTH_ENV, bad)
        with pytest.raises(ParameterError) as e:
            systems.batch_width()
        assert e.value.name == systems.BATCH_WIDTH_ENV
    monkeypatch.delenv(systems.BATCH_WIDTH_ENV)
    import heyoka as hy

    assert systems.batch_width() == hy.recommended_simd_size()


@pytest.fixture(scope="module")
def scalar_sections():
    n = 100
    return ({k: poincare_section(k, iterates=n) for k in KEYS},
            {k: poincare_section(k, iterates=n, precision="long double") for k in KEYS})


@pytest.mark.parametrize("b", WIDTHS)
def test_sections_agree_at_every_width(width, scalar_sections, b):
    """tests/test_batch.py's agreement at each width: the first 10 crossings within 1e-12 of the scalar path,
    then within 10x the float64 / long double distance; conservation on every lane; results in input order."""
    width(b)
    S_, L = scalar_sections
    res = poincare_sections(list(KEYS), iterates=100)
    assert [r.panel for r in res] == list(KEYS)
    for r in res:
        s, ld = S_[r.panel], L[r.panel]
        assert r.success and r.n_points == 100
        d_bs = np.max(np.abs(r.body_points - s.body_points), axis=1)
        d_sl = np.max(np.abs(s.body_points - ld.body_points), axis=1)
        assert np.max(d_bs[:10]) <= 1e-12, (b, r.panel, d_bs[:10])
        assert np.max(d_bs) <= 10 * np.max(d_sl), (b, r.panel, np.max(d_bs), np.max(d_sl))
        assert r.max_abs_dH <= 1.5e-13 and r.casimir_drift <= 1.5e-13


@pytest.fixture(scope="module")
def panel_starts():
    xs, ps = [], []
    for k in ("4a", "4b", "4c", "4d", "5a", "5b", "5c", "5d"):
        x0, p, st, _ = maps.start_point(maps.panel_base(k))
        assert st == I.OK
        xs.append(x0)
        ps.append(p)
    return np.array(xs).T, np.array(ps).T


def test_indicators_give_the_same_verdicts_at_every_width(panel_starts):
    """The 8 paper panels at T = 3000 (their default: below it the sticky Fig 4 orbits are marginal) with
    batch widths 1, 2, 4, 8 and with 3 orbits only (fewer than the lanes): the same verdicts (4d regular, the
    Fig 4(a)-(c) chaotic, the README's claim), conservation on every lane.  The finite-time exponent of a chaotic
    orbit is not compared: it carries every rounding difference (tests/test_chaos.py)."""
    x0, p = panel_starts
    ref = None
    for b in WIDTHS:
        r = I.body_indicators(x0, p, t_max=3000.0, batch_size=b)
        assert np.all(r.status == I.OK), (b, r.status)
        assert np.all(r.max_abs_dH <= 1e-11), (b, r.max_abs_dH)
        few = I.body_indicators(x0[:, :3], p[:, :3], t_max=3000.0, batch_size=b)
        if b >= 2:  # the SIMD kernels: within a width, the lane's result is bit-identical however many orbits
            np.testing.assert_array_equal(few.growth_exponent, r.growth_exponent[:3])
        np.testing.assert_array_equal(few.chaotic, r.chaotic[:3])
        if ref is None:
            ref = r.chaotic
            assert ref[:4].tolist() == [True, True, True, False]  # README / REPORT: 4(a)-(c) chaotic, 4(d) regular
        np.testing.assert_array_equal(r.chaotic, ref, err_msg=f"width {b}")


def test_maps_agree_at_every_width(width):
    """A small chaos map at widths 1, 2, 4, 8: the same missing points and the same classification on the
    points whose growth exponent is not within 10 % of the threshold (a marginal point's verdict is decided by
    its last digits, as between any two valid roundings); in practice all of them agree."""
    out = {}
    for b in WIDTHS:
        width(b)
        spec = maps.MapSpec(x=maps.parse_axis("x", "lam:0.12:0.2:4"), y=maps.parse_axis("y", "gamma:2.5:3.5:3"),
                            base=maps.panel_base("4a"), t_max=1000.0)
        assert spec.batch_size == b
        out[b] = maps.chaos_map(spec).fields
    ref = out[WIDTHS[-1]]
    for b, f in out.items():
        np.testing.assert_array_equal(f["status"], ref["status"], err_msg=f"width {b}")
        g, g0 = f["growth_exponent"], ref["growth_exponent"]
        clear = np.isfinite(g0) & (np.abs(g0 - I.GROWTH_THRESHOLD) > 0.1 * I.GROWTH_THRESHOLD)
        np.testing.assert_array_equal(g[clear] > I.GROWTH_THRESHOLD, g0[clear] > I.GROWTH_THRESHOLD)
        assert clear.sum() >= 0.75 * np.isfinite(g0).sum()


# ----------------------------------------------------------------------------------------------------------
# other BLAS kernels
# ----------------------------------------------------------------------------------------------------------
def numbers() -> dict:
    """The saddle and orbit numbers compared across BLAS kernels (run in a subprocess by the test below)."""
    sad = _saddle_numbers()
    prim, two, sp = _orbit_numbers()
    ps, sr = sad["periodic"], sad["straight"]
    return {"T": ps.T, "H": ps.H, "x": ps.x.tolist(), "Lambda": abs(ps.unstable_multiplier),
            "straight": [sr.unstable_eigenvalue.real, sr.unstable_eigenvalue.imag],
            "prim_T": sorted(r.T for r in prim), "lam_star": two.params.lam, "psi": sp.psi}


# kernels every x86-64 CPU with AVX2 runs (CI's and this machine's kind); OpenBLAS honours OPENBLAS_CORETYPE
KERNELS = ("Haswell", "Sandybridge")


@pytest.mark.parametrize("kernel", KERNELS)
def test_saddles_and_orbits_under_other_blas_kernels(kernel, reference_saddles, reference_orbits):
    import json
    import os
    import platform
    import subprocess
    import sys
    from pathlib import Path

    if platform.machine() not in ("x86_64", "AMD64"):
        pytest.skip("OPENBLAS_CORETYPE names x86-64 kernels")
    here = Path(__file__).resolve().parent
    code = f"import json, sys; sys.path.insert(0, {str(here)!r}); import test_portability as t; print(json.dumps(t.numbers()))"
    env = {**os.environ, "OPENBLAS_CORETYPE": kernel, "OPENBLAS_VERBOSE": "2"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=600,
                         cwd=here.parent.parent)
    assert out.returncode == 0, out.stderr[-2000:]
    assert f"Core: {kernel}" in out.stdout + out.stderr  # the kernel was really switched
    got = json.loads(out.stdout.strip().splitlines()[-1])
    ps, sr = reference_saddles["periodic"], reference_saddles["straight"]
    prim, two, sp = reference_orbits
    assert got["T"] == pytest.approx(ps.T, rel=1e-12) and got["H"] == pytest.approx(ps.H, rel=1e-12)
    np.testing.assert_allclose(got["x"], ps.x, atol=1e-13)
    assert got["Lambda"] == pytest.approx(abs(ps.unstable_multiplier), rel=1e-8)
    assert got["straight"] == pytest.approx([sr.unstable_eigenvalue.real, sr.unstable_eigenvalue.imag], abs=1e-12)
    np.testing.assert_allclose(got["prim_T"], sorted(r.T for r in prim), rtol=1e-9)
    assert got["lam_star"] == pytest.approx(two.params.lam, rel=1e-9)
    assert abs(got["psi"] - sp.psi) <= 1e-12
