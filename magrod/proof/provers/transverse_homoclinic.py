"""The prover: search (floating point) + rigorous steps (ball arithmetic) -> a certificate, or a one-line failure.

What is proved (docs/nonintegrability.md, "Theorem (computer-assisted)"): at exact rational (m, mu, gamma, delta,
lambdabar) with mu > 2 lambdabar, the reduced chart field of Hbar has a saddle-focus q* on Fix(R), and its unstable
manifold W^u crosses Sigma = {pbar_theta = 0} through Fix(R) = {psi in {0, pi}} with d theta_u / d psi != 0, i.e.
two transverse symmetric homoclinic orbits to q* (at psi = 0 and psi = pi).

Pipeline (every step that decides something is rigorous; the search only chooses where to look):
  1. saddle      float Newton (magrod.separatrix.splitting), refined in Arb, Krawczyk box (R-symmetric), eigenpairs (saddle.py)
  2. manifold    cone/slab conditions on a block around q* in eigen-coordinates (manifold.py)
  3. search      heyoka (float64, magrod.systems) from the circle |u| = r: the phases phi* where the first crossing
                 of Sigma has psi = 0 (mod 2 pi) and psi = pi, and the crossing times
  4. flight      for each phi*: the thin set (phi = phi_c) and the arc [phi_c - dphi, phi_c + dphi] of the boundary
                 circle, lifted to the body frame X(q, 0) (derive/validated.py: chart_body_lift), propagated by the
                 C^1 Lohner integrator (taylor.py) in the quadratic, singularity-free body field (the orbit passes
                 theta ~ 0.02, where the chart's 1/sin^3 theta terms wreck enclosures), guarded by sin^2 theta =
                 1 - e33^2 > 0 and the radicand > 0 on every step (so the lift stays valid), to the body section
                 g = e32 m1 - e31 m2 = sin(theta) pbar_theta = 0
  5. decide      interval Newton in phi for Gs = sin(theta) rho sin(psi) = 0 (unique phi* in the arc), sign of
                 Gc = sin(theta) rho cos(psi) (psi = 0 or pi), and d theta_u / d psi = -(de33/dphi) Gc / (sin(theta)
                 dGs/dphi) excludes 0
A certificate is written only if every check holds and the field is the derive-generated one (source digest).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from fractions import Fraction

import numpy as np
from flint import arb

from ...core.errors import ParameterError
from ...core.tolerances import PROOF_STEP_TOL
from ...generated import validated as gen
from .. import ball, fields, manifold, saddle, taylor
from ..kernel import homoclinic as homoclinic_kernel
from ..theorem import homoclinic_theorem

FORMAT = "magrod-proof-certificate/1"
TARGETS = {"0": 0.0, "pi": math.pi}  # the keys are theorem.TARGETS (a test pins it)
#: on a lambdabar interval: the Krawczyk box about the saddle at the centre lambdabar (the anchor x*(lam) of its
#: affine motion, kernel/homoclinic.saddle_motion)
SADDLE_RADIUS0 = Fraction(1, 10**25)


@dataclass
class ProofSettings:
    """Numerical choices of the prover (recorded in the certificate; the verifier replays them).

    prec: Arb working precision (bits); order: Taylor order; tol: per-step truncation target (absolute, on the
    centre trajectory); r: radius of the boundary circle in eigen-coordinates; dphi: half-width of the phase arc;
    saddle_radius: Krawczyk box half-width; eig_rad: eigenpair box half-width; lead: the flight stops this long
    (exact dyadic) before the float crossing time, and the crossing step has length 2 lead."""

    prec: int = 128
    order: int = 20
    tol: float = PROOF_STEP_TOL
    r: Fraction = Fraction(1, 100000)
    dphi: Fraction = Fraction(5, 10**7)
    saddle_radius: Fraction = Fraction(1, 10**25)
    eig_rad: Fraction = Fraction(1, 10**12)
    lead: Fraction = Fraction(1, 256)
    targets: tuple = ("0", "pi")  # the targets proved: the crossings psi = 0 and/or psi = pi
    #: > 0: the proof for every lambdabar in [lam - lam_rad, lam + lam_rad] at once: lambdabar a ball in the
    #: saddle's, eigenpairs' and manifold's enclosures (fields.IntervalParams), whose boxes must then hold the motion
    #: of q* and of its eigen-data over the interval (interval_proof_settings); the boundary circle centred on the
    #: moving saddle and lambdabar a state of the flights (kernel/homoclinic.saddle_motion, moving_arc)
    lam_rad: Fraction = Fraction(0)

    def as_json(self) -> dict:
        return {"prec": self.prec, "order": self.order, "tol": repr(self.tol), "r": _q(self.r), "dphi": _q(self.dphi),
                "saddle_radius": _q(self.saddle_radius), "eig_rad": _q(self.eig_rad), "lead": _q(self.lead),
                "targets": list(self.targets), "series_cap": ball.SERIES_CAP,
                **({"lam_rad": _q(self.lam_rad)} if self.lam_rad else {})}


class ProofFailure(RuntimeError):
    """A step of the proof could not be established; `reason` is the one-line explanation."""

    def __init__(self, reason: str, checks=None):
        self.reason = reason
        self.checks = checks or []
        super().__init__(reason)


def run_checked(prec: int, body, *, flights: bool = False, reraise_input: bool = False, stage=None) -> "ProofResult":
    """The provers' one scaffold (transverse_homoclinic, section_fixed_point, section_horseshoe.prove and horseshoe_widen.widen): ``body(check)`` builds the
    certificate at ``prec`` bits, ``check(name, holds, how)`` records every condition and stops at the first that
    fails.  A failed step is a ProofResult with its one-line reason, never an exception: ProofFailure; with
    ``flights`` a flight the validated integrator could not take (taylor's errors); a nan/inf ball, a singular
    matrix or a ValueError is a "numerical failure" (prefixed by ``stage[0]``, the step reached, when given).  With
    ``reraise_input`` a ParameterError (bad user input, a ValueError) propagates instead."""
    t0 = time.perf_counter()
    checks: list = []

    def check(name, holds, how):
        checks.append({"name": name, "holds": bool(holds), "how": how})
        if not holds:
            raise ProofFailure(f"{name} not established: {how}", checks)

    def failed(reason):
        return ProofResult(False, None, reason, checks, time.perf_counter() - t0)

    try:
        with ball.workprec(prec):
            cert = body(check)
    except ProofFailure as err:
        return failed(err.reason)
    except (taylor.EnclosureError, taylor.GuardError, taylor.CrossingError) as err:
        if not flights:
            raise
        return failed(f"flight not validated: {str(err)[:200]}")
    except (ArithmeticError, ValueError, np.linalg.LinAlgError) as err:  # nan/inf balls, singular matrices
        if reraise_input and isinstance(err, ParameterError):
            raise
        reason = f"numerical failure ({type(err).__name__}: {' '.join(str(err).split())[:160]})"
        return failed(reason if stage is None else f"{stage[0]}: {reason}")
    cert["checks"] = checks
    cert["wall_time_s"] = round(time.perf_counter() - t0, 3)
    return ProofResult(True, cert, "all checks hold", checks, time.perf_counter() - t0)


def _q(x) -> str:
    f = ball.fraction(x)
    return f"{f.numerator}/{f.denominator}"


def _exact(x) -> str:
    """Exact decimal string of a dyadic (float or exact arb)."""
    return ball.decimal(ball.fraction(x))


def validate_params(m, mu, gamma, delta, lam) -> fields.ExactParams:
    """Exact parameters, or ParameterError naming the field: finite; m > 0; gamma, delta >= 0; m < m_c =
    2 sqrt(1 + gamma) (the straight rod is a saddle, eq:buckling_load_2); mu > 2 lambdabar (the tilted saddle
    exists, eq:alignment_condition; the straight-rod equilibrium mu = 2 lambdabar is a different theorem)."""
    vals = {}
    for k, v in (("m", m), ("mu", mu), ("gamma", gamma), ("delta", delta), ("lam", lam)):
        try:
            f = ball.fraction(v if not isinstance(v, float) else repr(v))
        except (ValueError, ZeroDivisionError, TypeError):
            raise ParameterError(k, f"must be a finite number (decimal or p/q), got {str(v)[:40]!r}") from None
        if abs(f) > 10**6:
            raise ParameterError(k, f"must satisfy |{k}| <= 1e6, got {v}")
        vals[k] = f
    if vals["m"] <= 0:
        raise ParameterError("m", f"must be > 0, got {m}")
    for k in ("gamma", "delta"):
        if vals[k] < 0:
            raise ParameterError(k, f"must be >= 0, got {vals[k]}")
    # m < m_c  <=>  m^2 < 4 (1 + gamma), decided exactly
    if vals["m"] ** 2 >= 4 * (1 + vals["gamma"]):
        raise ParameterError("m", f"must satisfy m < m_c = 2 sqrt(1 + gamma) = {2 * math.sqrt(1 + float(vals['gamma'])):.6g} "
                                  f"(eq:buckling_load_2: no saddle at m >= m_c), got {m}")
    if vals["mu"] <= 2 * vals["lam"]:
        raise ParameterError("mu", f"must satisfy mu > 2 lambdabar (the tilted saddle exists only then; "
                                   f"eq:alignment_condition), got mu = {mu}, 2 lam = {float(2 * vals['lam']):g}")
    return fields.ExactParams(**vals)


# --------------------------------------------------------------------------------------------------------------
# floating-point search (heyoka via magrod.systems)
# --------------------------------------------------------------------------------------------------------------
def _float_saddle(p: fields.ExactParams):
    from ...core.params import RodParams
    from ...separatrix import splitting

    rp = RodParams(*p.floats())
    try:
        return splitting.splitting_saddle(rp, "long double")
    except ParameterError as err:  # not hyperbolic: a failed proof, not bad input
        raise ProofFailure(f"saddle: {err.message}") from None


def _real_basis(v) -> list:
    """(Re w, Im w) with w = v / |v| turned so that Re w and Im w are orthogonal (w.w real > 0).  That fixes
    LAPACK's arbitrary unit factor up to the sign of w; the sign is fixed too (the largest component of Re w
    positive, core.eigen.fix_sign), so the certificate's basis and phases never depend on the machine."""
    v = np.asarray(v, complex)
    v = v / np.linalg.norm(v)
    v = v * np.exp(-0.5j * np.angle(np.dot(v, v)))
    j = int(np.argmax(np.abs(v.real) * (1 + 1e-9 * np.arange(v.size)[::-1])))  # ties: the first index
    if v.real[j] < 0:
        v = -v
    return [v.real, v.imag]


