"""The horseshoe prover's independent flights (one return of each piece of each set) on every core, or on a Dask
cluster: scheduling only, outside the trust base.  The certificate is the serial prover's whatever ran the flights:
each flight is the same deterministic Arb computation wherever it runs (the same settings, precision and field), its
result travels as exact JSON (every ball's midpoint and radius as exact dyadic decimals, every step as an exact
rational), and the prover makes its checks on the results in the serial order, stopping at the first that fails.

A mapper is a callable ``mapper(fn, jobs)`` that runs ``fn(job)`` for each job wherever it likes and yields the results
in the order of ``jobs`` (``local_mapper(workers)``: fresh interpreters on this machine; ``magrod.proof.schedule.
dask_mapper(client)``: a Dask cluster); closing the iterator early (a failed check) stops what is left.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

from flint import arb

from ...core.errors import ParameterError
from .. import ball, fields, section_return, taylor
from ..section_return import Moving

# --------------------------------------------------------------------------------------------------------------
# exact JSON of a flight's result (arb balls, exact rationals, tuples)
# --------------------------------------------------------------------------------------------------------------


def encode(x):
    """x as JSON data, losslessly: an arb ball as its exact midpoint and radius (dyadic decimals), a Fraction as
    "p/q", a tuple as a tagged list; dicts, lists, str, int, float, bool and None as themselves."""
    if isinstance(x, arb):
        return {"__arb__": ball.to_json(x)}
    if isinstance(x, Fraction):
        return {"__q__": f"{x.numerator}/{x.denominator}"}
    if isinstance(x, bool) or x is None or isinstance(x, (int, float, str)):
        return x
    if isinstance(x, tuple):
        return {"__tuple__": [encode(v) for v in x]}
    if isinstance(x, list):
        return [encode(v) for v in x]
    if isinstance(x, dict):
        if not all(isinstance(k, str) for k in x):
            raise TypeError("only str keys travel as JSON")
        return {k: encode(v) for k, v in x.items()}
    raise TypeError(f"a {type(x).__name__} does not travel between the prover's processes")


def decode(x):
    """The inverse of encode, at the working precision (a ball's midpoint is exact when it fits: the precision the
    flight ran at)."""
    if isinstance(x, list):
        return [decode(v) for v in x]
    if isinstance(x, dict):
        if set(x) == {"__arb__"}:
            return ball.from_json(x["__arb__"])
        if set(x) == {"__q__"}:
            return Fraction(x["__q__"])
        if set(x) == {"__tuple__"}:
            return tuple(decode(v) for v in x["__tuple__"])
        return {k: decode(v) for k, v in x.items()}
    return x


def normalised(x):
    """decode(encode(x)): x as it arrives from another process.  The decoding is exact for midpoints but rounds a
    radius up by one unit in its 30-bit last place (python-flint builds a ball's radius through Arb's mag type, whose
    conversion rounds up even an exact value), so the prover passes every flight through this form whether it ran
    here or elsewhere: the certificate is then the same for every number of workers.  Flights keep their "t_a"."""
    return decode(encode(x))


def decoded(results, t_as=None):
    """A mapper's flight results, decoded (at the working precision), each with its t_a when t_as is given; a
    worker's error re-raised where the serial flight would have raised it; closing this generator closes the
    mapper's (its flights not yet taken are cancelled)."""
    try:
        for k, r in enumerate(results):
            if "err" in r:
                raise_error(r["err"])
            fl = decode(r["flight"])
            if t_as is not None:
                fl["t_a"] = t_as[k]
            yield fl
    finally:
        close(results)


def close(results) -> None:
    """Close a mapper's (or decoded's) iterator if it can be closed: a failed check cancels the flights left."""
    stop = getattr(results, "close", None)
    if stop is not None:
        stop()


# the errors a flight may raise, re-raised in the prover by name (the serial prover's reasons, word for word)
ERRORS = {"EnclosureError": taylor.EnclosureError, "GuardError": taylor.GuardError,
          "CrossingError": taylor.CrossingError, "InexactBall": ball.InexactBall, "ValueError": ValueError,
          "ZeroDivisionError": ZeroDivisionError, "ArithmeticError": ArithmeticError}


