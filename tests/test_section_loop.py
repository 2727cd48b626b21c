"""One section loop (issue 25): a start value (SectionStart, from section_start), an options value
(SectionOptions), one stream of section points (section_points) that poincare_section drains and the explorer
draws, and one crossing handling (section._Orbit) that the SIMD lanes of batch.py drive.  The explorer is a
client of the public API: no cli/ module, no private name of the numerics."""
from __future__ import annotations

import ast
import threading
import warnings
from pathlib import Path

import numpy as np
import pytest

import magrod as mr
from magrod.core import systems
from magrod.core.errors import ParameterError
from magrod.core.precision import Precision

ROOT = Path(mr.__file__).resolve().parent


def _same(a, b):
    """Two PoincareResults with the same points, to the last bit, and the same summary (but the wall time)."""
    for k, v in a.arrays().items():
        np.testing.assert_array_equal(v, b.arrays()[k], err_msg=k)
    sa, sb = a.summary(), b.summary()
    sa.pop("wall_s"), sb.pop("wall_s")
    assert sa == sb


# --------------------------------------------------------------------------------------------------------------
# one loop: the scalar path, the lanes, the stream and the explorer give the same points for the same start
def test_scalar_batch_stream_and_explorer_give_the_same_points(monkeypatch):
    """At SIMD width 1 a lane takes the scalar integrator's steps bit for bit (at wider widths the vector
    step-size formula may differ in the last bit: tests/test_batch.py), so all four consumers of a start must
    agree to the last bit, points and metadata alike."""
    from magrod.explorer import worker

    monkeypatch.setenv(systems.BATCH_WIDTH_ENV, "1")
    n = 150
    start = mr.section_start("4a")
    scalar = mr.poincare_section("4a", iterates=n)
    lanes = mr.poincare_sections(["4a", "4b"], iterates=n)[0]
    stream = mr.section_points(start, mr.SectionOptions(iterates=n), first=5, every=0.0)
    chunks = list(stream)
    explorer = worker.stream_section(worker.solve_start(start.params, start.h, start.theta0, start.ptheta0), n)
    _same(scalar, lanes)
    _same(scalar, stream.result)
    explorer.panel = "4a"  # a start clicked on the page names no panel; everything else is the same
    _same(scalar, explorer)
    assert len(chunks) > 2 and chunks[-1].n_total == n
    # a chunk's chart coordinates are the result's, evaluated on fewer columns: heyoka's compiled function runs
    # SIMD blocks and a scalar remainder, whose last bits may differ, so they agree to rounding, not bit for bit
    np.testing.assert_allclose(np.concatenate([c.points for c in chunks]), scalar.points, rtol=4e-16, atol=4e-16)
    np.testing.assert_allclose(np.concatenate([c.dH for c in chunks]), scalar.dH, rtol=0, atol=4e-16)
    np.testing.assert_array_equal(np.concatenate([c.times for c in chunks]), scalar.times)
    np.testing.assert_array_equal(np.concatenate([c.frame for c in chunks]), scalar.frame)


def test_the_scalar_fallback_of_many_starts_is_the_scalar_path():
    """Configurations without a lane kernel (the 4-D chart with its patches, long double) run each start through
    the same loop: bit-identical to one poincare_section per start, patches and frame switches included."""
    kw = dict(iterates=60, formulation="reduced", branch="pi", direction="any")
    many = mr.poincare_sections(["4c", "5a"], **kw)
    for key, r in zip(["4c", "5a"], many):
        _same(r, mr.poincare_section(key, **kw))


def test_a_cancelled_stream_ends_at_once_with_its_points():
    ev = threading.Event()
    ev.set()
    s = mr.section_points(mr.section_start("4a"), mr.SectionOptions(iterates=1000), cancel=ev)
    assert list(s) == [] and not s.result.success and s.result.message == "cancelled after 0 of 1000 iterates"
    with pytest.raises(RuntimeError):
        list(s)  # a stream runs once


