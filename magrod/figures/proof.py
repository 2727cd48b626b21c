"""The computer-assisted proof at the target: verify the shipped certificate
(magrod/proof/certificates/homoclinic_target.json, written by `magrod prove` at the target) with the complete
verifier, write proof_certificate.json (a copy), proof.json (the sidecar REPORT.md's claim row reads) and proof.png:
the float trace of W^u on Sigma (theta_u against psi, with its mirror image W^s) and the verified tangent slopes at
psi = 0 and psi = pi.  `magrod reproduce` verifies, it does not re-prove; `magrod prove` re-proves.
quick: the same verification (a few seconds), a coarser float trace."""
from __future__ import annotations

import time
from fractions import Fraction

import numpy as np

from ..core.io import atomic_write_json, ensure_writable_dir, versions
from .common import atomic_savefig, pyplot

TARGET = ("1.7", "0.04", "1", "1", "0.01")  # (m, mu, gamma, delta, lambdabar): a = 4, b = 1, eps = 0.1


SHIPPED = "homoclinic_target.json"
# statement 5 for every lambdabar in 1/100 +- 1e-9 (the circle about the moving saddle, lambdabar a state of the flights);
# verified by the full reproduction (~7 s), listed by --quick
TARGET_INTERVAL = "homoclinic_target_interval.json"
# Fig 4's rod at the panels' lambdabar where `magrod prove` succeeds: the saddle-focus's own level (statement 5a)
FIG4 = (("4a", "homoclinic_fig4a.json"), ("4b", "homoclinic_fig4b.json"), ("4c", "homoclinic_fig4c.json"),
        ("4d", "homoclinic_fig4d.json"))
# The figures' own levels: symmetric hyperbolic fixed points of the section map sin psi = 0, as (panel, file,
# statement): Fig 4 on h = 0.9 (statement 11; panel (c) has none from the float search,
# research/fig4_candidates.json) and Fig 5 on h = 0.8 (statement 13, the psi = pi branch)
FIG4_SECTION = (("4a", "fixed_point_fig4a.json", "11"), ("4b", "fixed_point_fig4b.json", "11"),
                ("4d", "fixed_point_fig4d.json", "11"),
                ("4a_interval", "fixed_point_fig4a_interval.json", "11"),  # every lambdabar in 27/200 +- 1e-6
                ("5a", "fixed_point_fig5a.json", "13"), ("5b", "fixed_point_fig5b.json", "13"),
                ("5c", "fixed_point_fig5c.json", "13"), ("5d", "fixed_point_fig5d.json", "13"),
                ("5a_interval", "fixed_point_fig5a_interval.json", "13"))  # every lambdabar in 2 +- 1e-5
# The horseshoes on those levels (statements 12, 13).  Their verifier flies with Newton's series and the sets in
# parallel processes (verify.py, kind section_horseshoe; 45-95 s of CPU each, 164 s for Fig 4(c)'s 81 sets); the full
# reproduction verifies every one (~8 min of CPU in all), --quick (the test suite's) none
FIG4_HORSESHOE = (("4a", "horseshoe_fig4a.json", "12"), ("4b", "horseshoe_fig4b.json", "12"),
                  # Fig 4(c): around the period-6 orbit of P (the cycle of 6 sets, section_horseshoe._prove_cycle)
                  ("4c", "horseshoe_fig4c.json", "12"),
                  # Fig 4(a)'s sets moving with lambdabar: every lambdabar in 27/200 +- 2e-11 (horseshoe_widen.widen)
                  ("4a_interval", "horseshoe_fig4a_interval.json", "12"),
                  ("5a", "horseshoe_fig5a.json", "13"), ("5b", "horseshoe_fig5b.json", "13"),
                  ("5c", "horseshoe_fig5c.json", "13"), ("5d", "horseshoe_fig5d.json", "13"),
                  ("5a_interval", "horseshoe_fig5a_interval.json", "13"))  # every lambdabar in 2 +- 2e-11