def raise_error(err) -> None:
    """Re-raise a worker's recorded error [class name, message] as the serial flight would have raised it."""
    name, msg = err
    if name == "LinAlgError":
        import numpy as np

        raise np.linalg.LinAlgError(msg)
    raise ERRORS.get(name, RuntimeError)(msg)


# --------------------------------------------------------------------------------------------------------------
# one piece's return: the job a worker runs
# --------------------------------------------------------------------------------------------------------------
#: the settings a piece's flight reads (HorseshoeSettings' names)
FLIGHT_SETTINGS = ("prec", "order", "tol", "tol_thin", "p_rad", "lead", "t1", "newton", "integrator",
                   "thin_integrator")


def prover_field(p, module, st):
    """The chart field the prover flies.  With the Taylor-model integrator its Taylor coefficients come from Newton's
    iteration on series, as the verifier's do (kernel/horseshoe_sets.py): the Taylor-model remainder is validated
    on the box's own coefficient balls, and Picard's balls (taylor.py's default, narrower on some boxes) let the
    prover accept a step that the verifier's replay on Newton's balls rejects (seen: Fig 4(b)'s N1, the variational
    remainder).  taylor.py's a priori enclosure does not depend on them that way, so its flights keep Picard's."""
    import dataclasses

    fld = fields.chart_field(p, module)
    if "taylor_model" in (st.integrator, st.thin_integrator):
        fld = dataclasses.replace(fld, series="newton")
    return fld


def widen_flight(job: dict, module=fields.gen) -> dict:
    """One return of a piece moving with lambdabar (section_return.piece_return with `moving`), from the JSON data of
    a widening job: the certificate's params, level and settings, the interval's radius "lam_rad", the piece "c", "A",
    its "pc", "t_a", the centre's steps "thin_steps", its set's "branch" and motion "v".  At the working precision."""
    s = job["settings"]
    p = fields.ExactParams(**{kk: Fraction(job["params"][kk]) for kk in fields.PARAMS})
    w = Fraction(job["lam_rad"])
    pars0, fld0 = p.balls(), fields.chart_field(p, module)
    parsL = fields.parameter_balls(p, w)
    fldL = fields.lam_state_field(p, module)
    if "taylor_model" in (s.get("integrator"), s.get("thin_integrator")):  # Newton's coefficients, as the verifier
        import dataclasses                                                 # (as prover_field)

        fld0, fldL = (dataclasses.replace(f, series="newton") for f in (fld0, fldL))
    mv = Moving(tuple(parsL), fldL, parsL[fields.LAM], p.lam, [Fraction(x) for x in job["v"]])
    return section_return.piece_return(
        pars0, Fraction(job["h"]), fld0, [Fraction(x) for x in job["c"]], [[Fraction(x) for x in row]
                                                                            for row in job["A"]],
        Fraction(job["pc"]), Fraction(s["p_rad"]), Fraction(job["t_a"]), Fraction(s["lead"]), t1=Fraction(s["t1"]),
        order=int(s["order"]), tol=float(s["tol"]), steps={"thin": [[Fraction(x) for x in ph]
                                                                    for ph in job["thin_steps"]]},
        newton=int(s["newton"]), thin_c1=False, integrator=section_return.integrator(s.get("integrator", "taylor")),
        thin_integrator=section_return.integrator(s.get("thin_integrator", "taylor")), branch=job["branch"],
        moving=mv, module=module)


def node_level_centre(p, h, c, pc: Fraction, prad: Fraction, branch: str, module=fields.gen) -> Fraction:
    """The level's root pbar_psi at the section point c (theta, pbar_theta) and the parameters p, to the working
    precision, as a dyadic: interval Newton's midpoint iterated from pc (a node's Newton centre; the verifier's
    Newton step from it then encloses the root to ~the working precision, where pc's neighbour's would leave
    ~|pc - root|^2 of width)."""
    for _ in range(4):
        pc = ball.fraction(section_return.level_newton_section(p.balls(), h, ball.q(c[0]), ball.q(c[1]), pc, prad,
                                                               module, branch)[0].mid())
    return pc


