"""`magrod prove --m 1.7 --gamma 1 --delta 1 --mu 0.04 --lam 0.01 --out DIR`: a computer-assisted proof that the
tilted saddle-focus of the reduced chart (mu > 2 lambdabar) has two transverse symmetric homoclinic orbits
(psi = 0 and psi = pi on Sigma = {pbar_theta = 0}), written as DIR/certificate.json
(magrod/proof/provers/transverse_homoclinic.py; docs/nonintegrability.md, "Theorem (computer-assisted)").  Parameters are read as exact rationals ("0.04" is
1/25).  `magrod prove --verify CERT` re-checks a certificate with the separate verifier (magrod/proof/verify.py)
and prints the theorem the verifier generated from what it checked.

Exit codes: 0 proved / verified; 1 a step could not be established (one line: which, and why) or a certificate
was rejected; 2 bad input (mu <= 2 lambdabar, m >= m_c, a non-finite value, an unreadable certificate).  Nothing
is written unless the proof holds.  A certificate whose content does not establish a theorem (a missing, repeated
or unknown target, a theorem text that is not the verified one) is rejected: exit 1.  `--mutate K` is a control:
it flips the sign of the K-th term of the generated chart field, and the run must fail.

`magrod prove --fixed-point THETA --level H ...` proves instead a symmetric hyperbolic fixed point of the section map
sin psi = 0 on the level Hbar = H (magrod/proof/provers/section_fixed_point.py; statement 11), the float search
looking for theta* on Fix(R) within 0.02 of THETA (no condition mu > 2 lambdabar: the level need not hold the tilted
saddle).  `magrod prove --horseshoe THETA --level H ...` proves a horseshoe of that section map (positive topological
entropy) by covering relations along the homoclinic orbit of the saddle near THETA
(magrod/proof/provers/section_horseshoe.py; statement 12; 1-2 min at Fig 4(a)); `--design NAME` selects the chain's
design (magrod/proof/designs/NAME.json: fig4a, fig4b, fig4c -- with `--branch pi --root smallest`, the cycle around
Fig 4(c)'s period-6 orbit -- and fig4d).  The pieces of its sets fly on every core (`--workers N`) or on a Dask
cluster (`--scheduler ADDRESS`); the certificate is the same for every choice."""
from __future__ import annotations

import contextlib

from fractions import Fraction

from ..core.errors import ParameterError
from .options import ROOT_INDEX_HELP, add_workers, integer, out_dir

DEFAULTS = {"m": "1.7", "mu": "0.04", "gamma": "1", "delta": "1", "lam": "0.01"}


