"""Benchmark (not a test): the axial-stretch sampling of a Poincaré run, the shipped way against the way it was done
before, in one run on the same orbit (Fig 4(a)'s panel start, the body frame, 10 000 iterates by default).

    python benchmarks/stretch_sampler.py [--iterates N] [--json benchmarks/stretch_sampler.json] [--smoke]

Three runs of `poincare_section(panel "4a", stretch_dt=0.05)`, each after a warm-up (compiled integrators):
  * none      : no stretch sampling (stretch_dt None), the section alone;
  * taylor    : the shipped sampler -- propagate_until's step callback keeps each step's Taylor coefficients
                (write_tc) and magrod evaluates them at the sample times (chaos/section._TaylorSteps);
  * c_output  : the previous sampler, reproduced here -- heyoka's continuous output (propagate_until(...,
                c_output=True)) built at every call, i.e. at every section crossing, and called at the sample times.
Reported: CPU seconds of each, the ratio c_output / taylor, the sampling's own cost over `none`, and that the two
samplers' summaries agree (the same samples to a few ulps; the integration itself is the same)."""
from __future__ import annotations

import argparse
import json
import time
from contextlib import contextmanager


@contextmanager
def _continuous_output_sampler():
    """The section loop with heyoka's continuous output instead of the step callback (the previous sampler)."""
    import heyoka._core as core

    from magrod.chaos import section

    cls = core.taylor_adaptive_dbl
    orig_pu, orig_step, orig_flush = cls.propagate_until, section._StretchSampler.step, section._StretchSampler.flush
    stash = {}

    def pu(self, t, *a, callback=None, write_tc=False, **kw):
        if callback is None:
            return orig_pu(self, t, *a, **kw)
        r = orig_pu(self, t, *a, c_output=True, **kw)
        stash["c_out"] = r[4]
        return r

    def flush(self, mode):
        self.add(stash.pop("c_out"), mode)

    cls.propagate_until = pu
    section._StretchSampler.step = lambda self, ta: True
    section._StretchSampler.flush = flush
    try:
        yield
    finally:
        cls.propagate_until = orig_pu
        section._StretchSampler.step, section._StretchSampler.flush = orig_step, orig_flush


def run(iterates: int) -> dict:
    from magrod.chaos import STRETCH_DT
    from magrod.chaos.section import poincare_section

    def one(stretch_dt):
        t = time.process_time()
        res = poincare_section("4a", iterates=iterates, stretch_dt=stretch_dt)
        return time.process_time() - t, res

    poincare_section("4a", iterates=20, stretch_dt=STRETCH_DT)  # compile once
    t_none, _ = one(None)
    t_taylor, a = one(STRETCH_DT)
    with _continuous_output_sampler():
        t_cout, b = one(STRETCH_DT)
    sa, sb = a.stretch, b.stretch
    same = (sa["n_samples"] == sb["n_samples"] and sa["fraction_compressed_body"] == sb["fraction_compressed_body"]
            and abs(sa["min_body"] - sb["min_body"]) <= 1e-12 and abs(sa["max_body"] - sb["max_body"]) <= 1e-12)
    return {"panel": "4a", "iterates": iterates, "samples": sa["n_samples"], "cpu_s": {
        "none": round(t_none, 2), "taylor": round(t_taylor, 2), "c_output": round(t_cout, 2)},
        "ratio_c_output_over_taylor": round(t_cout / t_taylor, 2),
        "sampling_cpu_s": {"taylor": round(t_taylor - t_none, 2), "c_output": round(t_cout - t_none, 2)},
        "summaries_agree": bool(same), "same_points": bool((a.points == b.points).all())}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--iterates", type=int, default=10_000)
    ap.add_argument("--json", default=None)
    ap.add_argument("--smoke", action="store_true", help="200 iterates, nothing written (CI runs every benchmark so)")
    a = ap.parse_args(argv)
    out = run(200 if a.smoke else a.iterates)
    out["date"] = time.strftime("%Y-%m-%d")
    print(json.dumps(out))
    if not (out["summaries_agree"] and out["same_points"]):
        raise SystemExit("stretch_sampler: the two samplers disagree")
    if a.json and not a.smoke:
        with open(a.json, "w") as fh:
            fh.write(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    main()