def widen2_flight(job: dict, module=fields.gen) -> dict:
    """The second-order flights of one piece over the interval (kernel/horseshoe_lam2.fly_piece, adaptive steps),
    from the JSON data of a widening job as widen_flight's plus "lam_nodes"; the nodes' Newton centres first
    (node_level_centre).  Returns fly_piece's result with "nodes_p_c"."""
    import dataclasses

    from ..kernel import horseshoe_lam2 as lam2

    s = job["settings"]
    p = fields.ExactParams(**{kk: Fraction(job["params"][kk]) for kk in fields.PARAMS})
    h, W, K = Fraction(job["h"]), Fraction(job["lam_rad"]), int(job["lam_nodes"])
    c = [Fraction(x) for x in job["c"]]
    A = [[Fraction(x) for x in row] for row in job["A"]]
    v = [Fraction(x) for x in job["v"]]
    pc = Fraction(job["pc"])
    npc = []
    for k, sv in enumerate(lam2.nodes(W, K)):
        if k == K // 2:
            npc.append(pc)  # the point piece's centre at lam, as its thin flight had it
            continue
        pk = dataclasses.replace(p, lam=p.lam + sv)  # the node's parameters, as the kernel's fly_piece makes them
        npc.append(node_level_centre(pk, h, [c[0] + v[0] * sv, c[1] + v[1] * sv], pc, Fraction(s["p_rad"]),
                                     job["branch"], module))
    out = lam2.fly_piece(p, h, s, c, A, v, W, K, pc, npc, Fraction(job["t_a"]), job["branch"], module,
                         node_tol=float(s["tol"]))
    out["nodes_p_c"] = npc
    return out


def widen2_job(job: dict) -> dict:
    """widen2_flight from JSON data -> {"flight": encoded result} or {"err": [class name, message]}."""
    return _flight_job(widen2_flight, job)


def _flight_job(flight, job: dict) -> dict:
    """flight(job) at the job's working precision -> {"flight": encoded result} or {"err": [class name, message]};
    one job at a time per process (python-flint's precision is process-wide)."""
    from ..kernel.pool import JOB_LOCK

    with JOB_LOCK:
        try:
            with ball.workprec(int(job["settings"]["prec"]), int(job["settings"]["series_cap"])):
                return {"flight": encode(flight(job))}
        except Exception as e:  # noqa: BLE001 - handed to the prover, which raises it where the serial run would
            return {"err": _error(e)}


def _error(e) -> list:
    """A worker's exception as [class name, message] (raise_error re-raises it)."""
    import numpy as np

    return ["LinAlgError" if isinstance(e, np.linalg.LinAlgError) else type(e).__name__, str(e)]


def piece_job(job: dict) -> dict:
    """One return of a section piece (section_return.piece_return with the prover's settings), from JSON data:
    {"params", "h", "settings", "c", "A", "pc", "branch", "t_a", "thin"} -> {"flight": encoded result} or
    {"err": [class name, message]}.  One job at a time per process: python-flint's precision is process-wide."""
    from ..kernel.pool import JOB_LOCK

    with JOB_LOCK:
        s = job["settings"]
        st = _FlightSettings(**{k: decode(s[k]) for k in FLIGHT_SETTINGS})
        try:
            with ball.workprec(int(st.prec), int(s["series_cap"])):
                p = fields.ExactParams(**{k: Fraction(v) for k, v in job["params"].items()})
                h = Fraction(job["h"])
                fld = prover_field(p, fields.gen, st)
                thin = decode(job["thin"]) if job["thin"] is not None else None
                c = [Fraction(v) for v in job["c"]]
                A = [[Fraction(v) for v in row] for row in job["A"]]
                fl = section_return.piece_return(
                    p.balls(), h, fld, c, A, Fraction(job["pc"]), st.p_rad, Fraction(job["t_a"]), st.lead, t1=st.t1,
                    order=st.order, tol=st.tol, tol_thin=st.tol_thin, newton=st.newton, box=True, thin=thin,
                    branch=job["branch"], module=fields.gen, integrator=section_return.integrator(st.integrator),
                    thin_integrator=section_return.integrator(st.thin_integrator))
                return {"flight": encode(fl)}
        except Exception as e:  # noqa: BLE001 - handed to the prover, which raises it where the serial run would
            return {"err": _error(e)}