def add_arguments(p):
    for k, h in (("m", "m = m3/sqrt(B C2), 0 < m < m_c = 2 sqrt(1 + gamma)"), ("mu", "mu > 2 lambdabar"),
                 ("gamma", "extensibility gamma >= 0"), ("delta", "shear compliance delta >= 0"),
                 ("lam", "lambdabar (field strength x current)")):
        p.add_argument(f"--{k}", default=DEFAULTS[k], help=f"{h} (exact decimal or p/q)")
    p.add_argument("--out", default=None, help="directory for certificate.json (required unless --verify)")
    p.add_argument("--verify", default=None, metavar="CERT", help="re-check the certificate CERT instead")
    p.add_argument("--targets", default="0,pi", help="which symmetric orbits: 0, pi or both (0,pi)")
    p.add_argument("--fixed-point", default=None, metavar="THETA", dest="fixed_point",
                   help="prove a hyperbolic fixed point of the section map sin psi = 0 on --level, theta* near THETA")
    p.add_argument("--horseshoe", default=None, metavar="THETA",
                   help="prove a horseshoe of the section map on --level by covering relations along the homoclinic "
                        "orbit of its symmetric saddle near theta = THETA (statement 12)")
    p.add_argument("--design", default="fig4a", metavar="NAME",
                   help="--horseshoe: the named design of the chain (fig4a: the settings of Fig 4(a)'s certificate; "
                        "fig4b: margins 1.5, m = 4 pull-backs, 14 excursion returns; fig4c: the period-6 cycle of Fig 4(c), "
                        "with --branch pi --root smallest; magrod/proof/designs/)")
    p.add_argument("--level", default=None, metavar="H",
                   help="the level Hbar = H of --fixed-point / --horseshoe (exact)")
    p.add_argument("--lam-rad", default="0", metavar="W", dest="lam_rad",
                   help="the homoclinic proof, --fixed-point, --horseshoe, --widen: for every lambdabar in [lam - W, "
                        "lam + W] (lambdabar a state of the validated flights; the homoclinic proof's circle, a fixed "
                        "point's box (--box) and a horseshoe's sets move with lambdabar)")
    p.add_argument("--box", default="moving", choices=("moving", "fixed"),
                   help="--fixed-point with --lam-rad: the theta-box follows the fixed point along lambdabar "
                        "(moving, theta_c + v (lambdabar - lam) +- K' W: ~10x wider intervals) or is the "
                        "same for every lambdabar (fixed, the first interval certificates)")
    p.add_argument("--widen", default=None, metavar="CERT",
                   help="re-prove the point horseshoe certificate CERT for every lambdabar in [lam - W, lam + W] "
                        "(--lam-rad W > 0) without re-proving the point (horseshoe_widen.widen)")
    p.add_argument("--lam-order", default=1, type=int, choices=(1, 2), metavar="ORDER", dest="lam_order",
                   help="--widen, --horseshoe with --lam-rad: how the sets' motion over the interval is enclosed: "
                        "1 (one flight of each piece swept over the interval) or 2 (nodes and second derivatives, "
                        "sub-interval by sub-interval: ~500x wider at Fig 4(a), 25-75 s of CPU per piece at 8-64 "
                        "sub-intervals; kernel/horseshoe_lam2.py)")
    p.add_argument("--lam-nodes", default=8, type=int, metavar="K", dest="lam_nodes",
                   help="--lam-order 2: the number of equal sub-intervals each piece starts with (even, 2 .. 64); "
                        "the prover doubles it, up to 64, for the sets whose links keep an (a') margin below 1/4")
    p.add_argument("--m-back", default=None, metavar="M", dest="m_back",
                   help="--horseshoe: pull-backs of the homoclinic point (HorseshoeSettings.m_back; default 5)")
    p.add_argument("--n-exc", default=None, metavar="N", dest="n_exc",
                   help="--horseshoe: returns of the excursion to Fix(R) (HorseshoeSettings.n_exc; default 8)")
    p.add_argument("--s-star", default=None, metavar="S", dest="s_star",
                   help="--horseshoe: float guess of the homoclinic point x0 + s* e_u (HorseshoeSettings.s_star)")
    p.add_argument("--passes", default=None, metavar="P,P,...",
                   help="--horseshoe: the chain passes' centre-flight tolerances, each 'tol' or 'thin' "
                        "(HorseshoeSettings.passes; default tol,tol,thin)")
    p.add_argument("--branch", default="0", choices=("0", "pi"),
                   help="--fixed-point / --horseshoe: the saddle's branch of the section, psi = 0 or pi")
    # --fixed-point / --horseshoe: the root of the level that x0 lifts to (one help text for --root everywhere)
    p.add_argument("--root", default="largest", metavar="I", help=ROOT_INDEX_HELP)
    add_workers(p, help="--verify: processes re-flying a horseshoe's sets; --horseshoe, --widen: processes flying the "
                        "sets' pieces (default: the CPUs this process may use; the certificate is the same for every "
                        "value)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="--verify / --horseshoe / --widen: fly a horseshoe's sets (pieces) on the running Dask "
                        "scheduler at ADDRESS (tcp://HOST:PORT or HOST:PORT) instead; the checks are made here in "
                        "their serial order")
    p.add_argument("--mutate", default=None, metavar="K",
                   help="control: flip the sign of the K-th term of the generated chart field (must fail)")