class _FloatFlow:
    """Chart trajectories in float64 (heyoka) from the boundary circle to the first crossing of pbar_theta = 0
    with theta > theta0 + 0.3 (the turning point after the excursion; theta0 = the saddle's theta, 0.14 at the
    target but 0.3-0.4 at the Fig 4 parameters, where theta > 0.3 alone picks a crossing next to the
    saddle)."""

    def __init__(self, p, xhat, V, r):
        import heyoka as hy

        from ...core import systems

        self.pars = np.array(p.floats())
        self.xh = np.array([float(v.mid()) for v in xhat])
        self.Vu = ball.to_floats(V)[:, :2]
        self.r = float(r)
        pt = hy.make_vars(*systems.STATE["reduced"])[systems.state_index("reduced", "ptheta")]
        self.ta = systems.taylor(systems.system("reduced"), [0.1, 0.0, 0.0, 1.0], self.pars,
                                 t_events=[hy.t_event(pt)])

    def cross(self, phi: float):
        ta = self.ta
        ta.time = 0.0
        ta.state[:] = self.xh + self.Vu @ (self.r * np.array([math.cos(phi), math.sin(phi)]))
        ta.reset_cooldowns()
        for _ in range(1000):
            oc = ta.propagate_until(500.0)[0]
            if int(oc) != -1:  # the time limit, not the event
                raise ProofFailure("search: no turning point of theta found from the boundary circle")
            if ta.state[0] > self.xh[0] + 0.3:
                return float(ta.time), ta.state.copy()
        raise ProofFailure("search: no turning point of theta found from the boundary circle")

    def phase(self, target: float, n=48):
        """phi* with psi(phi*) = target (mod 2 pi) by a scan and bisection, and its crossing time."""
        phis = np.linspace(0.0, 2 * math.pi, n + 1)

        def G(ph):
            return math.remainder(self.cross(ph)[1][1] - target, 2 * math.pi)

        vals = [G(ph) for ph in phis]
        for i in range(n):
            if vals[i] * vals[i + 1] < 0 and abs(vals[i] - vals[i + 1]) < 2.0:
                a, b, ga = phis[i], phis[i + 1], vals[i]
                break
        else:
            raise ProofFailure(f"search: W^u does not reach psi = {target:.6g} on Sigma (no sign change over the circle)")
        for _ in range(60):
            c = 0.5 * (a + b)
            gc = G(c)
            if gc == 0.0:
                a = b = c
                break
            if (gc > 0) == (ga > 0):
                a, ga = c, gc
            else:
                b = c
        phi = 0.5 * (a + b)
        return phi, self.cross(phi)[0]


