r"""The verdict on nonintegrability as data: numbered statements, each with the chain of steps it rests on.

A statement's status is *computed* from its chain, never typed: the weakest step decides (a step that cites another
statement inherits that statement's status).  docs/nonintegrability.md ("Verdict") and README.md ("What the
reproduction found") carry blocks rendered from this list (`render_verdict`, `render_summary`, `render_readme`);
tests/test_proof_statements.py fails if a block is stale, or if a "proved" / "computer-verified" label is attached
anywhere in README, docs or REPORT to a statement whose chain holds a conditional, heuristic or numerical step.

Statuses, strongest first (DESIGN.md, "Rigour"):
  proved             a symbolic identity in derive/ (report key given), or a cited theorem whose hypotheses are
                     all checked
  computer-verified  a rigorous enclosure (ball arithmetic, every rounding and truncation bounded)
  conditional        holds if the named hypothesis holds
  numerical          floating point with its error evidence
  heuristic          an analogy with theorems whose hypotheses are not met
Rewrite the blocks after an edit: `python -m magrod.proof.statements --write`.

The data is written in Unicode (H̄, λ̄, W^u, 10⁻¹³), as a terminal shows it; the blocks rendered into README.md and
docs/ carry its mathematics as myst dollar math ($\bar H$, $\bar\lambda$, $W^u$, $10^{-13}$), typeset by MathJax
(`markdown`), and the label check reads them back (`plain`).
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

RANK = {"proved": 4, "computer-verified": 3, "conditional": 2, "numerical": 1, "heuristic": 0}
RIGOROUS = ("proved", "computer-verified")
WEAK = ("conditional", "numerical", "heuristic")


@dataclass(frozen=True)
class Step:
    """One link of a chain: what it establishes, its status (or `ref`, another statement's number), and how."""

    what: str
    status: str | None = None
    how: str = ""
    ref: str | None = None


@dataclass(frozen=True)
class Statement:
    number: str
    title: str
    text: str  # markdown, one paragraph; the rendered label is prepended
    chain: tuple = ()
    #: regular expressions that identify the statement in prose (besides "statement N")
    phrases: tuple = field(default_factory=tuple)


def _s(number, title, text, chain, phrases=()):
    return Statement(number, title, " ".join(text.split()), tuple(chain), tuple(phrases))


STATEMENTS = (
    _s("1", "the printed Mel'nikov function vanishes",
       """The paper's first-order Mel'nikov function vanishes identically for all (m, γ, δ, a, b)
       (`melnikov_vanishes`); the printed nonintegrability argument (sec. 7, Corollary) proves nothing.""",
       [Step("the first-order Mel'nikov integrand is an exact derivative", "proved", "report key melnikov_vanishes")]),
    _s("2", "S is non-zero",
       """The second-order integral S is non-zero (negative) at the six (m, γ, δ) of the table and on every box
       decided by `benchmarks/enclosure_boxes.py` and (second-order form) `benchmarks/enclosure_corner.py`: 99.84 %
       of the box m ∈ [1, 2.2] × γ ∈ [1/4, 3] × δ ∈ [1/4, 3], all but part of the corner next to m_c
       (inside m ∈ [2.141, 2.2], γ ∈ [1/4, 0.363]), where it is verified at isolated grid points only
       (`enclose_S`, `box_theorem`); at γ = δ = 0 the ball contains 0 (S = 0 exactly there). S is
       the value of a formula; that it is the leading coefficient of the splitting is statement 3
       (conditional).""",
       [Step("the phase in closed form, the integrand's ball form", "proved",
             "report keys splitting_phase_closed_form, splitting_integrand_ball"),
        Step("S in ball arithmetic: Petras quadrature with error bounds, rigorous tail", "computer-verified",
             "magrod.separatrix.enclosure.enclose_S, box_theorem")]),
    _s("3", "the formal expansion",
       """Conditional on the validity of the first-order expansion in λ̄, uniformly as the saddle (a = 2b: the
       straight rod; a > 2b: the saddle-focus at θ0 = O(ε)) approaches the chart singularity θ = 0 where the
       blown-up field is singular (K2 ∋ J²/(2 sin²θ)). Then ψ_u = λ̄S/tan(θt/2) + O(λ̄²) at a = 2b and
       s1/ε³ → b√(a − 2b) S/(V′(θt)(1 + cos θt)) for a > 2b (every identity of the chain is a symbolic identity:
       `splitting_*`, `generic_*`). Evidence for the hypothesis (numerical): 8–9 digits at six a = 2b cases;
       ≤ 1.4e−5 at eight a > 2b cases, two precisions each.""",
       [Step("the blow-up, the unperturbed manifold, the parity of N, the a > 2b identities", "proved",
             "report keys splitting_*, generic_*"),
        Step("the O(λ̄²) remainder is uniformly small up to θ = 0", "conditional",
             "hypothesis H3; evidence numerical (8-9 digits, 1.4e-5)")],
       phrases=(r"formal (first-order )?expansion", r"leading coefficient of the splitting")),
    _s("4", "transversality for small ε",
       """Conditional on 3 (with 2 supplying S ≠ 0). For a > 2b and ε small, D′(0) = 2 s1 + O(ε⁴) ≠ 0 and
       D′(π) ≠ 0: W^u and W^s of the tilted saddle-focus intersect transversally in the energy level along two
       symmetric homoclinic orbits (the zeros themselves are forced by reversibility; their simplicity is the
       content).""",
       [Step("S ≠ 0", ref="2"), Step("s1 is b√(a − 2b) S/(V′(1 + cos)) ε³ + O(ε⁴)", ref="3")],
       phrases=(r"ε small", r"small ε", r"perturbative regime")),
    _s("5", "the theorem at one point",
       """At (m, μ, γ, δ, λ̄) = (17/10, 1/25, 1, 1, 1/100) the saddle-focus and both transverse symmetric homoclinic
       orbits exist, with a certificate re-checked by the complete verifier (section "Theorem (computer-assisted)"):
       statement 4 holds there without hypothesis 3. With Devaney's theorem (hypotheses checked: analytic
       2-degree-of-freedom Hamiltonian on the chart, saddle-focus, transverse homoclinic orbit) the saddle's energy
       level carries horseshoes (positive topological entropy); with Kozlov's argument (θ > 0 along the orbit, from
       the certificate's guards) no real-analytic integral of the chart system is independent of H̄ on that
       level. Quantified in λ̄ (m, μ, γ, δ fixed): all of this holds for every λ̄ in [1/100 − 10⁻⁹, 1/100 + 10⁻⁹],
       by a second certificate whose boundary circle is centred on the moving saddle x*(λ̄) (its affine motion
       x*(λ̄) ∈ K0 + B (λ̄ − 1/100), B ∋ dx*/dλ̄ over the interval, re-checked) and whose flights carry λ̄ as a state
       (homoclinic_target_interval.json, `magrod prove --lam-rad 1/1000000000`: prove 21 s, verify 7 s;
       dθ_u/dψ ∈ [−0.002717, −0.001907] at ψ = 0 and [0.000954, 0.001462] at ψ = π). 2·10⁻⁹ still proves,
       4·10⁻⁹ does not (`research/homoclinic_interval.py`): the interval Newton image in the phase, 5.8·10⁻⁶ at
       10⁻⁹, grows faster than the half-width beyond it (8.8·10⁻⁵ at 4·10⁻⁹, against the widest arc 3.2·10⁻⁵).
       About the fixed saddle x*(1/100) the limit was 1.5·10⁻¹³: on that circle the phase itself moves
       2.2·10⁶ × the half-width, on one about the moving saddle 7.9 × (`research/homoclinic_phase_motion.py`). Beyond that
       interval: hyperbolic equilibria and transverse intersections persist, so all of this holds on an open
       neighbourhood of the parameters, of unquantified size (cited persistence, hypotheses: the checked
       hyperbolicity and transversality, analytic dependence on the parameters).""",
       [Step("saddle, eigenpairs, local manifold, flight, crossings, transversality", "computer-verified",
             "magrod prove; magrod prove --verify (complete verifier)"),
        Step("the same on the λ̄ interval, λ̄ a ball in every enclosure", "computer-verified",
             "magrod prove --lam-rad; magrod prove --verify"),
        Step("the chart field is Hamilton's, R is a reversor, the lift intertwines the flows", "proved",
             "f = J∇H̄, f(Rx) = −R f(x) and the lift's intertwining f_body(X) = DX f + Ω G X (with the body field "
             "commuting with the rotation about d3) checked by the verifier at run time on the certificate's field, "
             "as exact identities (magrod/proof/identities.py); derived as report keys validated_fields, "
             "reversor_reduced, chart_body_lift"),
        Step("horseshoes (Devaney 1976) and no analytic second integral on the level (Kozlov 1996)", "proved",
             "cited theorems, every hypothesis checked by the certificate")],
       phrases=(r"one parameter point", r"17/10, 1/25")),
    _s("5a", "the theorem at Fig 4's rod, on the saddle's own level",
       """At (m, μ, γ, δ) = (17/10, 2/5, 3, 3), the rod of Fig 4 (non-perturbative: γ = δ = 3, μ − 2λ̄ ≈ 0.03–0.13),
       at each of the four panels' λ̄ = 27/200, 63/400, 7/40, 93/500: the tilted saddle-focus (eigenvalues
       ±1.112 ± 0.079i, ±1.088 ± 0.015i, ±1.073 ± 0.095i, ±1.065 ± 0.147i) has transverse symmetric homoclinic
       orbits: two at (a) and (b), dθ_u/dψ ∈ [−0.2879, −0.2818] at ψ = 0 and [0.03001, 0.03064] at ψ = π (a),
       [−0.3875, −0.3807] and [0.005909, 0.006052] (b); one at (c) and (d), at ψ = 0, dθ_u/dψ ∈ [0.01034, 0.01081]
       (c) and [0.3562, 0.4067] (d) (magrod/proof/certificates/homoclinic_fig4{a,b,c,d}.json, re-checked by the
       complete verifier; `magrod prove --m 1.7 --mu 0.4 --gamma 3 --delta 3 --lam 0.135`, and `--targets 0` at
       0.175, 0.186, where the float search finds no ψ = π crossing). With Devaney's and Kozlov's theorems as in 5
       (one transverse homoclinic orbit suffices): horseshoes and no real-analytic integral independent of H̄ on
       the saddle's level H̄(q*). That level is not the figure's h = 0.9 (the helix's H̄ is 0.8305, 0.7720, 0.7253,
       0.6955), so this is not a proof about Fig 4's section (statement 10).""",
       [Step("saddle, eigenpairs, local manifold, flight, crossings, transversality", "computer-verified",
             "magrod prove; magrod prove --verify (complete verifier)"),
        Step("the chart field is Hamilton's, R is a reversor, the lift intertwines the flows", "proved",
             "f = J∇H̄, f(Rx) = −R f(x) and the lift's intertwining f_body(X) = DX f + Ω G X (with the body field "
             "commuting with the rotation about d3) checked by the verifier at run time on the certificate's field, "
             "as exact identities (magrod/proof/identities.py); derived as report keys validated_fields, "
             "reversor_reduced, chart_body_lift"),
        Step("horseshoes (Devaney 1976) and no analytic second integral on the level (Kozlov 1996)", "proved",
             "cited theorems, every hypothesis checked by the certificate")],
       phrases=(r"2/5, 3, 3", r"Fig 4\(a\)'s rod", r"Fig 4's rod")),
    _s("6", "cited theorems",
       """Published theorems these plug into, with their hypotheses, are in the table below; a theorem is used as a
       step of a chain only where every hypothesis is checked (the saddle-centre theorems are not: statement 8).""",
       [Step("the table of cited theorems", "proved", "hypotheses checked row by row")]),
    _s("7", "the 9-D rod at the point of 5",
       """For the 9-D body system at the leaves whose (m, μ, λ̄) are those of 5 (γ = δ = 1) or of 5a (γ = δ = 3),
       and on open neighbourhoods of them: no real-analytic
       function F in involution with H and with m3, defined near the set {H = H(q*), m3 = m3*} of the leaf, is
       independent of H, m3 and the Casimirs on the component of that set which contains the homoclinic orbits
       (the S¹-orbits over the homoclinic orbits of 5). Proof: {F, m3} = 0 makes F∘X independent of the angle φ
       (`s1_descent`, with `poisson_map`), so F descends to an integral of the chart system on the level of 5;
       Kozlov's conclusion (5) makes it locally constant on the component of the level that holds the homoclinic
       orbits, hence F is locally constant on the S¹-orbits over it. The
       statement is about integrals in involution with m3; an integral F with {F, m3} ≠ 0 is not covered (its
       S¹-average may be dependent), which is statement 7b.""",
       [Step("no analytic integral of the chart independent of H̄ on the level", ref="5"),
        Step("the same at the rod of Fig 4(a)", ref="5a"),
        Step("an integral in involution with m3 descends to the chart", "proved", "report keys s1_descent, "
             "poisson_map (on the chart: sin θ ≠ 0, ρ ≠ 0)")],
       phrases=(r"in involution with m3",)),
    _s("7b", "the 9-D rod, every integral; the perturbative regime",
       """Conditional on the averaging gap, and on 4 for the perturbative regime: the 9-D body system has no
       additional real-analytic integral at all (not only none in involution with m3) on the leaves of 7, and the
       conclusions of 5 and 7 hold near the paper's perturbative regime (a > 2b, ε small). The step from an
       integral F with {F, m3} ≠ 0 to the chart (average over the S¹ of rotations about d3, or its Fourier modes)
       is not closed: the average may be a function of H, m3 and the Casimirs.""",
       [Step("statement 7 at the point and its persistence", ref="7"),
        Step("an integral with {F, m3} ≠ 0 has an independent S¹-average", "conditional",
             "the averaging gap (not closed)"),
        Step("small ε", ref="4")],
       phrases=(r"nonintegrability of the (extensible )?(magnetic )?rod(?![^.;]*in involution with m3)",
                r"every (additional )?integral", r"9-D (rod|body system)(?![^.;]*(in involution with m3|of 7|at the point of 5))")),
    _s("8", "the a = 2b offset and saddle-centre theory",
       """Heuristic. On μ = 2λ̄ the straight rod is, in the reduced system, a saddle-centre (hyperbolic in (θ, p̄θ),
       elliptic in the transverse force); at λ̄ = 0 it has a homoclinic loop (the closed form), and S ≠ 0 (2) says
       the loop breaks at first order (3): the offset is ρ sin ψ_u = λ̄²S. The saddle-centre theorems (Lerman 1991,
       Mielke–Holmes–O'Reilly 1992, Grotta-Ragazzo 1997) suggest transverse homoclinic orbits to the Lyapunov orbits
       on the nearby levels, and homoclinic orbits to the saddle-centre itself only at isolated λ̄ — as measured
       (the periodic saddle's primaries iff ν ≥ λ̄⁴S², the multipulse orbits of errata sec. 8 at λ̄* ≠ the printed
       values). They do not apply as theorems: they assume a homoclinic loop in the system itself plus a
       nondegeneracy condition, whereas here the loop exists only at λ̄ = 0, where the system is integrable; the
       "Lyapunov orbits" are identified with tilted saddles on other Casimir leaves; and the straight rod is a
       singular point of the S¹ reduction. Not implied: a primary symmetric homoclinic orbit to the straight rod on
       μ = 2λ̄ for small λ̄ (there is none: S ≠ 0), nor nonintegrability on the level μ = 2λ̄ itself.""",
       [Step("S ≠ 0", ref="2"), Step("the offset is λ̄²S", ref="3"),
        Step("the saddle-centre theorems, outside their hypotheses", "heuristic",
             "loop only at the integrable λ̄ = 0; Lyapunov orbits on other leaves; singular point of the reduction")],
       phrases=(r"saddle-cent(re|er)", r"Lyapunov orbits?")),
    _s("9", "no polynomial integral of degree ≤ 6",
       """Exact modular certificate (`magrod check --integrals`, magrod/integrability/first_integrals.py). The 9-D
       extensible magnetic rod (B1 = B2, c_J = c_H, c_K, λ generic) has no polynomial first integral of degree ≤ 6
       in (m, n, e3) beyond the polynomials in C1, C2, C3, H, m3, at the seeded random rational parameters and
       hence for all parameters outside a proper algebraic subset; controls: λ = 0 finds n·m, the inextensible rod
       I2, the anisotropic rod loses m3. Says nothing about non-polynomial integrals.""",
       [Step("the kernel of the integral condition, exact (modular rank bounds the rational one)", "proved",
             "magrod check --integrals")],
       phrases=(r"polynomial first integral",)),
    _s("10", "the paper's figures",
       """The Poincaré sections of Figs 4–5 look chaotic (at parameters where the rod's stretch goes negative,
       errata), and the chaos indicator classifies Fig 4(a)–(c) chaotic and 4(d) regular: evidence, not a proof,
       for the non-perturbative regime. Fig 4's level h = 0.9 does not contain the helical saddle (its H̄ is
       0.8305, 0.7720, 0.7253, 0.6955 at the four λ̄), so the homoclinic orbits of 5a are not about the figure's
       section; a horseshoe of P on Fig 4's own level h = 9/10 is computer-verified at every panel (statement
       12), at (d) too, where the indicator sees no chaos: a thin chaotic layer; on Fig 5's own level h = 4/5 the
       saddle of P and a horseshoe of P
       are computer-verified at the four panels (statement 13). Numerically (float64) at λ̄ = 0.135 the unstable
       manifold of the section map's symmetric saddle (the fixed point of statement 11; eigenvalue 5.748 of DP,
       33.04 of DP²) meets Fix(R) transversally (W^u and W^s cross at 0.72°): a candidate, not a proof
       (docs/nonintegrability.md, "Fig 4 on its own level").""",
       [Step("Poincaré sections and Lyapunov/FLI indicators in floating point, conservation budgets", "numerical",
             "magrod poincare, magrod lyapunov")],
       phrases=(r"Figs? 4(?!\(a\)'s rod|'s rod|'s own level h = 9/10|'s section level h = 9/10)",
                r"Figs? 5(?!'s own level|'s caption|'s level h = 4/5)",
                r"h = 0\.9(?! \(statement 11)", r"Poincaré sections?")),
    _s("11", "a saddle of the section map on Fig 4's section level h = 9/10",
       """At (m, μ, γ, δ) = (17/10, 2/5, 3, 3) on Fig 4's section level h = 9/10 (the level the figure shows), at
       λ̄ = 27/200, 63/400 and 93/500 (panels (a), (b), (d)): the section map P of {sin ψ = 0, d sin ψ/dt > 0} has a
       fixed point x0 on Fix(R), θ* = 0.3830461903149027 ± 9e−16 (a), 0.2830297097565 ± 6e−11 (b), 3.0572884842554857 ±
       1e−18 (d), whose orbit is periodic with return time T ∈ [5.7054660731, 5.7054660794] (a), [5.1345326717,
       5.1345326773] (b), [3.1910215795, 3.1910215818] (d), and DP(x0) is a saddle: det 1, tr DP(x0) ∈ [5.92198,
       5.92214] (a), [3.4896, 3.5376] (b), [2.23400, 2.23406] (d), so μ_u ∈ [5.74801, 5.74817], [3.1745, 3.2278],
       [1.61469, 1.61477] (magrod/proof/certificates/fixed_point_fig4{a,b,d}.json, re-checked by the complete
       verifier; `magrod prove --fixed-point 0.383 --level 0.9 --m 1.7 --mu 0.4 --gamma 3 --delta 3 --lam
       0.135`). At (a) also for every λ̄ in [13499/100000, 13501/100000] = 0.135 ± 10⁻⁵, λ̄ carried as a state
       variable through every enclosure and the θ-box following the fixed point, θ = θc + v (λ̄ − 0.135) ± 2·10⁻⁵
       with v = −85747/16384, the slope dθ*/dλ̄ to 16 bits (fixed_point_fig4a_interval.json, `--lam-rad 1/100000`: prove 2 s, verify
       2 s): θ* ∈ [0.3829777, 0.3831147], tr DP(x0) ∈ [3.8285, 8.0158] (tr = 2 + 4bc, since the half-map A between
       ψ = 0 and ψ = π has det A = 1: Hamilton's flow preserves dθ∧dp̄θ between the two sections); 1.2·10⁻⁵ fails
       at the Fix(R) Newton step, whose image grows like the square of the half-width (a box the same for every λ̄
       closed at 1.2·10⁻⁶ only: its derivative enclosures spanned the fixed point's whole motion,
       `research/fixed_point_interval_limits.py`). By 21 adjacent such boxes, for every λ̄ in [13479/100000,
       13521/100000] = 0.135 ± 2.1·10⁻⁴ (magrod/proof/certificates/fig4a_interval/,
       `research/fig4_lambda_interval.py`: 2–3 s prove + 2–3 s verify per box, each certificate re-checked by the
       complete verifier in that run and by a slow test, their union checked exactly by `tiling.chain_interval`;
       `magrod reproduce` verifies only the single box). Panel (c): the float search found no hyperbolic fixed point of P to prove
       (its horseshoe in statement 12 is built on a periodic orbit of period 6 instead). This is a hyperbolic
       periodic orbit, not chaos by itself: the horseshoe on that level at panels (a) and (b) is statement 12,
       built on this saddle's homoclinic orbit. A hyperbolic fixed point persists, so the same holds on an open interval of
       λ̄ around each value, of unquantified size.""",
       [Step("level, two-phase flight (no positive crossing before the half-way point), Fix(R) Newton, |tr DP| > 2",
             "computer-verified", "magrod prove --fixed-point; magrod prove --verify (complete verifier)"),
        Step("the chart field is Hamilton's, R is a reversor", "proved", "f = J∇H̄ (det DP = 1) and "
             "f(Rx) = −R f(x) checked by the verifier at run time on the certificate's field, as exact "
             "identities (magrod/proof/identities.py); report keys validated_fields, reversor_reduced"),
        Step("an orbit through two points of Fix(R) is periodic, crossings at ±t have one direction, DQ2 = R DQ⁻¹ R "
             "(reversibility; Devaney 1976)", "proved", "the argument of magrod/proof/provers/section_fixed_point.py, hypotheses "
             "checked by the certificate"),
        Step("the half-map A between ψ = 0 and ψ = π has det A = 1, so tr DP(x0) = 2 + 4bc (Hamilton's flow "
             "preserves dθ∧dp̄θ + dψ∧dp̄ψ; on the level's tangents with dψ = 0 the flow direction adds nothing)",
             "proved", "the argument of magrod/proof/provers/section_fixed_point.py (step 5), from report key validated_fields")],
       phrases=(r"fixed point of (the section map )?P", r"section map's (symmetric )?saddle", r"h = 9/10")),
    _s("12", "a horseshoe of the section map on Fig 4's own level h = 9/10, every panel",
       """At (m, μ, γ, δ) = (17/10, 2/5, 3, 3) and λ̄ = 27/200 (panel (a)) and 63/400 (panel (b)), on Fig 4's own
       level h = 9/10, the section map P of {sin ψ = 0, d sin ψ/dt > 0} has positive topological entropy: a
       compact forward-invariant set Λ with h_top(P|Λ) ≥ log ρ > 0.0882, ρ the largest root of x²⁸ = x²⁷ + 1 (a),
       and > 0.0707, x³⁸ = x³⁷ + 1 (b) (a horseshoe of P^n). At (a) 15 h-sets (parallelograms in (θ, p̄θ),
       half-sizes 1.3·10⁻¹⁰ … 1.4·10⁻¹³), at (b) 20 (4.7·10⁻⁹ … 2.2·10⁻¹¹; N17–N19 on the ψ = π branch of Σ+):
       N0 at the saddle x0 of statement 11 and N1 … Nk along its homoclinic orbit (W^u of x0 meets Fix(R) at the
       8th return (a), the 14th (b)) carry the covering relations N0 ⇒ N0 and N0 ⇒ N1 ⇒ … ⇒ Nk (Zgliczyński &
       Gidea 2004), each checked on validated C¹ returns of the set (one piece per set, two for N16 at (b)); N0
       and Nk are R-symmetric and N0 is disjoint from the others, so reversibility closes the chain into a loop of
       length 2k through N0 (docs/nonintegrability.md, "A horseshoe on Fig 4's own level").
       Certificates magrod/proof/certificates/horseshoe_fig4a.json and horseshoe_fig4b.json, re-checked by the
       verifier (kind section_horseshoe; `magrod prove --horseshoe 0.383 --level 0.9 --m 1.7 --mu 0.4 --gamma 3
       --delta 3 --lam 0.135`, and `--horseshoe 0.283 ... --lam 0.1575 --design fig4b`). (a): prove 338 s on 2
       cores; verify 44–58 s of CPU, with Newton's series and the sets in two processes, so the full `magrod
       reproduce` re-checks it and REPORT has its row; `--quick` does not, and says so. (b): prove 323 s on 2
       cores (another proof on the other core at times; 221 s at load 0.3–1); verify 83 s wall, 85 s of CPU
       (load 2–3, the same verifier); the full `magrod reproduce` re-checks it too.
       Over an interval: (a) holds for every λ̄ in [27/200 − 2·10⁻¹¹, 27/200 + 2·10⁻¹¹] (the same bound on
       h_top): the same sets move with λ̄, N_j(λ̄) = c_j + v_j (λ̄ − 27/200) + A_j [−1, 1]², v_j the chain's
       float motion (N0 and Nk move along Fix(R)), and every covering condition, the symmetry and the swept
       disjointness are checked for all λ̄ at once, λ̄ a fifth state of the validated flights
       (horseshoe_fig4a_interval.json, `magrod prove --widen horseshoe_fig4a.json --lam-rad 1/50000000000`:
       441 s at load ~3, 188 s for half the width at load ~2; verify 168 s wall at load ~3). Held fixed, the sets
       hold only for |λ̄ − 27/200| ≲ 10⁻¹⁶; moving, the limit is N12 ⇒ N13 ((a′) margin 0.54 at 10⁻¹¹, 0.27 at
       2·10⁻¹¹, −5.2 at 10⁻¹⁰): the 5-D box's derivative enclosures grow with its λ̄ extent. Second order in λ̄,
       the same sets and motions hold for every λ̄ in 27/200 ± 43/2³² (≈ 1.0012·10⁻⁸, 500× wider;
       horseshoe_fig4a_interval_wide.json, `magrod prove --widen horseshoe_fig4a.json --lam-rad 43/4294967296
       --lam-order 2 --lam-nodes 8`): each piece's image is its centre curve, enclosed by thin flights at K + 1
       nodes and, between them, the interpolation error [P″] h²/8 ([P″] from a C¹ flight of the 10-state
       variational system along the curve and the section map's second derivative), plus the piece's extent,
       DP at 27/200 over the piece and [F_us] (λ̄ − 27/200) over the swept box (a C¹ flight of the 15-state
       variational system and the mixed second derivative), checked on each of K sub-intervals
       (kernel/horseshoe_lam2.py; K = 8, and 16 at N10 and N11, 64 at N12, where the prover doubled it);
       (a′) ≥ 0.180, (b) ≥ 2.94; prove 395 s on 2 cores; verified by CI in a step of its own, not by the full `magrod
       reproduce`, whose REPORT says so. Beyond ~10⁻⁸ the linear motion's own drift takes the margin (0.29 of
       N13's width there; new sets, or sets moving nonlinearly).
       Panel (c) (λ̄ = 7/40, no hyperbolic fixed point of P): h_top(P|Λ) ≥ log ρ > 0.0152, ρ the largest root of
       x¹⁶⁰ = x¹⁵⁴ + 1, from 81 h-sets (half-sizes 1.2·10⁻⁸ … 1.6·10⁻¹², all on the ψ = π branch): a cycle N0 ⇒ N1
       ⇒ … ⇒ N5 ⇒ N0 of sets at the six points of a symmetric period-6 orbit of P (θ = 1.98883 on Fix(R); float
       |μ_u(DP⁶)| = 5.685) and the chain N5 ⇒ N6 ⇒ … ⇒ N80 along the orbit's unstable manifold to Fix(R) (its 62nd
       return from the fundamental domain), N0 and N80 R-symmetric, N0 disjoint from the others; the cycle and
       the chain closed by reversibility are loops of lengths 6 and 160 through N0, so the visits to N0 code
       concatenations of the blocks 1 0⁵ and 1 0¹⁵⁹ (horseshoe_fig4c.json, `magrod prove --horseshoe
       1.988829300900816 --level 0.9 --m 1.7 --mu 0.4 --gamma 3 --delta 3 --lam 0.175 --design fig4c --branch
       pi --root smallest`; prove 450–452 s, verify 83 s with the two-process verifier, 165 s in one; (a′) ≥ 0.120,
       (b) ≥ 1.199).
       Panel (d) (λ̄ = 93/500, the panel the chaos indicator calls regular): h_top(P|Λ) ≥ log ρ > 0.0437, ρ the
       largest root of x⁷² = x⁷¹ + 1, from 37 h-sets along the homoclinic orbit of the weak saddle of statement 11
       (μ_u = 1.615; W^u meets Fix(R) at the 35th return; N30, N31 in 4 × 4 and 8 × 8 pieces, N32–N34 in 2 × 2,
       the orbit passing within 0.0103 of θ = π), a thin chaotic layer (horseshoe_fig4d.json, `magrod prove
       --horseshoe 3.057288 --level 9/10 --m 17/10 --mu 2/5 --gamma 3 --delta 3 --lam 93/500 --design fig4d`;
       prove 391 s on 2 cores (587 s on one), the centres by the Taylor-model integrator; verify 1131 checks, 282 s on 2 cores,
       by CI in a step of its own, not by the full `magrod reproduce`, whose REPORT says so; (a′) ≥ 0.0496,
       (b) ≥ 1.15).""",
       [Step("the covering relations, the symmetry of N0 and Nk, the disjointness, the cover by pieces, the "
             "entropy bound", "computer-verified", "magrod prove --horseshoe; magrod prove --verify (kind "
             "section_horseshoe)"),
        Step("the chart field is Hamilton's, 2π-periodic in ψ, and R is a reversor", "proved",
             "f = J∇H̄, f(Rx) = −R f(x) and the 2π-periodicity in ψ (the field a rational function of sin ψ, "
             "cos ψ) checked by the verifier at run time on the certificate's field, as exact identities "
             "(magrod/proof/identities.py); derived as report keys validated_fields, reversor_reduced"),
        Step("a closed chain of coverings and back-coverings has an orbit for every sequence of loops "
             "(Zgliczyński & Gidea 2004, the covering-chain theorem); N ⇒ M gives R(M)^T ⇐ R(N)^T; the coding of "
             "the visits to N0 is a semiconjugacy onto the block shift", "proved",
             "cited theorem, hypotheses checked by the certificate; the lemma and the argument in "
             "docs/nonintegrability.md")],
       phrases=(r"horseshoe of (the section map )?P", r"covering relations?")),
    _s("13", "a horseshoe of the section map on Fig 5's own level h = 4/5 (sec. 9's regime)",
       """At (m, μ, δ, λ̄) = (17/10, 4, 1/4, 2) (Fig 5's caption: μ = 2λ̄, λ̄ = O(1), γ ≪ 1), on Fig 5's own
       level h = 4/5: (i) at each of the four panels' γ = 3/20, 41/200, 26/125, 6/25 the section map P of
       {sin ψ = 0, d sin ψ/dt > 0} has a symmetric fixed point x0 on Fix(R) on the ψ = π branch of the section
       (ψ′ < 0 there), θ* = 3.0119924258452433 (a), 3.0229203731343103 (b), 3.0235875345755768 (c),
       3.0310416089851843 (d) (each ± 1.1·10⁻¹⁸), return time T ∈ [5.2655355, 5.2655356] (a) … [5.2866768,
       5.2866769] (d), and DP(x0) is a flip saddle: tr DP(x0) ∈ [−5.53060, −5.53043] (a), [−6.83098, −6.83073]
       (b), [−6.90221, −6.90195] (c), [−7.65867, −7.65833] (d) (certificates
       magrod/proof/certificates/fixed_point_fig5{a,b,c,d}.json, `magrod prove --fixed-point 3.012 --level 0.8
       --m 1.7 --mu 4 --gamma 0.15 --delta 0.25 --lam 2 --branch pi --root 0`); at (a) also for every λ̄ in [19999/10000,
       20001/10000] = 2 ± 10⁻⁴ (μ = 4 fixed; fixed_point_fig5a_interval.json, the θ-box following the fixed point,
       θc + v (λ̄ − 2) ± 2.5·10⁻⁵, `--lam-rad 1/10000`: tr DP(x0) ∈ [−7.0454, −4.0155]; 1.5·10⁻⁴ fails in the box's
       flight; a box the same for every λ̄ closed at 10⁻⁵); (ii) at each of the four γ P has positive
       topological entropy: a compact forward-invariant set Λ with h_top(P|Λ) ≥ log ρ, log ρ > 0.0839 (a),
       > 0.0882 (b), > 0.0985 (c), > 0.0985 (d), ρ the largest root of x^L = x^(L−1) + 1, L = 30, 28, 24, 24 —
       h-sets N0 … Nk, k = 15, 14, 12, 12 (half-sizes 6.3·10⁻¹² … 4.9·10⁻⁹), N0 at the saddle of (i) and N1 … Nk
       along its homoclinic orbit (W^u meets Fix(R) at the 12th, 11th, 9th, 9th return, W^u and W^s crossing
       there at 22.5°, 40.6°, 25.9°, 28.3°, numerically), N0 ⇒ N0 and N0 ⇒ N1 ⇒ … ⇒ Nk (Zgliczyński & Gidea
       2004), N0 and Nk R-symmetric, reversibility closing the chain into a loop of length L (certificates
       magrod/proof/certificates/horseshoe_fig5{a,b,c,d}.json, kind section_horseshoe; prove 460, 267, 297,
       401 s on 2 cores at load 2–6, verify 95, 76, 52, 70 s (load ~2, the
       parallel verifier; 357, –, 139, 168 s with the serial one before it); the saddles' and the horseshoes' certificates are re-checked by the full `magrod reproduce`, not by `--quick`). Every
       certificate is re-checked by the complete verifier. At (a) the horseshoe also holds for every λ̄ in
       [99999999999/50000000000, 100000000001/50000000000] = 2 ± 2·10⁻¹¹ (μ = 4 fixed), its sets moving with λ̄
       as in statement 12 (horseshoe_fig5a_interval.json, `magrod prove --widen horseshoe_fig5a.json --lam-rad
       1/50000000000`: prove 306 s, verify 197 s wall, both at load ~3; (a′) ≥ 0.391, (b) ≥ 2.77; at 10⁻¹⁰
       N13 ⇒ N14 fails (a′)). Otherwise only these four points of the parameter space are certified; a
       hyperbolic set persists, so each statement holds on an open parameter neighbourhood, of unquantified size
       beyond the intervals stated. Fig 5's panels' orbits make the rod's axial stretch
       negative on 2.4–6.1 % of their arclength (errata; not checked along the horseshoe's orbits): a theorem
       about the paper's equations, not about a physical rod.""",
       [Step("the saddle: level, two-phase flight, Fix(R) Newton, |tr DP| > 2 (statement 11's prover on the ψ = π "
             "branch)", "computer-verified", "magrod prove --fixed-point --branch pi; magrod prove --verify"),
        Step("the covering relations, the symmetry of N0 and Nk, the disjointness, the cover by pieces, the "
             "entropy bound", "computer-verified", "magrod prove --horseshoe --branch pi; magrod prove --verify "
             "(kind section_horseshoe)"),
        Step("the chart field is Hamilton's, 2π-periodic in ψ, and R is a reversor", "proved",
             "f = J∇H̄, f(Rx) = −R f(x) and the 2π-periodicity in ψ (the field a rational function of sin ψ, "
             "cos ψ) checked by the verifier at run time on the certificate's field, as exact identities "
             "(magrod/proof/identities.py); derived as report keys validated_fields, reversor_reduced"),
        Step("the covering-chain theorem, the reversed-chain lemma, the block-shift entropy (statement 12's "
             "argument, unchanged: it never uses the branch of N0)", "proved",
             "cited theorem, hypotheses checked by the certificate; docs/nonintegrability.md")],
       phrases=(r"Fig 5's own level", r"h = 4/5", r"sec\. 9's (regime|conjecture)")),
)

BY_NUMBER = {s.number: s for s in STATEMENTS}


def status(number: str, _seen=()) -> str:
    """The status of statement `number`: the weakest status along its chain (references followed)."""
    if number in _seen:
        raise ValueError(f"statement {number}: circular chain {_seen + (number,)}")
    st = BY_NUMBER[number]
    worst = "proved"
    for step in st.chain:
        s = status(step.ref, _seen + (number,)) if step.ref is not None else step.status
        if s not in RANK:
            raise ValueError(f"statement {number}: unknown status {s!r}")
        if RANK[s] < RANK[worst]:
            worst = s
    return worst


# --------------------------------------------------------------------------------------------------------------
# Markdown: the statements' data is written in Unicode (H̄, λ̄, W^u), which a terminal shows as it stands; the blocks
# rendered into README.md and docs/ (myst's dollar math, MathJax) carry it as mathematics ($\bar H$, $W^u$).
# --------------------------------------------------------------------------------------------------------------
GREEK = {"α": r"\alpha", "β": r"\beta", "γ": r"\gamma", "δ": r"\delta", "ε": r"\varepsilon", "θ": r"\theta",
         "κ": r"\kappa", "λ": r"\lambda", "μ": r"\mu", "ν": r"\nu", "ξ": r"\xi", "π": r"\pi", "ρ": r"\rho",
         "σ": r"\sigma", "τ": r"\tau", "φ": r"\varphi", "ψ": r"\psi", "ω": r"\omega", "Δ": r"\Delta",
         "Λ": r"\Lambda", "Σ": r"\Sigma"}
OPS = {"≠": r"\neq", "∈": r"\in", "≤": r"\le", "≥": r"\ge", "≪": r"\ll", "≲": r"\lesssim", "≈": r"\approx",
       "±": r"\pm", "×": r"\times", "·": r"\cdot", "−": "-", "→": r"\to", "⇒": r"\Rightarrow", "⇐": r"\Leftarrow",
       "∘": r"\circ", "∋": r"\ni", "√": r"\sqrt", "′": "'", "…": r"\dots", "∗": "*"}
_SUP = dict(zip("⁰¹²³⁴⁵⁶⁷⁸⁹⁻", "0123456789-"))
_SUPS = "[" + "".join(_SUP) + "]+"
# formulas a symbol-by-symbol reading gets wrong (functions, subscripts written as ASCII, groups of exponents)
FORMULAS = {
    "K2 ∋ J²/(2 sin²θ)": r"K_2 \ni J^2/(2\sin^2\theta)",
    "ψ_u = λ̄S/tan(θt/2) + O(λ̄²)": r"\psi_u = \bar\lambda S/\tan(\theta_t/2) + O(\bar\lambda^2)",
    "s1/ε³ → b√(a − 2b) S/(V′(θt)(1 + cos θt))": r"s_1/\varepsilon^3 \to b\sqrt{a - 2b}\, S/(V'(\theta_t)(1 + \cos\theta_t))",
    "s1 is b√(a − 2b) S/(V′(1 + cos)) ε³ + O(ε⁴)": r"$s_1$ is $b\sqrt{a - 2b}\, S/(V'(1 + \cos))\, \varepsilon^3 + O(\varepsilon^4)$",
    "D′(0) = 2 s1 + O(ε⁴) ≠ 0": r"D'(0) = 2 s_1 + O(\varepsilon^4) \neq 0",
    "D′(π) ≠ 0": r"D'(\pi) \neq 0",
    "dθ_u/dψ": r"d\theta_u/d\psi", "h_top(P|Λ)": r"h_{\mathrm{top}}(P|_\Lambda)", "h_top": r"h_{\mathrm{top}}",
    "x^L = x^(L−1) + 1": r"x^L = x^{L-1} + 1", "W^u": "W^u", "W^s": "W^s", "P^n": "P^n",
    "R(M)^T ⇐ R(N)^T": r"R(M)^T \Leftarrow R(N)^T", "N ⇒ M": r"N \Rightarrow M",
    "|μ_u(DP⁶)|": r"|\mu_u(DP^6)|", "N_j(λ̄) = c_j + v_j (λ̄ − 27/200) + A_j [−1, 1]²":
        r"N_j(\bar\lambda) = c_j + v_j (\bar\lambda - 27/200) + A_j [-1, 1]^2", "v_j": "v_j",
    "H̄(q*)": r"\bar H(q^*)", "{H = H(q*), m3 = m3*}": r"\{H = H(q^*),\ m_3 = m_3^*\}", "F∘X": r"F\circ X", "{F, m3}": r"\{F, m_3\}", "ρ sin ψ_u = λ̄²S": r"\rho\sin\psi_u = \bar\lambda^2 S",
    "ν ≥ λ̄⁴S²": r"\nu \ge \bar\lambda^4 S^2", "λ̄²S": r"\bar\lambda^2 S", "λ̄S": r"\bar\lambda S",
    "(θ, p̄θ)": r"(\theta, \bar p_\theta)", "m_c": "m_c", "c_J = c_H, c_K": "c_J = c_H, c_K",
    "DQ2 = R DQ⁻¹ R": r"DQ_2 = R\, DQ^{-1} R", "Σ+": r"\Sigma^+", "C¹": "C^1", "S¹": "S^1", "n·m": r"n\cdot m",
    "μ_u": r"\mu_u", "ψ_u": r"\psi_u", "d sin ψ/dt > 0": r"d\sin\psi/dt > 0", "sin ψ = 0": r"\sin\psi = 0",
    "S ≠ 0": r"S \neq 0", "|λ̄ − 27/200|": r"|\bar\lambda - 27/200|",
    "{sin ψ = 0, d sin ψ/dt > 0}": r"\{\sin\psi = 0,\ d\sin\psi/dt > 0\}", "T ∈": r"T \in", "tr DP(x0)": r"\operatorname{tr} DP(x_0)", "DP(x0)": r"DP(x_0)", "DP²": "DP^2", "x0": "x_0", "log ρ": r"\log\rho",
}
_GREEK = "".join(GREEK)
_ATOM = re.compile(r"(?:\d+(?:\.\d+)?·)?10" + _SUPS                         # powers of ten: 2·10⁻¹¹
                   + r"|\d*(?:[A-Za-z]̄|[" + _GREEK + r"]̄?)(?:_\w|\d(?![\d.])|t\b|\*|′)?(?:" + _SUPS + ")?"  # 2λ̄, θ0
                   + r"|\b(?:N(?:\d+|k|j)|[mCedBsKnI]\d)\b"                 # h-sets N0 … Nk, indexed names m3, C1
                   + r"|\(m(?:, (?:[" + _GREEK + r"]̄?|[a-z]\d?))+\)"              # tuples (m, μ, γ, δ), (m, n, e3)
                   + r"|\bO\([" + _GREEK + "̄" + "".join(_SUP) + r"\d]+\)"           # orders O(ε), O(λ̄²), O(1)
                   + r"|\b[mT](?= ∈)|\ba [=>≥] 2b\b"                                # m ∈ [1, 2.2]; a > 2b
                   + r"|\b[A-Za-z]" + _SUPS + r"|\b\d" + _SUPS                # x²⁸, the block 0⁵
                   + r"|[≠∈≤≥≪≲≈⇒⇐→…]")                                      # relations (math only when joined)
_RELATIONS = "≠∈≤≥≪≲≈⇒⇐→…"
# what may stand between two pieces of mathematics and join them into one: operators and digits, or one ", "
_JOIN = re.compile(r"[ \d=<>+/≠∈≤≥≪≲≈±×·−→⇒⇐∘…]*|, ")
# a relation or an operator with a number, an interval or a tuple after a piece of mathematics belongs to it
# (θ = 0, λ̄ = 27/200, T ∈ [5.2, 5.3], = (17/10, 2/5, 3, 3)); after a relation, the number alone does (γ ≪ 1)
_NUMBER = r"(?:[−-]?\d+(?:[./]\d+)*(?:e[−-]\d+)?(?![\d./]|\w)|\[[−-]?[\d./]+, [−-]?[\d./]+\]|\([\d/.]+(?:, [\d/.]+)+\))"
_OPERAND = re.compile(r"\s*[=≠<>≤≥≪∈+−]\s*" + _NUMBER)
_BARE = re.compile(r"\s*" + _NUMBER)
# a list "μ, γ, δ" is one piece of mathematics, "λ̄ = 2, γ ≪ 1" two
_RELATION = re.compile(r"\\neq|\\in\b|\\le|\\ge|\\ll|\\approx|\\to|\\Rightarrow|\\lesssim|[=<>]")
_ENDS_IN_RELATION = re.compile(r"(\\neq|\\in|\\le|\\ge|\\ll|\\approx|=|<|>)$")


def _latex(s: str) -> str:
    """A Unicode formula as LaTeX: Greek letters, bars, indices, superscripts, operators."""
    out = re.sub(r"(?<=\d)e([−-]\d+)\b", r"\\cdot 10^{\1}", s)  # 1.4e−5
    out = re.sub(r"(\w)̄", lambda m: rf"\bar {m.group(1)}", out)
    out = re.sub(_SUPS, lambda m: "^{" + "".join(_SUP[c] for c in m.group(0)) + "}", out)
    out = re.sub(r"(?<=[" + _GREEK + r"])(\d|t\b)", r"_\1", out)  # θ0, θt
    out = re.sub(r"\b([mCedBsKnI])(\d)\b", r"\1_\2", out)  # m3, C1
    out = re.sub(r"\bN(\d+|k|j)\b", r"N_{\1}", out)  # the h-sets
    out = re.sub(r"(?<=[" + _GREEK + r"])\*", "^*", out)
    out = "".join(GREEK.get(c, OPS.get(c, c)) + (" " if c in GREEK or OPS.get(c, "").startswith("\\") else "")
                  for c in out)
    out = re.sub(r"\\bar (\\\w+) ", r"\\bar\1 ", out)
    return re.sub(r" +(?=[\^_',)])", "", out).strip()


def markdown(text: str) -> str:
    """`text` (the statements' Unicode) with its mathematics as myst dollar math: the formulas of FORMULAS, Greek
    letters, barred and indexed symbols, powers of ten, and the relations and numbers that join them.  Code spans
    are left alone."""
    pieces = []  # [is_math, text]
    pat = re.compile("|".join(re.escape(f) for f in sorted(FORMULAS, key=len, reverse=True)) + "|" + _ATOM.pattern)
    for k, part in enumerate(re.split(r"(`[^`]*`)", text)):
        if k % 2:
            pieces.append([False, part])
            continue
        pos = 0
        for m in pat.finditer(part):
            pieces.append([False, part[pos:m.start()]])
            f = FORMULAS.get(m.group(0))
            pieces.append([False, f] if f is not None and f.startswith("$") else
                          [True, f if f is not None else _latex(m.group(0))])
            pos = m.end()
        pieces.append([False, part[pos:]])
    merged = []
    for is_math, s in pieces:
        if (is_math and len(merged) >= 2 and merged[-2][0] and not merged[-1][0] and _JOIN.fullmatch(merged[-1][1])
                and (merged[-1][1] != ", " or not (_RELATION.search(merged[-2][1]) or _RELATION.search(s)))):
            sep = _latex(merged.pop()[1])
            merged[-1][1] += (", " if sep == "," else f" {sep} " if sep else " ") + s
        elif is_math and merged and merged[-1][0]:
            merged[-1][1] += s
        else:
            merged.append([is_math, s])
    out = []
    for i, (is_math, s) in enumerate(merged):
        if is_math and i + 1 < len(merged) and not merged[i + 1][0]:
            m = _OPERAND.match(merged[i + 1][1]) or (_ENDS_IN_RELATION.search(s) and _BARE.match(merged[i + 1][1]))
            if m:
                s += " " + _latex(m.group(0))
                merged[i + 1][1] = merged[i + 1][1][m.end():]
        if is_math and s.strip() in {_latex(c) for c in _RELATIONS}:
            s, is_math = next(c for c in _RELATIONS if _latex(c) == s.strip()), False  # a lone relation: text
        out.append("$" + re.sub(" +", " ", s.strip()) + "$" if is_math else s)
    return "".join(out)


def plain(text: str) -> str:
    r"""The inverse of `markdown` for reading prose: dollar math back to Unicode ($\bar\lambda$ -> λ̄, $m_3$ -> m3),
    so that a statement's phrases ("ε small", "in involution with m3") are found in rendered blocks too."""
    inv = {v: k for k, v in {**OPS, **GREEK}.items() if v.startswith("\\")}
    inv.update({f"\\{f}": f"{f} " for f in ("sin", "cos", "tan", "log")})

    def math(m):
        s = re.sub(r"\\bar\s*(\\[A-Za-z]+|\w)", lambda b: inv.get(b.group(1), b.group(1)) + "̄", m.group(1))
        s = re.sub(r"\\[A-Za-z]+", lambda c: inv.get(c.group(0), ""), s)
        return re.sub(r"[{}^_]|\\(?=\W)", "", s).replace("  ", " ")

    return re.sub(r"\$([^$]+)\$", math, text)


def render_verdict() -> str:
    """The numbered list of docs/nonintegrability.md, section "Verdict" (labels computed from the chains)."""
    out = []
    for st in STATEMENTS:
        chain = "; ".join(f"{s.what} — " + (f"statement {s.ref} ({status(s.ref)})" if s.ref else
                                           f"{s.status}" + (f", {s.how}" if s.how else "")) for s in st.chain)
        out.append(_wrap(markdown(f"{st.number}. **{status(st.number)}** ({st.title}). {st.text}")))
        out.append(_wrap(markdown(f"   *Chain:* {chain}.")))
    return "\n".join(out)


def _wrap(text: str) -> str:
    """Markdown lines of at most 116 characters, never broken inside a piece of mathematics."""
    import textwrap

    text = re.sub(r"\$[^$]+\$", lambda m: m.group(0).replace(" ", "\x00"), text)
    out = textwrap.fill(text, 116, subsequent_indent="   ", break_long_words=False, break_on_hyphens=False)
    return out.replace("\x00", " ")


def _by_status():
    groups = {}
    for st in STATEMENTS:
        groups.setdefault(status(st.number), []).append(st.number)
    return groups


def render_summary() -> str:
    """The Summary paragraph of docs/nonintegrability.md."""
    g = _by_status()
    lists = "; ".join(f"{k}: {', '.join(g[k])}" for k in RANK if k in g)
    return _wrap(markdown(f"**Summary** ({lists}). At the parameter point of 5, (m, μ, γ, δ, λ̄) = (17/10, 1/25, 1, 1, "
            f"1/100), and at Fig 4's rod (5a: (17/10, 2/5, 3, 3) at the four panels' λ̄, non-perturbative), the "
            f"saddle's energy level of the reduced chart system carries horseshoes and no real-analytic "
            f"integral independent of H̄ (**{status('5')}**), and the 9-D rod has there no real-analytic integral "
            f"in involution with m3 that is independent of H, m3 and the Casimirs on the component of that level "
            f"which contains the homoclinic orbits "
            f"(**{status('7')}**, statement 7); the first also for every λ̄ in 1/100 ± 10⁻⁹ (a certificate with λ̄ a "
            f"ball, statement 5), and both hold on an open neighbourhood of that point, of unquantified "
            f"size (cited persistence). Nonintegrability of the 9-D rod against every integral (not only those in "
            f"involution with m3), and near the perturbative regime, is **{status('7b')}** (7b; 4 rests on the "
            f"formal expansion 3). On Fig 4's own level h = 9/10 the section map has a hyperbolic fixed point (a "
            f"saddle) at panels (a), (b), (d) (**{status('11')}**, 11; at (a) for every λ̄ in 0.135 ± 2.1·10⁻⁴, by 21 "
            f"boxes of 2·10⁻⁵), and at every panel a horseshoe: "
            f"positive topological entropy of the section map (**{status('12')}**, 12, covering relations along the "
            f"saddle's homoclinic orbit, at (c) around a period-6 orbit of P; at (a) for every λ̄ in 0.135 ± "
            f"2·10⁻¹¹; at (d), which the chaos indicator calls regular, a thin chaotic layer); the indicator's "
            f"classification of the panels is **{status('10')}** evidence (10). In sec. 9's regime (λ̄ = 2, γ ≪ 1), on Fig 5's own level h = 4/5 (μ = 2λ̄ = 4, δ = 1/4): a "
            f"saddle of the section map at the four panels' γ and a horseshoe at each (**{status('13')}**, "
            f"13; at γ = 3/20 the saddle for every λ̄ in 2 ± 10⁻⁴, the horseshoe in 2 ± 2·10⁻¹¹). The paper's own "
            f"argument (sec. 7) does not prove it (1)."))


def render_readme() -> str:
    """The README bullet on nonintegrability."""
    return _wrap(markdown(f"- Nonintegrability: at one parameter point, (m, μ, γ, δ, λ̄) = (17/10, 1/25, 1, 1, 1/100), and "
            f"for every λ̄ in 1/100 ± 10⁻⁹ there, two transverse homoclinic orbits of the tilted saddle-focus are **{status('5')}** (`magrod prove`, a "
            f"certificate re-checked by a separate, complete verifier), hence horseshoes on that level and no "
            f"real-analytic integral of the reduced system independent of H̄ there, the same at Fig 4's rod (the four panels' λ̄) on the saddle-focus's "
            f"own level (**{status('5a')}**; that level is not the one Fig 4 shows), and for the 9-D rod none in "
            f"involution with m3 "
            f"(**{status('7')}**); every other nonintegrability claim (every integral, not only those in involution with "
            f"m3; the perturbative regime) is **{status('7b')}**; on Fig 4's own level h = 9/10 a saddle of the section "
            f"map at three of the four panels is **{status('11')}** (at (a) for every λ̄ in 0.135 ± 2.1·10⁻⁴), a "
            f"horseshoe of the section map (positive "
            f"topological entropy) at all four panels is **{status('12')}** (statement 12; at (a) for every λ̄ in "
            f"0.135 ± 2·10⁻¹¹; at (d), which the chaos indicator calls regular, too), on Fig 5's own level h = 4/5 "
            f"(sec. 9's regime: λ̄ = 2, γ ≪ 1) a saddle of the section map at the four panels and a horseshoe at "
            f"each are **{status('13')}** (statement 13), and the chaos of Figs 4–5 "
            f"elsewhere is **{status('10')}** evidence "
            f"(`docs/nonintegrability.md`, \"Verdict\").")).replace("\n   ", "\n  ")


BLOCKS = {  # file (relative to the repository) -> {block name: renderer}
    "docs/nonintegrability.md": {"verdict": render_verdict, "summary": render_summary},
    "README.md": {"nonintegrability": render_readme},
}


def _markers(name):
    return (f"<!-- statements:{name} (generated by magrod.proof.statements; edit the data there) -->",
            f"<!-- /statements:{name} -->")


def blocks(text: str) -> dict:
    """The generated blocks found in a file's text: name -> content (without the markers)."""
    out = {}
    for m in re.finditer(r"<!-- statements:(\w+) \(generated[^\n]*-->\n(.*?)\n<!-- /statements:\1 -->", text, re.S):
        out[m.group(1)] = m.group(2)
    return out


def rewrite(text: str, renderers: dict) -> str:
    for name, fn in renderers.items():
        a, b = _markers(name)
        pat = re.compile(re.escape(a) + r"\n.*?\n" + re.escape(b), re.S)
        if not pat.search(text):
            raise ValueError(f"block {name!r} not found (markers {a!r} ... {b!r})")
        body = f"{a}\n{fn()}\n{b}"
        text = pat.sub(lambda _m, body=body: body, text)
    return text


# --------------------------------------------------------------------------------------------------------------
# the label check: a strong label must not be attached to a weak statement
# --------------------------------------------------------------------------------------------------------------
_STRONG = re.compile(r"(?<![\w-])(proved|computer-verified)(?![\w-])", re.I)
_NEG = re.compile(r"\b(not|no|never|nor|without)\b[^.;]{0,40}$", re.I)


def clauses(text: str) -> list:
    """Sentences and semicolon/dash-separated clauses of prose (markdown paragraphs joined, code stripped)."""
    text = plain(re.sub(r"`[^`]*`", " ", text))
    text = re.sub(r"\s+", " ", text)
    return [c.strip() for c in re.split(r"(?<=[.;!?])\s+|\s+—\s+|\s+\|\s+|,\s+(?:and|but)\s+", text) if c.strip()]


def mentions(clause: str) -> set:
    """Statement numbers a clause refers to: "statement N", "statements N and M", or a statement's phrases."""
    out = set()
    for m in re.finditer(r"\bstatements? ((?:\d+b?(?:, | and | or |–))*\d+b?)", clause, re.I):
        out |= set(re.findall(r"\d+b?", m.group(1)))
    for st in STATEMENTS:
        if any(re.search(p, clause, re.I) for p in st.phrases):
            out.add(st.number)
    return {n for n in out if n in BY_NUMBER}


def overclaims(text: str) -> list:
    """Clauses that attach "proved"/"computer-verified" to a statement whose status is weaker, unless the clause
    also names that weaker status (e.g. "computer-verified coefficient ... conditional on 3") or negates the
    label ("not proved")."""
    bad = []
    for c in clauses(text):
        strong = [m for m in _STRONG.finditer(c) if not _NEG.search(c[:m.start()])]
        if not strong:
            continue
        for n in sorted(mentions(c)):
            s = status(n)
            if s in WEAK and s not in c.lower() and not (s == "conditional" and "conditional" in c.lower()):
                bad.append((n, s, c[:200]))
    return bad


def _main(argv=None):
    import argparse

    ap = argparse.ArgumentParser(prog="python -m magrod.proof.statements")
    ap.add_argument("--write", action="store_true", help="rewrite the generated blocks in README.md and docs/")
    ap.add_argument("--root", default=str(Path(__file__).resolve().parents[2]))
    a = ap.parse_args(argv)
    for rel, renderers in BLOCKS.items():
        p = Path(a.root) / rel
        new = rewrite(p.read_text(), renderers)
        if a.write:
            p.write_text(new)
        print(f"{rel}: {'written' if a.write else 'ok'} ({', '.join(renderers)})")


if __name__ == "__main__":
    _main()