def run(args) -> dict:
    if args.verify is not None:
        return _verify(args)
    for opt in ("workers", "scheduler"):
        if getattr(args, opt) is not None and args.horseshoe is None and getattr(args, "widen", None) is None:
            raise ParameterError(opt, "applies to --verify, --horseshoe and --widen (the other provers' flights run "
                                      "in this process)")
    if (getattr(args, "lam_order", 1) != 1 or getattr(args, "lam_nodes", 8) != 8) and args.horseshoe is None \
            and getattr(args, "widen", None) is None:
        raise ParameterError("lam_order", "--lam-order and --lam-nodes apply to --widen and --horseshoe with --lam-rad")
    if getattr(args, "lam_order", 1) == 2 and (args.lam_nodes < 2 or args.lam_nodes % 2 or args.lam_nodes > 64):
        raise ParameterError("lam_nodes", f"must be an even integer in 2 .. 64, got {args.lam_nodes}")
    _flight_workers(args)  # refused before anything runs or is written
    if args.fixed_point is not None:
        return _fixed_point(args)
    if args.horseshoe is not None:
        return _horseshoe(args)
    if getattr(args, "widen", None) is not None:
        return _widen(args)
    from ..proof import (TARGET_ANGLES, ProofSettings, interval_proof_params, interval_proof_settings, mutated_fields,
                         prove_homoclinic, validate_proof_params, validated_fields)

    p = validate_proof_params(args.m, args.mu, args.gamma, args.delta, args.lam)
    targets = tuple(t.strip() for t in str(args.targets).split(",") if t.strip())
    if not targets or any(t not in TARGET_ANGLES for t in targets) or len(set(targets)) != len(targets):
        raise ParameterError("targets", f"must be 0, pi or 0,pi, got {args.targets!r}")
    w = _lam_rad(args)
    interval_proof_params(p, w)  # mu > 2 (lambdabar + W), checked before anything runs
    st = interval_proof_settings(w, targets=targets) if w else ProofSettings(targets=targets)
    if args.out is None:
        raise ParameterError("out", "an output directory is required (or --verify CERT)")
    dest = out_dir("out", args.out)
    module = validated_fields
    if args.mutate is not None:
        module = mutated_fields(integer("mutate", args.mutate, minimum=0, maximum=1000))
    say = None if args.quiet else _stage
    res = prove_homoclinic(p, st, module=module, progress=say)
    out = {"ok": res.ok, "params": p.as_json(), "wall_time_s": round(res.wall_time_s, 3),
           "checks": res.checks, "reason": res.reason}
    if not res.ok:
        out["error"] = res.reason
        return out
    from ..core import io

    io.ensure_writable_dir(dest, "out")
    path = io.atomic_write_json(dest / "certificate.json", {**res.certificate, "provenance": _provenance(args)})
    out["certificate"] = str(path)
    out["crossings"] = [{"target": c["target"], "dtheta_dpsi": c["dtheta_dpsi"], "phi_star": c["newton"]}
                        for c in res.certificate["crossings"]]
    if w:  # the interval the certificate holds on (exact)
        out["lam_interval"] = [str(p.lam - w), str(p.lam + w)]
    return out


def _section_inputs(args, flag: str):
    """What --fixed-point and --horseshoe share: the exact parameters and level, theta (the value of `flag`) in
    (0, pi), the output directory and the chart field (mutated under --mutate).  Every input is checked before
    anything is computed or written."""
    import math

    from ..proof import mutated_fields, validate_fixed_point, validated_fields

    field, value = flag.replace("-", "_"), getattr(args, flag.replace("-", "_"))
    if args.level is None:
        raise ParameterError("level", f"--{flag} needs the level: --level H (exact decimal or p/q)")
    p, h = validate_fixed_point(args.m, args.mu, args.gamma, args.delta, args.lam, args.level)
    try:
        theta = float(value)
    except ValueError:
        raise ParameterError(field, f"must be a number theta in (0, pi), got {value!r}") from None
    if not 0 < theta < math.pi:
        raise ParameterError(field, f"must be a number theta in (0, pi), got {value!r}")
    if args.out is None:
        raise ParameterError("out", "an output directory is required (or --verify CERT)")
    dest = out_dir("out", args.out)
    module = validated_fields
    if args.mutate is not None:
        module = mutated_fields(integer("mutate", args.mutate, minimum=0, maximum=1000))
    return p, h, theta, dest, module