# --------------------------------------------------------------------------------------------------------------
# rigorous pieces shared by the prover's steps
# --------------------------------------------------------------------------------------------------------------
def structural_tests(p, module, points) -> list:
    """Refutation tests of the hypotheses the theorem takes from derive/ (reversor_reduced, Hamilton's equations):
    f(R x) + R f(x) and f - J grad Hbar (grad by arb_series) must contain 0 at each point (balls).  A mutated field
    fails them; for the derived field they are identities (proved symbolically), so these are checks, not proofs."""
    fld = fields.chart_field(p, module)
    R = fields.REVERSOR
    out = []
    worst_R = worst_H = True
    for x in points:
        x = [ball.q(ball.fraction(v)) if not isinstance(v, arb) else v for v in x]
        fx = fld.f(x)
        fR = fld.f([r * v for r, v in zip(R, x)])
        worst_R &= all((a + r * b).contains(0) for a, b, r in zip(fR, fx, R))
        grad = _gradient(lambda y: module.chart_hamiltonian(y, p.balls())[0], x)
        ham = [grad[2], grad[3], -grad[0], -grad[1]]  # (theta, psi, pbar_theta, pbar_psi): canonical pairs
        worst_H &= all((a - b).contains(0) for a, b in zip(fx, ham))
    out.append(("reversibility_test", worst_R, f"f(R x) + R f(x) contains 0 at {len(points)} points (balls)"))
    out.append(("hamiltonian_test", worst_H, f"f - J grad Hbar contains 0 at {len(points)} points (balls)"))
    return out