def widen_job(job: dict) -> dict:
    """One return of a piece moving with lambdabar (widen_flight) from JSON data ->
    {"flight": encoded result} or {"err": [class name, message]}; one job at a time per process."""
    return _flight_job(widen_flight, job)


class _FlightSettings:
    def __init__(self, **kw):
        self.__dict__.update(kw)


def settings_json(st) -> dict:
    """The flight settings of a HorseshoeSettings as piece_job reads them (exact: the tolerances as floats, the
    fractions as "p/q")."""
    out = {k: encode(getattr(st, k)) for k in FLIGHT_SETTINGS}
    out["series_cap"] = ball.SERIES_CAP
    return out


# --------------------------------------------------------------------------------------------------------------
# the local mapper: fresh interpreters, one job at a time each, results in the order of the jobs
# --------------------------------------------------------------------------------------------------------------
def cpus() -> int:
    """The CPUs this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def mapper_for(workers, mapper, module):
    """The mapper a prover's `workers` / `mapper` arguments ask for: `mapper` itself; else local_mapper(workers)
    (None: the CPUs this process may use), or None (the flights here) for one worker.  A control's mutated field
    (module other than the generated one) is not importable by another process: its flights stay here."""
    if module is not fields.gen:
        return None
    if mapper is not None:
        return mapper
    n = cpus() if workers is None else int(workers)
    if n < 1:
        raise ParameterError("workers", f"must be at least 1, got {workers}")
    return local_mapper(n) if n > 1 else None


def local_mapper(workers: int):
    """A mapper running jobs in `workers` fresh interpreters on this machine (no multiprocessing: nothing of the
    caller's __main__ is re-run and no process-wide state is changed), each fed one job at a time, so that a long
    flight does not hold up the others' work; the results are yielded in the order of the jobs."""
    workers = int(workers)
    if workers < 1:
        raise ParameterError("workers", f"must be at least 1, got {workers}")

    def mapper(fn, jobs):
        import selectors

        jobs = list(jobs)
        if not jobs:
            return
        root = str(Path(__file__).resolve().parents[3])  # the magrod the caller runs, for the children too
        env = dict(os.environ, PYTHONPATH=os.pathsep.join([root] + [v for v in [os.environ.get("PYTHONPATH")] if v]))
        env.update(OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")
        code = f"from magrod.proof.provers.flights import _worker_main; _worker_main({fn.__module__!r}, {fn.__name__!r})"
        procs = [subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                  env=env, text=True, bufsize=1) for _ in range(min(workers, len(jobs)))]
        sel = selectors.DefaultSelector()
        results, running, nxt = {}, {}, 0
        try:
            for pr in procs:
                sel.register(pr.stdout, selectors.EVENT_READ, pr)

            def feed(pr):
                nonlocal nxt
                if nxt < len(jobs):
                    pr.stdin.write(json.dumps(jobs[nxt]) + "\n")
                    pr.stdin.flush()
                    running[pr.pid] = nxt
                    nxt += 1
                else:  # nothing left for it: it ends, and its end of output is no longer news
                    pr.stdin.close()
                    sel.unregister(pr.stdout)

            for pr in procs:
                feed(pr)
            for want in range(len(jobs)):
                while want not in results:
                    for key, _ in sel.select():
                        pr = key.data
                        line = pr.stdout.readline()
                        if not line:
                            raise RuntimeError(f"a flight worker ended without a result (exit status {pr.wait()})")
                        results[running.pop(pr.pid)] = json.loads(line)
                        feed(pr)
                yield results.pop(want)
        finally:
            sel.close()
            for pr in procs:
                if pr.poll() is None:
                    pr.kill()
                pr.wait()
                for f in (pr.stdin, pr.stdout):
                    try:
                        f.close()
                    except (OSError, ValueError):
                        pass

    return mapper


def _worker_main(module: str, name: str) -> None:
    """A worker of local_mapper: one JSON job per stdin line, one JSON result per stdout line."""
    import importlib

    fn = getattr(importlib.import_module(module), name)
    for line in sys.stdin:
        sys.stdout.write(json.dumps(fn(json.loads(line))) + "\n")
        sys.stdout.flush()