def _section_result(res, p, h, dest, extra, args) -> dict:
    """The JSON result of a section-map proof; the certificate (with its provenance) is written only when the proof
    holds."""
    out = {"ok": res.ok, "params": p.as_json(), "level": f"{h.numerator}/{h.denominator}",
           "wall_time_s": round(res.wall_time_s, 3), "checks": res.checks, "reason": res.reason}
    if not res.ok:
        out["error"] = res.reason
        return out
    from ..core import io

    io.ensure_writable_dir(dest, "out")
    out["certificate"] = str(io.atomic_write_json(dest / "certificate.json",
                                                  {**res.certificate, "provenance": _provenance(args)}))
    out.update(extra(res.certificate))
    return out


def _root(args) -> int:
    r = getattr(args, "root", "largest")
    return {"smallest": 0, "largest": -1}.get(r) if r in ("smallest", "largest") else \
        integer("root", r, minimum=-4, maximum=4)


def _horseshoe(args) -> dict:
    from dataclasses import replace

    from ..proof import HORSESHOE_DESIGNS as DESIGNS
    from ..proof import prove_horseshoe

    design = getattr(args, "design", "fig4a")
    if design not in DESIGNS:
        raise ParameterError("design", f"must be one of {', '.join(DESIGNS)}, got {design!r}")
    st0 = DESIGNS[design]()
    st = replace(st0, branch=getattr(args, "branch", "0"), root=_root(args))
    if st0.period != 1 and (st.branch, st.root) != (st0.branch, st0.root):
        # a cycle design is about one periodic orbit: its branch and root are part of it, not a choice
        raise ParameterError("branch", f"design {design} is the period-{st0.period} orbit on the branch psi = "
                                       f"{st0.branch}, root {st0.root}: pass --branch {st0.branch} --root "
                                       f"{ {0: 'smallest', -1: 'largest'}.get(st0.root, st0.root) }")
    p, h, theta, dest, module = _section_inputs(args, "horseshoe")
    for k, lo, hi in (("m_back", 0, 12), ("n_exc", 1, 80)):
        if getattr(args, k, None) is not None:
            st = replace(st, **{k: integer(k, getattr(args, k), minimum=lo, maximum=hi)})
    if getattr(args, "s_star", None) is not None:
        try:
            s_star = float(args.s_star)
        except ValueError:
            raise ParameterError("s_star", f"must be a number, got {args.s_star!r}") from None
        if not 0 < abs(s_star) < 1:
            raise ParameterError("s_star", f"must satisfy 0 < |s*| < 1, got {args.s_star!r}")
        st = replace(st, s_star=s_star)
    if getattr(args, "passes", None) is not None:
        passes = tuple(x.strip() for x in str(args.passes).split(",") if x.strip())
        if not passes or len(passes) > 6 or any(x not in ("tol", "thin") for x in passes):
            raise ParameterError("passes", f"must be 1-6 of tol, thin separated by commas, got {args.passes!r}")
        st = replace(st, passes=passes)
    w = _lam_rad(args)
    say = None if args.quiet else _stage
    with _flight_mapper(args) as (workers, mapper):
        res = prove_horseshoe(p, h, theta, st, module=module, progress=say, workers=workers, mapper=mapper)
        if res.ok and w:
            from ..proof import widen_horseshoe

            res = widen_horseshoe(res.certificate, w, module=module, progress=say, workers=workers, mapper=mapper,
                                  order=args.lam_order, nodes=args.lam_nodes)
    return _section_result(res, p, h, dest, lambda c: {"entropy": c["entropy"]}, args)