def _gradient(F, x):
    from flint import arb_series

    g = []
    for i in range(len(x)):
        y = [arb_series([v, 1 if j == i else 0], prec=2) for j, v in enumerate(x)]
        c = F(y)
        cs = c.coeffs() if isinstance(c, arb_series) else [c]
        g.append(cs[1] if len(cs) > 1 else arb(0))
    return g


def lift_arc(p, man: manifold.LocalManifold, phi_lo, phi_hi, module=gen):
    """The boundary arc gamma([phi_lo, phi_hi]) of the local manifold, lifted to the body frame at phi = 0:
    a C^1 set (C = mid(DX(Q) V), r0 = y - y_c, the mean-value remainder in r; W = I) and the body tangent box
    DX(Q) V dy containing d X(gamma(phi)) / d phi."""
    ybox, dy = man.circle_arc(phi_lo, phi_hi)
    yc = [y.mid() for y in ybox]
    Q = ball.column(ball.vec(man.xhat) + man.V * ball.vec(ybox))
    qc = ball.column(ball.vec(man.xhat) + man.V * ball.vec(yc))
    xc = fields.lift(p, qc, module)
    JV = fields.lift_jacobian(p, Q, module) * man.V
    C0 = JV.mid()
    dyb = ball.vec([y - c for y, c in zip(ybox, yc)])
    err = ball.column((JV - C0) * dyb)
    S = taylor.initial_set([a + e for a, e in zip(xc, err)], c1=True)
    S.C, S.r0 = C0, dyb
    return S, JV * ball.vec(dy)


def body_section(flight):
    """(g, grad g, guard) for the body flight (kernel/homoclinic.PointFlight or LamStateFlight): g = sin(theta)
    pbar_theta; guard = (1 - e33, 1 + e33, radicand), positive iff the chart is defined (|e3| = 1 is the Casimir C3,
    so sin^2 theta = 1 - e33^2)."""
    def g(x):
        return flight.events(x)["g"]

    def dg(x):
        return flight.gradient(x, "g")

    def guard(Y):
        e = Y[fields.E33]
        return [1 - e, 1 + e, flight.events(Y)["rad"]]

    return g, dg, guard


