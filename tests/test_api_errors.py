"""The public Python functions validate what the CLI validates (issue 17, item 2): RodParams, chaos.Axis and
mr.chaos_map raise ParameterError (a ValueError) naming the field, before any computation (each case must fail in
well under a second: nothing is integrated)."""
import math
import time

import pytest

import magrod as mr
from magrod.chaos import maps
from magrod.core.errors import ParameterError
from magrod.core.params import RodParams

GOOD = dict(m=1.7, mu=0.4, gamma=3.0, delta=3.0, lam=0.135)

# (what, call, field named)
CASES = [
    # RodParams: every value the CLI refuses
    ("m nan", lambda: RodParams(**{**GOOD, "m": float("nan")}), "m"),
    ("m inf", lambda: RodParams(**{**GOOD, "m": math.inf}), "m"),
    ("m negative", lambda: RodParams(**{**GOOD, "m": -1.7}), "m"),
    ("m tiny", lambda: RodParams(**{**GOOD, "m": 1e-4}), "m"),
    ("m subnormal", lambda: RodParams(**{**GOOD, "m": 1e-320}), "m"),
    ("gamma huge", lambda: RodParams(**{**GOOD, "gamma": 1e308}), "gamma"),
    ("delta negative", lambda: RodParams(**{**GOOD, "delta": -1.0}), "delta"),
    ("gamma + delta < 0", lambda: RodParams(**{**GOOD, "gamma": -4.0}), "gamma"),
    ("lam bool", lambda: RodParams(**{**GOOD, "lam": True}), "lam"),
    ("mu text", lambda: RodParams(**{**GOOD, "mu": "abc"}), "mu"),
    ("mu None", lambda: RodParams(**{**GOOD, "mu": None}), "mu"),
    ("mu complex", lambda: RodParams(**{**GOOD, "mu": 1j}), "mu"),
    # Axis
    ("axis name", lambda: maps.Axis("foo", 0, 1, 2), "name"),
    ("axis reversed, n < 0", lambda: maps.Axis("lam", 1, 0, -5), "n"),
    ("axis reversed", lambda: maps.Axis("lam", 1, 0, 5), "hi"),
    ("axis nan", lambda: maps.Axis("lam", float("nan"), 1, 4), "lo"),
    ("axis inf", lambda: maps.Axis("lam", 0, math.inf, 4), "hi"),
    ("axis n 1e9", lambda: maps.Axis("lam", 0, 1, 1e9), "n"),
    ("axis n 2.5", lambda: maps.Axis("lam", 0, 1, 2.5), "n"),
    ("axis n bool", lambda: maps.Axis("lam", 0, 1, True), "n"),
    ("axis empty", lambda: maps.Axis("lam", 0.3, 0.3, 4), "hi"),
    # chaos_map
    ("map bad axis", lambda: mr.chaos_map(("foo", 0, 1, 2), ("gamma", 2, 3, 2)), "x"),
    ("map same axis", lambda: mr.chaos_map(("lam", 0.1, 0.2, 2), ("lam", 0.1, 0.2, 2)), "y"),
    ("map fixed and varied", lambda: mr.chaos_map(("lam", 0.1, 0.2, 2), ("gamma", 2, 3, 2), lam=0.5), "lam"),
    ("map unknown value", lambda: mr.chaos_map(("lam", 0.1, 0.2, 2), ("gamma", 2, 3, 2), zeta=1), "zeta"),
    ("map theta0 0", lambda: mr.chaos_map(("lam", 0.1, 0.2, 2), ("gamma", 2, 3, 2), theta0=0.0), "theta0"),
    ("map theta0 pi", lambda: mr.chaos_map(("lam", 0.1, 0.2, 2), ("gamma", 2, 3, 2), theta0=math.pi), "theta0"),
    ("map theta0 axis through 0", lambda: mr.chaos_map(("theta0", 0.0, 1.0, 2), ("gamma", 2, 3, 2)), "x"),
    ("map theta0 axis past pi", lambda: mr.chaos_map(("lam", 0.1, 0.2, 2), ("theta0", 1.0, 3.2, 2)), "y"),
    ("map renorm tiny", lambda: mr.chaos_map(("lam", 0.1, 0.2, 2), ("gamma", 2, 3, 2), renorm_dt=1e-9), "renorm_dt"),
    ("map renorm 2.3e-308", lambda: mr.chaos_map(("lam", 0.1, 0.2, 2), ("gamma", 2, 3, 2), renorm_dt=2.3e-308),
     "renorm_dt"),
    ("map renorm > T/2", lambda: mr.chaos_map(("lam", 0.1, 0.2, 2), ("gamma", 2, 3, 2), t_max=100, renorm_dt=60),
     "renorm_dt"),
    ("map renorm 0", lambda: mr.chaos_map(("lam", 0.1, 0.2, 2), ("gamma", 2, 3, 2), renorm_dt=0), "renorm_dt"),
    ("map t_max nan", lambda: mr.chaos_map(("lam", 0.1, 0.2, 2), ("gamma", 2, 3, 2), t_max=float("nan")), "t_max"),
    ("map 4096^2 at T 3000", lambda: mr.chaos_map(("lam", 0, 0.3, 4096), ("gamma", 0, 3, 4096)), "t_max"),
    ("map tile 0", lambda: mr.chaos_map(("lam", 0.1, 0.2, 2), ("gamma", 2, 3, 2), tile=0), "tile"),
    ("map tile 2.5", lambda: mr.chaos_map(("lam", 0.1, 0.2, 2), ("gamma", 2, 3, 2), tile=2.5), "tile"),
    ("map root", lambda: mr.chaos_map(("lam", 0.1, 0.2, 2), ("gamma", 2, 3, 2), root="middle"), "root"),
    ("map panel", lambda: mr.chaos_map(("lam", 0.1, 0.2, 2), ("gamma", 2, 3, 2), panel="9z"), "panel"),
    ("map no panel, values missing", lambda: mr.chaos_map(("lam", 0.1, 0.2, 2), ("gamma", 2, 3, 2), panel=None),
     "m"),
    ("map all unphysical", lambda: mr.chaos_map(("delta", -3, -1, 2), ("gamma", 2, 3, 2)), "delta"),
]