# Shipped certificates no reproduction verifies, each with the command that does (REPORT has a row saying so).
# Fig 4(d)'s horseshoe (the panel the chaos indicator calls regular: 37 sets, 1131 checks) is the one whose prove +
# verify exceeds 10 minutes on 2 cores (prove 391 s with --workers 2, 587 s on one core; verify 282 s, ~400 s of
# CPU), so it is verified in CI's own step (.ci/run), not inside the full reproduction, which it would lengthen by
# a third.
# (The 21 boxes of magrod/proof/certificates/fig4a_interval/ are one benchmark's tiling, verified by a slow test;
# reproduce verifies the single box fixed_point_fig4a_interval.json.)
# Fig 4(a)'s horseshoe on 27/200 +- 43/2^32 (second order in lambdabar, kernel/horseshoe_lam2.py: 9 to 65 node
# flights and two variational flights for each of the 14 pieces, ~6 min of CPU to verify) is verified by its own CI
# step too.
NOT_IN_REPRODUCE: tuple = (("4d", "horseshoe_fig4d.json", "12"),
                           ("4a_interval_wide", "horseshoe_fig4a_interval_wide.json", "12"))


def build(out_dir, *, quick: bool = False, progress=False) -> list[str]:
    """Verify the shipped certificates (every one; --quick: the target, Fig 4(a)'s homoclinic orbit and its section
    fixed point) and write their copies, proof.json and proof.png.

    The certificates are verified together by proof.schedule.verify_many: independent certificates in processes
    on every core, each remembered under OUT/.state/verified/ by the hashes of the certificate and of the
    verifier's trust base (a second run does not verify again; a changed certificate or verifier does).  The
    sidecar is assembled in this module's fixed order whatever ran the checks.  `progress`: True shows a bar
    per certificate; a callable is called progress(done, total, name, cached) after each."""
    out = ensure_writable_dir(out_dir)
    t0 = time.perf_counter()
    # --quick verifies one certificate of each kind but the horseshoe (the target, Fig 4(a)'s homoclinic orbit and
    # its section saddle); the full reproduction verifies every shipped certificate
    fig4, fig4_section = (FIG4[:1], FIG4_SECTION[:1]) if quick else (FIG4, FIG4_SECTION)
    fig4_horseshoe = () if quick else FIG4_HORSESHOE
    names = [SHIPPED] + ([] if quick else [TARGET_INTERVAL]) + [n for _, n in fig4] + \
        [n for _, n, _ in (*fig4_section, *fig4_horseshoe)]
    verified = _verify_all(names, out, progress)

    cert, v, _ = verified[SHIPPED]
    side = {"params": cert["params"], "ok": v.ok, "reason": v.reason, "n_checks": len(v.checks), "quick": quick,
            "certificate": f"magrod/proof/certificates/{SHIPPED}", "re_proved": False, "versions": versions()}
    paths = [str(atomic_write_json(out / "proof_certificate.json", cert))]
    if v.ok:
        side.update(verified=True, verify_reason=v.reason, verify_checks=len(v.checks),
                    verify_wall_time_s=round(v.wall_time_s, 1), theorem=v.theorem,
                    crossings=[{"target": c["target"], "dtheta_dpsi": c["dtheta_dpsi"], "phi_star": c["newton"]}
                               for c in cert["crossings"]],
                    eigenvalue_u=cert["saddle"]["lam_u"])
    # Fig 4's rod: the relative equilibrium's own level, not the figure's h = 0.9
    side["fig4"] = []
    side["not_verified_in_quick"] = ([TARGET_INTERVAL] if quick else []) + [n for _, n in FIG4[len(fig4):]] + \
        [n for _, n, _ in (*FIG4_SECTION[len(fig4_section):], *FIG4_HORSESHOE[len(fig4_horseshoe):])]
    if not quick:
        ti, v4, entry = verified[TARGET_INTERVAL]
        side["target_interval"] = {**entry, "lam_rad": ti["settings"]["lam_rad"], "slopes": v4.slopes}
        paths.append(str(atomic_write_json(out / "proof_certificate_interval.json", ti)))
    for key, name in fig4:
        other, v4, entry = verified[name]
        side["fig4"].append({"panel": key, **entry, "slopes": v4.slopes})
        paths.append(str(atomic_write_json(out / f"proof_certificate_fig{key}.json", other)))
    # the section certificates (statements 11-13): verified, one sidecar entry each, a copy beside the figure
    for group, prefix, entries in (("fig4_section", "fixed_point", fig4_section),
                                   ("fig4_horseshoe", "horseshoe", fig4_horseshoe)):
        side[group] = []
        for key, name, st in entries:
            other, v4, entry = verified[name]
            side[group].append({"panel": key, **entry, "level": other["level"], "statement": st,
                                "lam_rad": str(other.get("settings", {}).get("lam_rad", "0")),
                                **({"values": v4.values} if group == "fig4_section" else {})})
            paths.append(str(atomic_write_json(out / f"proof_certificate_{prefix}_fig{key}.json", other)))
    side["not_verified_in_reproduce"] = [{"panel": k, "certificate": f"magrod/proof/certificates/{n}", "statement": st}
                                         for k, n, st in NOT_IN_REPRODUCE]
    side["wall_time_s"] = round(time.perf_counter() - t0, 1)
    paths.append(str(atomic_write_json(out / "proof.json", side)))
    paths.append(str(_figure(out, side, quick)))
    return paths