def crossing_quantities(flight, cr: taylor.CrossingEnclosure, tangent) -> dict:
    """At the crossing of Sigma: Gs, Gc, s2 on the state enclosure, and the phase derivatives along the curve
    c(phi) = crossing point: v = (I - f grad g^T / (grad g . f)) DPhi tangent, dGs = grad Gs . v, de33 = v_e33."""
    ev = flight.events(cr.x)
    out = {"Gs": ev["Gs"], "Gc": ev["Gc"], "s2": ev["s2"], "gdot": cr.gdot, "tau": cr.tau}
    if cr.W is not None:
        u = ball.column(cr.W * tangent)
        grad = flight.gradient(cr.x, "g")
        gu = sum((a * b for a, b in zip(grad, u)), arb(0))
        gf = sum((a * b for a, b in zip(grad, cr.fx)), arb(0))
        v = [ui - fi * gu / gf for ui, fi in zip(u, cr.fx)]
        gs = flight.gradient(cr.x, "Gs")
        out["dGs"] = sum((a * b for a, b in zip(gs, v)), arb(0))
        out["de33"] = v[fields.E33]
    return out


# --------------------------------------------------------------------------------------------------------------
# the prover
# --------------------------------------------------------------------------------------------------------------
@dataclass
class ProofResult:
    ok: bool
    certificate: dict | None
    reason: str
    checks: list = field(default_factory=list)
    wall_time_s: float = 0.0


def prove(params: fields.ExactParams, settings: ProofSettings | None = None, *, module=gen,
          progress=None) -> ProofResult:
    """Prove (or fail to prove) two transverse symmetric homoclinic orbits of the tilted saddle-focus.

    Parameters
    ----------
    params : ExactParams
        Exact rational (m, mu, gamma, delta, lambdabar), from `validate_params`.
    settings : ProofSettings, optional
        Numerical choices (precision, Taylor order, circle radius, phase arc, targets psi = 0 and/or pi).
    module : module, optional
        The generated field module (generated/validated.py); a mutated copy (`fields.mutated_module`) for
        controls.  A certificate is only issued for the derive-generated module.
    progress : callable, optional
        progress(stage: str), called at each stage.

    Returns
    -------
    ProofResult
        ok, certificate (a JSON-able dict, None unless every check holds), reason (one line: the first check
        that could not be established), checks (name, holds, how), wall_time_s.

    Raises
    ------
    ParameterError
        Never for a failed proof (that is ok = False); only from `validate_params` before.

    Examples
    --------
    >>> from magrod.proof.provers import transverse_homoclinic
    >>> p = transverse_homoclinic.validate_params("1.7", "0.04", "1", "1", "0.01")
    >>> res = transverse_homoclinic.prove(p)  # doctest: +SKIP
    >>> res.ok, res.certificate["crossings"][0]["dtheta_dpsi"]["mid"][:8]  # doctest: +SKIP
    (True, '-0.00229')

    Notes
    -----
    Method: module docstring (saddle by Krawczyk, local manifold by cone conditions, C^1 Lohner flight in the
    body frame to Sigma, interval Newton in the phase).  Cost at the target: ~35-50 s on one core (benchmarks/
    prove_target.py).  Accuracy: every decision is an exact comparison of ball bounds (128-bit Arb).
    References: docs/nonintegrability.md, "Theorem (computer-assisted)".
    """
    st = settings or ProofSettings()
    stage = ["start"]
    params = interval_params(params, st.lam_rad)

    def say(msg):
        stage[0] = msg
        if progress is not None:
            progress(msg)

    return run_checked(st.prec, lambda check: _prove(params, st, module, check, say), reraise_input=True,
                       stage=stage)


def interval_params(p: fields.ExactParams, lam_rad) -> fields.ExactParams:
    """p itself (lam_rad 0), or p with lambdabar the interval [lam - lam_rad, lam + lam_rad] (fields.IntervalParams);
    ParameterError naming lam_rad unless 0 <= lam_rad <= 1 and mu > 2 (lam + lam_rad) (the tilted saddle exists
    for every lambdabar of the interval, eq:alignment_condition)."""
    try:
        w = Fraction(lam_rad)
    except (TypeError, ValueError, ZeroDivisionError):
        raise ParameterError("lam_rad", f"must be an exact number >= 0, got {str(lam_rad)[:40]!r}") from None
    if w < 0 or w > 1:
        raise ParameterError("lam_rad", f"must be in [0, 1], got {lam_rad}")
    if w == 0:
        return p
    if p.mu <= 2 * (p.lam + w):
        raise ParameterError("lam_rad", f"must satisfy mu > 2 (lambdabar + lam_rad) (the tilted saddle exists on the "
                                        f"whole interval; eq:alignment_condition), got lam_rad = {w}")
    return fields.IntervalParams(p.m, p.mu, p.gamma, p.delta, p.lam, lam_rad=w)