def _widen(args) -> dict:
    """--widen CERT --lam-rad W: the point horseshoe certificate CERT over [lam - W, lam + W] (its own parameters)."""
    from ..proof import load_certificate, validate_fixed_point, widen_horseshoe

    w = _lam_rad(args)
    if not w:
        raise ParameterError("lam_rad", "--widen needs --lam-rad W > 0")
    cert = load_certificate(args.widen)
    if cert.get("kind") != "section_horseshoe" or Fraction(cert["settings"].get("lam_rad", "0")) != 0:
        raise ParameterError("widen", f"must be a point certificate of kind section_horseshoe, got {args.widen!r}")
    if args.out is None:
        raise ParameterError("out", "an output directory is required")
    dest = out_dir("out", args.out)
    p, h = validate_fixed_point(*(cert["params"][k] for k in ("m", "mu", "gamma", "delta", "lam")), cert["level"])
    with _flight_mapper(args) as (workers, mapper):
        res = widen_horseshoe(cert, w, progress=None if args.quiet else _stage, workers=workers, mapper=mapper,
                              order=args.lam_order, nodes=args.lam_nodes)
    return _section_result(res, p, h, dest, lambda c: {"entropy": c["entropy"]}, args)


#: the options that decide a certificate's content, in the order `provenance` spells them (the output directory,
#: --quiet / --json and the controls do not)
_PROVENANCE_OPTIONS = ("fixed_point", "horseshoe", "widen", "level", "m", "mu", "gamma", "delta", "lam", "targets",
                       "design", "branch", "root", "m_back", "n_exc", "s_star", "passes", "lam_rad", "box",
                       "lam_order", "lam_nodes")


def _provenance(args) -> dict:
    """What produced a certificate (its "provenance" field; the verifier checks none of it): the command, each
    option that decides the content spelt out (a certificate's file only by its name: no machine paths)."""
    import shlex
    from pathlib import PurePath

    mode = next((k for k in ("fixed_point", "horseshoe", "widen") if getattr(args, k, None) is not None), None)
    words = ["magrod", "prove"]
    for k in _PROVENANCE_OPTIONS:
        v = getattr(args, k, None)
        if v is None or (k == "targets" and mode) or (k in ("design", "m_back", "n_exc", "s_star", "passes")
                                                     and mode != "horseshoe") or \
                (k in ("branch", "root") and mode not in ("fixed_point", "horseshoe")) or \
                (k == "lam_rad" and str(v) in ("0", "0/1")) or \
                (k == "box" and (mode != "fixed_point" or str(getattr(args, "lam_rad", "0")) in ("0", "0/1"))) or \
                (mode == "widen" and k in ("m", "mu", "gamma", "delta", "lam", "level")) or \
                (k in ("lam_order", "lam_nodes") and (mode not in ("widen", "horseshoe") or getattr(args, "lam_order", 1) == 1)):
            continue
        words += [f"--{k.replace('_', '-')}", PurePath(str(v)).name if k == "widen" else str(v)]
    return {"command": shlex.join(words), "recorded": "by magrod prove"}


def _lam_rad(args) -> Fraction:
    try:
        w = Fraction(str(args.lam_rad))
    except (ValueError, ZeroDivisionError):
        raise ParameterError("lam_rad", f"must be an exact number >= 0, got {args.lam_rad!r}") from None
    if w < 0 or w > 1:
        raise ParameterError("lam_rad", f"must be in [0, 1], got {args.lam_rad!r}")
    return w


def _fixed_point(args) -> dict:
    from ..proof import FixedPointSettings, interval_settings_for, prove_fixed_point

    p, h, theta, dest, module = _section_inputs(args, "fixed-point")
    w = _lam_rad(args)
    branch = getattr(args, "branch", "0")
    progress = None if args.quiet else _stage
    if w and getattr(args, "box", "moving") == "moving":
        from ..proof import prove_fixed_point_moving

        res = prove_fixed_point_moving(p, h, theta, w, root=_root(args), branch=branch, module=module, progress=progress)
    else:
        st = interval_settings_for(p, h, theta, w, root=_root(args), branch=branch) if w else FixedPointSettings()
        res = prove_fixed_point(p, h, theta, st, root=_root(args), branch=branch, module=module, progress=progress)
    return _section_result(res, p, h, dest, lambda c: {"fixed_point": {"newton": _theta_star(c), "trace": c["trace"],
                                                                        "mu_u": c["mu_u"]}}, args)


