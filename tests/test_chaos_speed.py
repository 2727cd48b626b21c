"""The chaos-map throughput changes of issue 18 change no number: the fused renormalisation call gives the values
of the separate compiled functions bit for bit, and indicators computed through it equal those of the unfused
path bit for bit (so every map classification is unchanged)."""
import numpy as np

from magrod.chaos import indicators as I
from magrod.chaos import maps
from magrod.core import systems


def test_fused_renormalisation_function_equals_the_separate_ones():
    rng = np.random.default_rng(7)
    x = rng.normal(size=(systems.dim("body"), 13))
    p = np.repeat(np.array([1.7, 0.4, 3.0, 3.0, 0.135])[:, None], 13, axis=1)
    out = systems.body_renorm_functions()(x, p)
    f = systems.body_functions()
    np.testing.assert_array_equal(out[0], f["H"](x, p)[0])
    np.testing.assert_array_equal(out[1:4], f["casimirs"](x, p))
    np.testing.assert_array_equal(out[4], systems.body_stretch()(x, p)[0])
    np.testing.assert_array_equal(out[5:], systems.body_neutral_gradients()(x, p))


def test_indicators_through_the_fused_path_equal_the_unfused_path():
    base = maps.panel_base("4a")
    starts = []
    for lam, gamma in ((0.135, 3.0), (0.186, 3.0), (0.15, 2.5), (0.2, 3.5), (0.17, 2.0)):
        x0, p, st, _ = maps.start_point({**base, "lam": lam, "gamma": gamma})
        assert st == I.OK
        starts.append((x0, p))
    x0 = np.array([s[0] for s in starts]).T
    p = np.array([s[1] for s in starts]).T
    # 5 orbits in batches of 8, 4 and 2 lanes: fewer orbits than lanes, and a padded last batch (issue 24: the
    # checker was built for the orbits, not for the padded lanes, and failed to broadcast at width 8)
    for b in (8, 4, 2):
        ta = systems.body_tangent_batch(b, None)
        w0 = I.generic_w0(x0.shape[0], x0.shape[1])
        fused = I.tangent_indicators(ta, x0, w0, p, t_max=400.0, project=I.project_neutral, check=I.body_check,
                                     history=True)

        def plain_check(xs, ps):
            chk = I.body_check(xs, ps)
            return lambda x, q: chk(x, q)  # not a _BodyCheck: the unfused path

        plain = I.tangent_indicators(ta, x0, w0, p, t_max=400.0,
                                     project=lambda x, w, q: I.project_neutral(x, w, q), check=plain_check,
                                     history=True)
        assert np.all(fused.status == I.OK), (b, fused.status)
        for key in (*I._KEYS, "status", "log_growth"):
            np.testing.assert_array_equal(getattr(fused, key), getattr(plain, key), err_msg=f"{key}, width {b}")
