"""Every tolerance of magrod's numerics, defined once, with the reason for its value.

Modules import these names; none defines its own copy.  A tolerance here is a property of a method (a multiple
of the unit roundoff, a measured floor with its margin) -- never an unexplained number.
"""
from __future__ import annotations

import math

from .precision import Precision

EPS = 2.0**-52  # float64 machine epsilon (np.finfo(float).eps), spelled out so this module needs no numpy

# --- accuracy gates of results (verify=True) ------------------------------------------------------------------
# Integrated with tol = eps, Hbar and the Casimirs drift by ~1e-13 over the paper's 10 000 iterates (measured on
# every Fig 4/5 panel, benchmarks/README.md); a drift above these bounds means the run did not do what it claims
# (e.g. a damaged compiled integrator from the JIT cache) and the result is refused.
ENERGY_TOL = 1e-10
CASIMIR_TOL = 1e-10
# A start given with its pbar_psi0 (a chart point) belongs to the level Hbar = h of a section portrait if
# |Hbar(start) - h| <= START_LEVEL_TOL: the same bound the result's own gate puts on every section point, so a
# start that passes cannot make its orbit fail the gate at t = 0.
START_LEVEL_TOL = ENERGY_TOL
# A chaos-indicator orbit whose first integrals drift by more than this has left its invariant set: nothing
# computed on it is trusted (the paper's runs keep them to ~1e-13).
DRIFT_LIMIT = 1e-8

# --- saddles ----------------------------------------------------------------------------------------------------
# mu = 2 lam is a condition on the input: accept the rounding of a decimal input (64 ulp), nothing more
MU_TOL = 64 * EPS
# Re(eigenvalue) below this is not hyperbolic: the Jacobian is computed to ~eps, and eigenvalues of a defective
# quartet (m = m_c, Hamiltonian-Hopf) split like sqrt(eps)
HYPERBOLIC_TOL = 1e3 * math.sqrt(EPS)

# --- shooting onto Fix(R) ---------------------------------------------------------------------------------------
# Newton converged iff max |(pbar_theta, sin psi)(x(T))| <= SHOOTING_TOL
SHOOTING_TOL = 1e-10
# distance of the launch point from the saddle on its linear unstable manifold, per precision: the O(eps^2)
# launch error stays below the residual floor of that precision (docs/errata.md: lam* insensitive to it)
LAUNCH_DISTANCE = {Precision.DOUBLE: 1e-7, Precision.LONG_DOUBLE: 1e-9}
# the two launch distances of an uncertainty estimate (a different eps is a different launch phase)
LAUNCH_DISTANCES = (1e-7, 1e-9)
# Newton stops after this many iterations without halving the best residual (it then samples rounding noise)
STALL_ITERATIONS = 4
# "within the floor" means best residual <= FLOOR_FACTOR x the measured floor (the floor is a max over 8 samples
# of noise about a smooth fit through the best iterate, which carries noise of the same size)
FLOOR_FACTOR = 2.0
# a stalled Newton counts as converged only below this: the double floor after near-saddle passages is
# 1e-8..1e-7; 1e-6 rad from Fix(R) is far below any feature of the orbit
FLOOR_CAP = 1e-6

# --- splitting of the separatrix --------------------------------------------------------------------------------
# launch distance (relative to theta0 for the tilted saddle) per precision: its square below the rounding unit
SPLITTING_LAUNCH = {Precision.DOUBLE: 1e-8, Precision.LONG_DOUBLE: 1e-10, Precision.QUAD: 1e-17, Precision.MP: 1e-30}

# --- root finding and bisection (every tolerance here, none as a literal elsewhere) ------------------------------
# pbar_psi0 roots of Hbar = h are O(1): Brent to 1e-15 absolute, then the best of the neighbouring doubles is kept
ROOT_XTOL = 1e-15
# bisection of sin psi over the free parameter stops at a few ulp of relative width (inside the noise band it just
# picks a point in it: magrod.orbits.multipulse.bisect)
BISECTION_RTOL = 1e-15
# the Fig 2 Mel'nikov amplitude's zero gamma* by Brent on the float64 amplitude: its own error bound is ~1e-13
MELNIKOV_ZERO_XTOL = 1e-13
# the accessible-threshold line of a section portrait (a figure annotation): 1e-6 of a lambdabar range of O(0.1)
THRESHOLD_XTOL = 1e-6

# --- saddles and branches -----------------------------------------------------------------------------------------
# Gauss-Newton residual of the helical relative equilibrium (its equations are O(1); converged runs reach ~1e-20)
RELATIVE_EQUILIBRIUM_TOL = 1e-13
# eigenvalues that agree to this (relative) count as one for ordering (core.eigen.order): LAPACK's rounding then
# cannot swap members of a conjugate pair or a quartet
EIGEN_TIE_TOL = 1e-9
# continuation's Newton corrector: the shooting residual bound
CONTINUATION_TOL = SHOOTING_TOL
# the 2-pulse branch to the periodic saddle folding in mu (docs/errata.md): its long double residual floor is
# 1e-13 .. 1e-12, so the corrector runs at 2e-12 (tests/test_continuation.py, figures/continuation.py)
FOLD_BRANCH_TOL = 2e-12