def interval_proof_settings(lam_rad, **kw) -> ProofSettings:
    """ProofSettings for a lambdabar interval of half-width lam_rad: the saddle's Krawczyk box and the eigenpair
    boxes widened to hold their motion over the interval (float differences at lambdabar +- 1e-6: |dq*/dlambdabar|
    = 6.8 at the target, 2.6 at Fig 4(a)'s rod: 16 lam_rad leaves room for it; the eigenpairs' enclosures are
    wider, ~270 lam_rad at the target, because Df over the saddle box (radius ~7.5 lam_rad) has entries
    ~5000 lam_rad wide (the chart's 1/sin^3 theta terms at theta0 = 0.14): 1000 lam_rad), the rest as at the
    point."""
    w = Fraction(lam_rad)
    st = ProofSettings(lam_rad=w, **kw)
    return replace(st, saddle_radius=max(st.saddle_radius, 16 * w), eig_rad=max(st.eig_rad, 1000 * w))


def _prove(p, st, module, check, say) -> dict:
    fld = fields.chart_field(p, module)
    say("saddle")
    sd = _float_saddle(p)
    # refined at the centre lambdabar (an interval's field would stop Newton at its width): the anchor of the
    # saddle's affine motion on an interval (saddle_motion) needs x*(lam) to ~1e-25
    xhat = saddle.refine(fields.chart_field(p.centre(), module),
                         [float(v) for v in sd.q])
    J = ball.to_floats(fld.df(xhat).mid())
    w, Vc = np.linalg.eig(J)
    iu = [i for i in range(len(w)) if w[i].real > 0 and w[i].imag > 0]
    is_ = [i for i in range(len(w)) if w[i].real < 0 and w[i].imag > 0]
    check("saddle_focus_float", len(iu) == 1 and len(is_) == 1,
          f"float eigenvalues of the chart Jacobian at the saddle: {np.round(w, 6).tolist()}")
    guess = [(complex(w[iu[0]]), Vc[:, iu[0]]), (complex(w[is_[0]]), Vc[:, is_[0]])]
    E = saddle.enclose(fld, xhat, st.saddle_radius, eig_guess=guess, eig_rad=st.eig_rad)
    for k, v in E.checks.items():
        check(f"saddle_{k}", v, {"krawczyk_inside": "K(X) in the interior of X (unique zero in X)",
                                 "box_R_symmetric": "X is symmetric in (psi, pbar_theta): the zero lies on Fix(R)"}.get(
                                     k, "eigenpair Krawczyk / sign of the enclosed eigenvalue"))
    say("structure")
    pts = [E.xhat] + _orbit_samples(p, E.xhat)
    for name, holds, how in structural_tests(p, module, pts):
        check(name, holds, how)
    say("manifold")
    Vf = np.column_stack(_real_basis(guess[0][1]) + _real_basis(guess[1][1]))
    V = ball.exact_matrix(Vf.tolist())
    man = manifold.choose(fld, E.xhat, V, E.K, st.r)
    for k, v in man.checks.items():
        check(f"manifold_{k}", v, "cone/slab condition of magrod.proof.manifold on the block")
    flow = _FloatFlow(p, E.xhat, V, st.r)
    motion = None
    if st.lam_rad:
        # the circle about the moving saddle, lambdabar a state of the flights (kernel/homoclinic.moving_arc)
        say("saddle motion")
        K0, B, ok = homoclinic_kernel.saddle_motion(p, module, E.xhat, E.K, SADDLE_RADIUS0)
        check("saddle_motion", ok, "Krawczyk at the centre lambdabar and the slope dx*/dlambdabar over the interval")
        U = man.bounds["U"]
        check("moving_circle_inside", U + st.r < man.r_block,
              f"|u*| + r = {float(U + st.r):.6g} < r_block = {float(man.r_block):.6g}")
        K0, B = [_stored_ball(v) for v in K0], [_stored_ball(v) for v in B]
        motion = {"radius0": _q(SADDLE_RADIUS0), "K0": [stored(v) for v in K0], "slope": [stored(v) for v in B]}
        flight = homoclinic_kernel.LamStateFlight(
            p, module, lambda lo, hi: homoclinic_kernel.moving_arc(p, man.V, man.xhat, K0, B, man.L, man.r, lo, hi,
                                                                  module))
    else:
        flight = homoclinic_kernel.PointFlight(p, module, lambda lo, hi: lift_arc(p, man, lo, hi, module))
    g, dg, guard = body_section(flight)
    crossings = []
    for tgt in st.targets:
        say(f"psi = {tgt}")
        phi_f, t_f = flow.phase(TARGETS[tgt])
        phic = ball.fraction(phi_f)
        t_a = Fraction(math.floor((t_f - float(st.lead)) * 2**20), 2**20)
        dphi = st.dphi
        for attempt in range(4):
            rec = _flight(flight, g, dg, guard, phic, dphi, t_a, st)
            ok_newton = rec["newton_inside"]
            if ok_newton or attempt == 3:
                break
            dphi = dphi * 4  # the thin set's Gs enclosure did not fit into the arc: widen it
        c = rec["values"]
        name = f"psi={tgt}"
        check(f"{name}: section_transversal", ball.excludes_zero(c["arc"]["gdot"]),
              f"d/dt (sin theta pbar_theta) over the crossing step = {c['arc']['gdot']}")
        check(f"{name}: psi_branch", (ball.positive if tgt == "0" else ball.negative)(c["arc"]["Gc"]),
              f"Gc = sin(theta) rho cos(psi) = {c['arc']['Gc']} (cos psi {'> 0' if tgt == '0' else '< 0'})")
        check(f"{name}: dpsi_dphi_nonzero", ball.excludes_zero(c["arc"]["dGs"]),
              f"dGs/dphi over the arc = {c['arc']['dGs']}")
        check(f"{name}: unique_zero", ok_newton,
              f"interval Newton phi_c - Gs(phi_c)/dGs = {rec['newton']} inside the arc [{float(phic - dphi):.9g}, "
              f"{float(phic + dphi):.9g}]")
        check(f"{name}: transversality", ball.excludes_zero(c["arc"]["de33"]) and ball.excludes_zero(rec["dtheta_dpsi"]),
              f"dtheta_u/dpsi enclosure {rec['dtheta_dpsi']} (de33/dphi = {c['arc']['de33']})"
              + ("" if ball.excludes_zero(rec["dtheta_dpsi"]) else " contains 0"))
        crossings.append({"target": tgt, "phi_c": _q(phic), "dphi": _q(dphi), "t_a": _q(t_a),
                          "h_cross": _q(2 * st.lead), **rec["record"]})
    digest = fields.source_digest(module)
    check("field_is_derived", digest == fields.source_digest(gen),
          "the vector field is the derive-generated generated/validated.py (SHA-256 of its source)")
    return _certificate(p, st, E, man, crossings, digest, motion)