def _shipped(name: str) -> dict:
    import json
    from importlib import resources

    return json.loads(resources.files("magrod.proof").joinpath("certificates", name).read_text())


def _entry(name: str, cert: dict, v) -> dict:
    """The sidecar entry every REPORT row reads (parameters, verdict, checks, theorem, file, time)."""
    return {"params": cert["params"], "ok": v.ok, "reason": v.reason, "n_checks": len(v.checks),
            "theorem": v.theorem, "certificate": f"magrod/proof/certificates/{name}",
            "verify_wall_time_s": round(v.wall_time_s, 1)}


def _verify_all(names, out, progress) -> dict:
    """name -> (certificate, VerifyResult, sidecar entry) for the shipped certificates `names`, verified by the
    complete verifier through proof.schedule (processes, the cache under OUT/.state/verified)."""
    from ..core.progress import bar
    from ..proof import verify_certificates

    certs = [(n, _shipped(n)) for n in names]
    with bar(len(certs), "verifying certificates", progress is True, unit="certificate") as update:
        def report(done, total, name, cached):
            update(1)
            if callable(progress) and progress is not True:
                progress(done, total, name, cached)

        results = verify_certificates(certs, cache_dir=out / ".state" / "verified", progress=report)
    return {n: (c, v, _entry(n, c, v)) for (n, c), v in zip(certs, results)}


def _verified(name: str) -> tuple:
    """(certificate, VerifyResult, sidecar entry) of the shipped certificate `name`, verified by the complete
    verifier in this process (no cache)."""
    from ..proof import verify_certificate

    cert = _shipped(name)
    v = verify_certificate(cert)
    return cert, v, _entry(name, cert, v)


def _figure(out, side, quick):
    plt = pyplot()
    from ..separatrix import tilted_curve

    fig, ax = plt.subplots(figsize=(6, 4))
    c = tilted_curve(1.7, 1.0, 1.0, 4.0, 1.0, 0.1, "double", n_phases=32 if quick else 96)
    psi = np.array(c.psi)
    o = np.argsort(psi)
    ax.plot(psi[o], np.array(c.theta)[o], ".", ms=3, label=r"$W^u\cap\Sigma$ (float64)")
    ax.plot(-psi[o], np.array(c.theta)[o], ".", ms=2, alpha=0.6, label=r"$W^s\cap\Sigma$ (mirror image)")
    ax.set_xlim(-np.pi, np.pi)
    for cr in side.get("crossings", []):
        x0 = 0.0 if cr["target"] == "0" else np.pi
        s = float(Fraction(cr["dtheta_dpsi"]["mid"]))
        for x in ((0.0,) if x0 == 0 else (-np.pi, np.pi)):
            ax.axvline(x, color="k", lw=0.4)
        ax.annotate(rf"$\psi={'0' if x0 == 0 else chr(92) + 'pi'}$: $d\theta_u/d\psi \in$ {s:+.3e} "
                    rf"$\pm$ {float(Fraction(cr['dtheta_dpsi']['rad'])):.1e} (computer-verified)",
                    xy=(0.02, 0.95 - 0.07 * (x0 > 0)), xycoords="axes fraction", fontsize=7)
    ax.set_xlabel(r"$\psi$")
    ax.set_ylabel(r"$\theta$ on $\Sigma = \{\bar p_\theta = 0\}$")
    ax.set_title(f"transverse symmetric homoclinic orbits (computer-assisted) at (m, mu, gamma, delta, lam) = "
                 f"{', '.join(TARGET)}", fontsize=7)
    ax.legend(fontsize=7, loc="lower right")
    return atomic_savefig(fig, out / "proof.png", dpi=130)
