import pytest


def pytest_addoption(parser):
    parser.addoption("--full", action="store_true", default=False,
                     help="also run the full-size reproductions marked slow")


def pytest_collection_modifyitems(config, items):
    if config.getoption("--full"):
        return
    skip = pytest.mark.skip(reason="full-size reproduction: run with --full")
    for item in items:
        if "slow" in item.keywords:
            item.add_marker(skip)


@pytest.fixture(scope="session")
def derivation():
    """Run the whole SymPy derivation once per test session (also used by the regenerate-and-diff test)."""
    import tempfile
    from pathlib import Path

    from magrod.derive.build import build

    with tempfile.TemporaryDirectory() as tmp:
        files = build(Path(tmp), verbose=False)
    return files