# --- quadratures ---------------------------------------------------------------------------------------------------
# the real128 reference runs of the Mel'nikov and splitting quadratures: heyoka's tolerance near real128's epsilon
# (1.9e-34) with room for its step-size control; a string because real128 tolerances are passed exactly
REAL128_QUADRATURE_TOL = "1e-32"
# derived vs measured a > 2b splitting coefficient: the relative bound asked of it (magrod.separatrix.generic)
GENERIC_AGREEMENT = 1e-4

# The starts of a model's section (magrod/chaos/model_chaos.py) are put on the level of H and the Casimirs
# by Gauss-Newton steps until |g(x) - g0| <= MODEL_LEVEL_TOL: a few ulp of the O(1) values, far inside the
# conservation gates ENERGY_TOL and CASIMIR_TOL the sections are then held to.
MODEL_LEVEL_TOL = 64 * EPS

# --- computer-assisted proofs and rigorous enclosures ---------------------------------------------------------------
# The validated Taylor integrator (magrod.proof.taylor) picks each step so that the centre trajectory's last two
# Taylor terms are ~PROOF_STEP_TOL (Jorba-Zou): the Lagrange remainder then adds ~1e-25 per step, ~1e-22 over the
# ~10^3 steps of a flight, far below the 1e-12 .. 1e-5 radii of every box a proof flies (so it never decides a
# check), and above the 128-bit rounding (~1e-38 relative), so the steps are not wasted on rounding noise.  A step
# control, not an accuracy claim: every enclosure is rigorous whatever its value.
PROOF_STEP_TOL = 1e-25
# the horseshoe's centre flights (statement 12): at PROOF_STEP_TOL their enclosures after one return are
# 1e-14..2e-13, too wide to resolve the sets N13, N14 (N12 => N13 failed with y_s in +-11.8); at 1e-32 they are
# ~5e-20 (2.3x the steps).  The pieces' flights stay at PROOF_STEP_TOL.
HORSESHOE_CENTRE_TOL = 1e-32
# the same at Fig 4(b) (magrod/proof/designs/fig4b.json, whose sets are >= 7e-11, entry widths times sin(angle) >= 1.5e-11):
# the return from x0 (T = 5.13) encloses P(x0) to 8e-10 at 1e-25 (152 steps), 2.6e-10 at 1e-26, 3.5e-12 at 1e-27
# (192), 4.5e-14 at 1e-28 (217), 3.6e-19 at 1e-32 (353 steps); the first run at 1e-25 failed at N9 => N10 (a') with
# the centre's offset alone y_s in +-0.300.  1e-28 resolves the sets at 0.6x the steps of 1e-32.
HORSESHOE_CENTRE_TOL_FIG4B = 1e-28
# magrod.separatrix.enclosure.enclose_S: the improper integral is cut at T where its rigorous tail bound is
# <= ENCLOSURE_TAIL_TOL; 1e-20 is far below |S| (>= 9e-5 on the box of statement 2) and the 1e-10 asked of the six table
# points, and costs only a few units of tau_T (the tail decays like e^(-kappa T)).
ENCLOSURE_TAIL_TOL = 1e-20
# box_theorem decides the sign of S on a box: the tail only has to be small against |S| there (>= 9e-5), so 1e-8
# keeps T short (the boxes' cost grows with T) with a margin of 10^4.
BOX_TAIL_TOL = 1e-8
# box_theorem(order=2): the absolute accuracy asked of acb.integral for the centre value and gradient of S (the
# balls are rigorous whatever is asked; this only decides how hard Arb works): small against |S| >= 1e-5 on the
# corner next to m_c, and 1e-12 costs little more than 1e-8.
BOX_CENTRE_ABS_TOL = 1e-12
# The float search of magrod.proof.provers.section_fixed_point (where to look for the section map's symmetric fixed point): heyoka at
# 1e-15 keeps the bisected theta* (and the half-way crossing time) within ~1e-13 of the true ones over the ~3-unit
# half-orbit, far inside the 1e-10 .. 4e-6 theta-boxes the proof then decides on; a search choice, never a decision.
FIXED_POINT_SEARCH_TOL = 1e-15
# An orbit file of another model (magrod.orbits.reversible.orbit_from_file) is re-shot, not trusted: the saddle, its
# phase-fixed unstable eigenvector and the reversor are recomputed in the same arithmetic, so the launch point and
# the reversor's matrix reproduce the file's to rounding (measured: 0 for the anisotropic rod); 1e3 eps relative to
# the state's size separates rounding from a changed model (an edited model file moves them by far more).
ORBIT_FILE_TOL = 1e3 * EPS

# --- symmetric homoclinic orbits of any model (magrod/orbits/reversible.py) ------------------------------------------
# Newton on the Fix(R) condition has converged when max |x_flipped(T)| <= this: the floor is ~ eps / delta (rounding
# amplified along W^u from the launch distance delta = 1e-6), ~1e-10, with a margin of 10.
SYMMETRIC_ORBIT_TOL = 1e-9
# Two reversors found by the scan of body-frame reflections are the same one when their matrices agree to this: the
# scan bisects the reflection angle to ~1e-12, so distinct reversors (entries differing by O(1)) are never merged.
REVERSOR_MATCH_TOL = 1e-9