@pytest.mark.parametrize("what,call,name", CASES, ids=[c[0] for c in CASES])
def test_public_functions_refuse_what_the_cli_refuses(what, call, name):
    t0 = time.perf_counter()
    with pytest.raises(ParameterError) as e:
        call()
    assert isinstance(e.value, ValueError) and e.value.name == name, (e.value.name, e.value.message)
    assert time.perf_counter() - t0 < 5.0  # refused up front, nothing integrated


def test_the_bounds_are_the_ones_stated():
    """The limits in the messages are the module constants; the estimate is points x (T cost + start cost)."""
    with pytest.raises(ParameterError) as e:
        mr.chaos_map(("lam", 0, 0.3, 4096), ("gamma", 0, 3, 4096))
    spec = maps.MapSpec(maps.Axis("lam", 0, 0.3, 4096), maps.Axis("gamma", 0, 3, 4096), base=maps.panel_base("4a"))
    cpu_h = maps.estimated_cpu_s(spec) / 3600
    assert f"{cpu_h:.3g} CPU-hours" in e.value.message and f"{maps.MAX_WALL_HOURS:g} h" in e.value.message
    assert cpu_h == pytest.approx(4096 ** 2 * (3000 * maps.COST_PER_TIME + maps.COST_PER_START) / 3600)
    # the same map is accepted with enough workers, and a 32 x 32 map at T = 3000 on one
    assert maps.check_cost(spec, workers=16) < maps.MAX_WALL_HOURS * 3600
    small = maps.MapSpec(maps.Axis("lam", 0.12, 0.2, 32), maps.Axis("gamma", 2, 4, 32), base=maps.panel_base("4a"))
    assert maps.check_cost(small, 1) < 60
    # renorm_dt at exactly the bounds is accepted
    maps.MapSpec(small.x, small.y, base=small.base, t_max=3000.0, renorm_dt=3000.0 / maps.MAX_RENORMALISATIONS)
    maps.MapSpec(small.x, small.y, base=small.base, t_max=3000.0, renorm_dt=1500.0)
