"""Independent checker of a proof certificate (`magrod prove --verify CERT`).

It re-runs every rigorous step from the certificate's stored inputs and accepts only if (a) every recomputed
enclosure lies inside the certificate's ball for it and (b) every claimed inequality holds for the certificate's
balls.  Separate code from the prover: it imports neither magrod.proof.provers.transverse_homoclinic nor the prover's saddle / manifold
modules; the Krawczyk tests, the cone conditions, the lift of the boundary arc, the phase derivatives and the
interval Newton step are implemented again here.

The checker is this module (the entry: the certificate's kind, then its module) and the kernel package
magrod/proof/kernel/: schema.py (the format, the kinds, the result, reading a certificate, the checks every kind
shares), one module per kind -- homoclinic.py (statement 5), fixed_point.py (statement 11), horseshoe.py
(statement 12; with horseshoe_sets.py, the checks of one set, and horseshoe_lam2.py, a set's checks on a lambdabar
interval to second order) -- and pool.py (the horseshoe's sets in child processes, their checks replayed here in
the serial order).  Shared with the prover are only (the trust base; a test fences it, docs/nonintegrability.md, "The
verifier's trust base"):
  - the generated field (generated/validated.py, whose SHA-256 must match the certificate), through
    magrod.proof.fields, which also builds from it the chart field with lambdabar as a fifth state variable
    (lambdabar' = 0; fields.lam_state_field) and the body field with lambdabar as a tenth
    (fields.body_lam_state_field; with the events' and the lift's derivatives in lambdabar) for the certificates on
    a lambdabar interval;
  - the ball helpers (magrod.proof.ball);
  - the validated integrator (magrod.proof.taylor), which the verifier drives with the certificate's exact step
    sizes;
  - the validated first return to the section sin psi = 0 (magrod.proof.section_return), for the section
    certificates (fixed point and horseshoe);
  - the variational systems of the lambdabar-state field and the section map's second derivatives at a crossing
    (magrod.proof.variational), for a horseshoe certificate on a lambdabar interval to second order;
  - the field's structure (magrod.proof.identities): reversibility under R, the Hamiltonian form (det DP = 1) and
    chart_jacobian = Df, checked at run time as exact rational-function identities on the field's source before its
    digest, in every kind (kernel.schema.check_structure); the horseshoe's 2 pi-periodicity in psi
    (identities.psi_periodic); and the homoclinic kind's lift to the body frame (identities.lift_check: the lift
    intertwines the chart and body flows up to the rotation about d3, the body field commutes with it, the events
    are invariant chart forms, the body and lift Jacobians are derivatives);
  - the theorem's wording (magrod.proof.theorem), and core.errors for the error type.

Completeness: a certificate is accepted only if what it contains establishes the theorem the verifier prints.  The
targets must be recognised ("0" or "pi", nothing else), distinct, exactly the settings' targets, one crossing each;
the settings must be those the stored data were made with (saddle radius, circle radius, crossing step); and the
certificate's "theorem" text must be the one generated here from the verified parameters and targets (a text that
claims more, or other, than the checks is rejected).  The printed theorem is that generated text, never the
certificate's.

Provenance: a certificate may carry "provenance", an object of strings naming the command or script and the settings
that produced it (`magrod prove` writes it; the shipped certificates' were reconstructed when it was introduced).  No
check reads it and the theorem does not depend on it; only its form is checked (not an object of strings: exit 2).

Failure modes: `CertificateError` (unreadable, wrong format, missing or malformed fields: not a certificate, exit 2)
and a result with ok = False and a one-line reason naming the check that failed and what it requires (a
certificate that fails a check, a working precision too low for its checks included: exit 1).
"""
from __future__ import annotations

import time

from . import fields
from .kernel import fixed_point, homoclinic, horseshoe
from .kernel.schema import (FORMAT, HOMOCLINIC, KINDS, SECTION_FIXED_POINT, SECTION_HORSESHOE, CertificateError,
                            VerifyResult, check_form, load)

__all__ = ["FORMAT", "KINDS", "HOMOCLINIC", "SECTION_FIXED_POINT", "SECTION_HORSESHOE", "CertificateError",
           "VerifyResult", "load", "verify"]


def verify(cert: dict, *, module=fields.gen, workers: int | None = None, mapper=None) -> VerifyResult:
    """Re-check a proof certificate with code separate from the prover.

    Parameters
    ----------
    cert : dict
        The certificate (`load(path)` or the prover's dict).
    module : module, optional
        The generated field module; its SHA-256 must equal the certificate's and the installed one's.
    workers : int, optional
        Kind "section_horseshoe" only: the sets are re-flown in this many spawned processes (default: the CPUs this
        process may use; 1: in this process).  The checks, their order and the result are the same for every
        value (each set's checks are replayed in the serial order; Arb is deterministic).
    mapper : callable, optional
        Kind "section_horseshoe": mapper(fn, jobs) runs fn(*job) for each job wherever it likes (a Dask cluster:
        magrod.proof.schedule.dask_mapper) and yields the results in the order of jobs; the sets are re-flown by it
        instead of `workers` processes.  Scheduling only: the records are replayed here in the serial order.

    Returns
    -------
    VerifyResult
        ok, reason (one line: "certificate verified ..." or "certificate rejected: <check>: <why>"), checks.

    Raises
    ------
    CertificateError
        (a ParameterError naming "verify") if a field is missing or malformed.

    Examples
    --------
    >>> from magrod.proof import verify
    >>> res = verify.verify(verify.load("out/certificate.json"))  # doctest: +SKIP
    >>> res.ok  # doctest: +SKIP
    True

    Notes
    -----
    The kind's module (magrod/proof/kernel/) recomputes every rigorous step: for the homoclinic kind the saddle's
    Krawczyk image, the eigenpairs, the cone conditions, both flights with the stored exact steps, the section
    crossings, the Newton step and dtheta_u/dpsi; every recomputed enclosure must lie in the certificate's ball and
    every claim must hold on the certificate's balls.  Every kind first checks the field's structure
    (kernel.schema.check_structure).  Cost: about the prover's rigorous part (~30-40 s at the target).
    """
    t0 = time.perf_counter()
    kind = check_form(cert)
    if kind == SECTION_FIXED_POINT:
        return fixed_point.verify(cert, module, t0)
    if kind == SECTION_HORSESHOE:
        return horseshoe.verify(cert, module, t0, workers, mapper)
    return homoclinic.verify(cert, module, t0)