def _theta_star(c) -> dict:
    """theta* of a fixed-point certificate over its lambdabar interval: the Newton ball, which a moving box's v
    moves by v (lambdabar - lam) (radius |v| lam_rad more)."""
    b, s = c["newton"], c["settings"]
    if "v" not in s:
        return b
    rad = Fraction(b["rad"]) + abs(Fraction(s["v"])) * Fraction(s["lam_rad"])
    return {"mid": b["mid"], "rad": str(rad)}


def _stage(msg):
    import sys

    print(f"magrod prove: {msg}", file=sys.stderr, flush=True)


def _flight_workers(args):
    """--workers as an int (None: not given), refused with --scheduler."""
    if args.scheduler is not None and args.workers is not None:
        raise ParameterError("workers", "sizes the local processes that --scheduler replaces: give one of them")
    return None if args.workers is None else integer("workers", args.workers, minimum=1, maximum=256)


@contextlib.contextmanager
def _flight_mapper(args):
    """(workers, mapper) for a horseshoe's independent flights: `--workers N` local processes, or `--scheduler
    ADDRESS` a Dask cluster (its client closed on the way out)."""
    workers = _flight_workers(args)
    if args.scheduler is None:
        yield workers, None
        return
    from ..proof import dask_mapper
    from ..store.cluster import close_quietly, connect

    client = connect(args.scheduler)
    try:
        yield None, dask_mapper(client)
    finally:
        close_quietly(client)


def _verify(args) -> dict:
    from ..proof import load_certificate, verify_certificate

    with _flight_mapper(args) as (workers, mapper):
        cert = load_certificate(args.verify)
        res = verify_certificate(cert, workers=workers, mapper=mapper)
    out = {"ok": res.ok, "certificate": str(args.verify), **res.to_dict()}
    if not res.ok:
        out["error"] = res.reason
    return out


def format_text(d) -> str:
    if "certificate" in d and "params" not in d:  # --verify (a prove result always carries its params)
        head = f"{d['certificate']}: {d['reason']} ({len(d['checks'])} checks, {d['wall_time_s']:.1f} s)"
        if not d["ok"]:
            return head
        # the theorem as the verifier generated it from what it checked (never the certificate's own text)
        lines = [head, f"theorem: {d['theorem']}"]
        for t, (lo, hi) in d["slopes"].items():
            lines.append(f"  psi = {t}: dtheta_u/dpsi in [{float(Fraction(lo)):.6e}, {float(Fraction(hi)):.6e}]")
        for k, (lo, hi) in d.get("values", {}).items():
            lines.append(f"  {k} in [{float(Fraction(lo)):.12g}, {float(Fraction(hi)):.12g}]")
        return "\n".join(lines)
    if not d["ok"]:
        return f"not proved: {d['reason']}"
    if "fixed_point" in d:
        fp = {k: [float(Fraction(b["mid"]) - Fraction(b["rad"])), float(Fraction(b["mid"]) + Fraction(b["rad"]))]
              for k, b in d["fixed_point"].items()}
        return (f"proved: {len(d['checks'])} checks hold ({d['wall_time_s']:.1f} s); certificate {d['certificate']}\n"
                + "\n".join(f"  {name} in [{fp[k][0]:.12g}, {fp[k][1]:.12g}]" for k, name in
                            (("newton", "theta*"), ("trace", "tr DP(x0)"), ("mu_u", "mu_u"))))
    lines = [f"proved: {len(d['checks'])} checks hold ({d['wall_time_s']:.1f} s); certificate {d['certificate']}"]
    if "entropy" in d:  # --horseshoe (its text output read d["crossings"]: a KeyError after the certificate was written)
        e = d["entropy"]
        return "\n".join(lines + [f"  h_top(P|Lambda) >= log rho > {e['log_rho_lower']:.6g}, rho > {e['rho_lower']}"])
    if "lam_interval" in d:
        lines.append(f"  for every lambdabar in [{d['lam_interval'][0]}, {d['lam_interval'][1]}]")
    for c in d["crossings"]:
        lines.append(f"  psi = {c['target']}: phi* in [{c['phi_star']['mid']} +- {c['phi_star']['rad']}], "
                     f"dtheta_u/dpsi in [{c['dtheta_dpsi']['mid']} +- {c['dtheta_dpsi']['rad']}]")
    return "\n".join(lines)