# --------------------------------------------------------------------------------------------------------------
# the start and the options: one resolver, errors naming the field
@pytest.mark.parametrize("kw, name", [
    (dict(theta0=0.0), "theta0"), (dict(theta0=float("nan")), "theta0"), (dict(h=-5.0), "h"),
    (dict(h=float("inf")), "h"), (dict(root=7), "root"), (dict(root="middle"), "root"),
    (dict(p_psi0=2.0, h=None), "p_psi0"), (dict(lam="0.1"), "lam"), (dict(kappa=1.0), "kappa"),
])
def test_section_start_names_the_field(kw, name):
    with pytest.raises(ParameterError) as e:
        mr.section_start("4a", **kw)
    assert e.value.name == name, (e.value.name, e.value.message)


def test_section_start_of_a_rod_needs_the_start_and_checks_the_level():
    P = mr.panel("4a")
    with pytest.raises(ParameterError) as e:
        mr.section_start(P.params, P.h)
    assert e.value.name == "theta0" and "missing" in e.value.message
    s = mr.section_start(P.params, P.h, P.theta0, P.ptheta0)
    assert (s.params, s.h, s.panel, s.root_index) == (P.params, P.h, None, 0) and len(s.roots) == 2
    on = mr.section_start(P.params, P.h, P.theta0, P.ptheta0, p_psi0=s.p_psi0)  # h and p_psi0 on the level
    assert on.h == P.h and on.roots.tolist() == [s.p_psi0]
    with pytest.raises(ParameterError) as e:  # off the level by far more than START_LEVEL_TOL
        mr.section_start(P.params, P.h, P.theta0, P.ptheta0, p_psi0=s.p_psi0 + 1e-6)
    assert e.value.name == "h" and "off the level" in e.value.message
    # a panel is a system: its start is resolved once (section_start), the same points as from that start
    a = mr.section_points(P, mr.SectionOptions(iterates=5)).run()
    b = mr.section_points(mr.section_start(P), mr.SectionOptions(iterates=5)).run()
    assert np.array_equal(a.points, b.points)
    with pytest.raises(ParameterError) as e:
        mr.section_points(3.5)  # not a system
    assert e.value.name == "system"


@pytest.mark.parametrize("kw, name", [
    (dict(iterates=0), "iterates"), (dict(iterates=2.5), "iterates"), (dict(iterates=10**9), "iterates"),
    (dict(direction="up"), "direction"), (dict(branch="2pi"), "branch"), (dict(formulation="x"), "formulation"),
    (dict(precision="quad"), "precision"), (dict(precision="long double", formulation="reduced"), "precision"),
    (dict(t_max=-1.0), "t_max"), (dict(stretch_dt=0.0), "stretch_dt"), (dict(pole_switch=(0.2, 0.1)), "pole_switch"),
    (dict(radicand_switch=(0.0, 1e-3)), "radicand_switch"),
])
def test_section_options_name_the_option(kw, name):
    with pytest.raises(ParameterError) as e:
        mr.SectionOptions(**kw)
    assert e.value.name == name, (e.value.name, e.value.message)


def test_options_defaults_are_poincare_sections():
    o = mr.SectionOptions(iterates=300)
    r = mr.poincare_section("4a", iterates=300)
    assert (o.time_limit, o.taylor_tol, o.direction, o.branch, o.formulation) == \
        (r.t_max, r.tol, r.direction, r.branch_filter, r.formulation)
    assert o.batchable and not mr.SectionOptions(stretch_dt=0.05).batchable


# --------------------------------------------------------------------------------------------------------------
# the explorer is a client of the face (an AST rule; the finder is checked on a source that breaks it)
def _explorer_violations(sources: dict) -> list:
    """(file, what) for every import of a cli/ module and every private name taken from a magrod module."""
    out = []
    for rel, src in sources.items():
        tree = ast.parse(src)
        modules = set()  # local names bound to magrod modules
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module != "__future__":
                mod = "." * node.level + (node.module or "")
                inside = node.level > 0 or mod.startswith("magrod")
                if inside and (mod.lstrip(".").split(".")[0] == "cli" or mod.startswith("magrod.cli")
                               or any(a.name == "cli" for a in node.names)):
                    out.append((rel, f"imports {mod}"))
                for a in node.names:
                    if inside and a.name.startswith("_"):
                        out.append((rel, f"imports the private {mod}.{a.name}"))
                    if inside:
                        modules.add(a.asname or a.name)
            elif isinstance(node, ast.Import):
                for a in node.names:
                    if a.name.startswith("magrod"):
                        modules.add(a.asname or a.name.split(".")[0])
                        if ".cli" in a.name:
                            out.append((rel, f"imports {a.name}"))
        for node in ast.walk(tree):
            if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in modules
                    and node.attr.startswith("_") and not node.attr.startswith("__")):
                out.append((rel, f"uses the private {node.value.id}.{node.attr}"))
    return out