def _stored_ball(x: arb) -> arb:
    """x as the verifier will read it back from the certificate (stored, then from_json): the flights must start
    from the balls the certificate holds, which contain x."""
    return ball.from_json(stored(x))


def _orbit_samples(p, xhat, n=6) -> list:
    """A few chart states along a float W^u trajectory (where the structural tests are made)."""
    import heyoka as hy  # noqa: F401 - systems builds the integrator

    from ...core import systems

    x0 = np.array([float(v.mid()) for v in xhat]) + np.array([1e-3, 1e-3, 1e-3, 0.0])
    ta = systems.taylor(systems.system("reduced"), x0, np.array(p.floats()))
    out = []
    for t in np.linspace(2.0, 12.0, n):
        ta.propagate_until(float(t))
        out.append([ball.dyadic(v) for v in ta.state])
    return out


def _flight(flight, g, dg, guard, phic, dphi, t_a, st) -> dict:
    """Thin set (phi_c) and arc ([phi_c - dphi, phi_c + dphi]) to the crossing; Newton in phi; d theta/d psi."""
    vals, record = {}, {}
    for kind, lo, hi in (("thin", phic, phic), ("arc", phic - dphi, phic + dphi)):
        S, tangent = flight.lift(lo, hi)
        tr = taylor.Trajectory()
        try:
            S = taylor.propagate(flight.field, S, t_a, order=st.order, tol=st.tol, guard=guard, record=tr)
            cr = taylor.cross_section(flight.field, S, g, dg, 2 * st.lead, st.order, guard=guard)
        except (taylor.EnclosureError, taylor.GuardError, taylor.CrossingError) as err:
            raise ProofFailure(f"flight ({kind}, phi_c = {float(phic):.9g}) not validated: {err}") from None
        q = crossing_quantities(flight, cr, tangent)
        vals[kind] = q
        record[kind] = {"steps": [_exact(h) for h in tr.steps], "guard_min": [float(v) for v in tr.guard_min],
                        "max_width": max(tr.widths), "n_steps": len(tr.steps),
                        "enclosures": {k: stored(v) for k, v in q.items()}}
    thin, arc = vals["thin"], vals["arc"]
    N = ball.q(phic) - thin["Gs"] / arc["dGs"]
    inside = ball.excludes_zero(arc["dGs"]) and _interior(N, ball.interval(phic - dphi, phic + dphi))
    dtdp = -arc["de33"] * arc["Gc"] / (arc["s2"].sqrt() * arc["dGs"])
    record["newton"] = stored(N)
    record["dtheta_dpsi"] = stored(dtdp)
    return {"values": vals, "newton": N, "newton_inside": inside, "dtheta_dpsi": dtdp, "record": record}


