"""The Examples sections of the public API run as doctests (each example takes seconds on a warm JIT cache)."""
import doctest
import inspect

import pytest

import magrod


@pytest.mark.parametrize("name", sorted(magrod.__all__))
def test_examples_run(name):
    obj = getattr(magrod, name)
    finder = doctest.DocTestFinder(recurse=False)
    tests = finder.find(obj, name=f"magrod.{name}", globs={"magrod": magrod})
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    for t in tests:
        runner.run(t)
    res = runner.summarize(verbose=False)
    assert res.failed == 0, f"{res.failed} of {res.attempted} examples of magrod.{name} failed"
    if inspect.isfunction(obj) or name in ("RodParams", "Precision", "ParameterError"):
        assert res.attempted > 0, f"magrod.{name} has no example"