def test_the_explorer_uses_only_the_public_api():
    sources = {str(p.relative_to(ROOT)): p.read_text() for p in sorted((ROOT / "explorer").glob("*.py"))}
    assert sources and _explorer_violations(sources) == []


def test_the_explorer_rule_finds_what_the_old_explorer_did():
    """The three breaches of the explorer before issue 25 (explorer/__init__.py, model.py, worker.py)."""
    old = {"a.py": "from ..cli.options import integer\n",
           "b.py": "from ..chaos.section import _admissible_interval\n",
           "c.py": "from ..chaos import section\nres = section._assemble(1, 2)\nta = section._integrators()\n"}
    found = _explorer_violations(old)
    assert [f for f, _ in found] == ["a.py", "b.py", "c.py", "c.py"], found


# --------------------------------------------------------------------------------------------------------------
# Precision all the way down
def test_systems_builders_take_a_precision():
    x = systems.hy.make_vars("x")
    ld = systems.taylor([(x, -x)], [1.0], precision=Precision.LONG_DOUBLE)
    assert ld.state.dtype == np.longdouble
    mp = systems.taylor([(x, -x)], [1.0], precision="mp", bits=100)
    assert mp.state[0].prec == 100
    old = systems.taylor([(x, -x)], [1.0], fp_type=systems.hy.real, prec=100)  # the deprecated spelling
    assert old.state[0].prec == 100
    assert systems.taylor([(x, -x)], [1.0], precision="mp").state[0].prec == Precision.MP.bits
    assert systems.arithmetic(np.longdouble) == (Precision.LONG_DOUBLE, None)
    assert systems.fp_array([0.5], Precision.QUAD)[0] == systems.fp_array([0.5], systems.hy.real128)[0]
    with pytest.raises(ParameterError) as e:
        systems.integrator("body", precision="half")
    assert e.value.name == "precision"
    f = systems.splitting_functions(Precision.LONG_DOUBLE)
    assert f is systems.splitting_functions(np.longdouble) and f["H"].precision is Precision.LONG_DOUBLE


def test_a_section_result_carries_its_precision():
    r = mr.poincare_section("4a", iterates=5, precision="long double")
    name = np.dtype(np.longdouble).name  # "float128" on x86-64 Linux: the file schema's spelling, unchanged
    assert r.precision is Precision.LONG_DOUBLE and r.summary()["fp_type"] == name
    with pytest.warns(DeprecationWarning, match="precision"):
        assert r.fp_type == name
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        r.summary(), r.to_dict()  # the file schema keeps its "fp_type" key without the deprecated attribute


def test_no_fp_type_prec_pairs_in_the_section_loop():
    """The section modules speak Precision only (no fp_type=/prec= keyword reaches the systems builders)."""
    for rel in ("chaos/section.py", "chaos/batch.py", "explorer/worker.py"):
        tree = ast.parse((ROOT / rel).read_text())
        bad = [(rel, n.lineno, k.arg) for n in ast.walk(tree) if isinstance(n, ast.Call)
               for k in n.keywords if k.arg in ("fp_type", "prec")]
        assert bad == []


def test_two_streams_interleaved_on_one_thread_do_not_share_an_integrator():
    """A suspended stream holds its thread's cached integrators; a second stream on the same thread gets its own
    pair (zip of two streams), so both give their own orbit's points."""
    opts = mr.SectionOptions(iterates=120)
    a, b = (mr.section_points(mr.section_start(k), opts, first=3, every=0.0) for k in ("4a", "4d"))
    ia, ib = iter(a), iter(b)
    for _ in zip(ia, ib):
        pass
    list(ia), list(ib)  # drain what zip left
    _same(a.result, mr.poincare_section("4a", iterates=120))
    _same(b.result, mr.poincare_section("4d", iterates=120))