def _eig_input(inp) -> dict:
    lam, v, k = inp
    return {"lam": [_exact(lam.real), _exact(lam.imag)], "v": [[_exact(z.real), _exact(z.imag)] for z in v], "k": k}


def _interior(a: arb, b: arb) -> bool:
    lo, hi = ball.bounds(a)
    blo, bhi = ball.bounds(b)
    return blo < lo and hi < bhi


def stored(x: arb) -> dict:
    """The certificate's ball for an enclosure x: x widened by 2^-10 of its radius plus 2^-(prec - 8) of its
    midpoint, so that a verifier whose last-bit rounding differs (another python-flint build) still finds its
    recomputation inside; any tampering larger than that widening is detected."""
    m, r = ball.mid_rad(x)
    from flint import ctx

    slack = r / 1024 + abs(m) * Fraction(1, 2 ** (ctx.prec - 8)) + Fraction(1, 2 ** (2 * ctx.prec))
    return ball.to_json(arb(x.mid(), x.rad() + ball.q(slack)))


def _cb(z):
    return {"re": stored(z.real), "im": stored(z.imag)}


def _certificate(p, st, E, man, crossings, digest, motion=None) -> dict:
    cb = _cb

    return {
        "format": FORMAT,
        # the text the verifier regenerates from what it verified and requires verbatim (magrod.proof.theorem)
        "theorem": homoclinic_theorem(p.as_json(), [c["target"] for c in crossings], _q(st.lam_rad)),
        "params": p.as_json(),
        "settings": st.as_json(),
        "field_digest": digest,
        "saddle": {"xhat": [_exact(v) for v in E.xhat], "radius": _q(st.saddle_radius),
                   "K": [stored(v) for v in E.K],
                   "eig_input_u": _eig_input(E.eig_inputs[0]), "eig_input_s": _eig_input(E.eig_inputs[1]),
                   "lam_u": cb(E.lam_u), "lam_s": cb(E.lam_s),
                   "v_u": [cb(z) for z in E.v_u], "v_s": [cb(z) for z in E.v_s], **(motion or {})},
        "manifold": {"V": [[_exact(man.V[i, j]) for j in range(man.V.ncols())] for i in range(man.V.nrows())],
                     "r_block": _q(man.r_block), "rho": _q(man.rho), "L": _q(man.L), "r": _q(man.r),
                     "rho_eff": _q(man.rho_eff),
                     "bounds": {k: _q(v) for k, v in man.bounds.items()}},
        "crossings": crossings,
        "hypotheses_symbolic": ["reversor_reduced", "validated_fields", "chart_body_lift", "casimirs", "force",
                                "poisson_map", "full_ham_nondim"],
    }
