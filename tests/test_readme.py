"""The README opens with the two set-up commands, and .ci/run runs exactly the README's test command, then its
reproduce command."""
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def _blocks():
    text = (ROOT / "README.md").read_text()
    return re.findall(r"```bash\n(.*?)```", text, flags=re.S)


@pytest.mark.skipif(not (ROOT / "README.md").exists(), reason="needs the source tree")
def test_readme_commands_and_ci_agree():
    blocks = _blocks()
    cmds = [[ln for ln in b.splitlines() if ln and not ln.startswith("#")][0] for b in blocks[:2]]
    assert "magrod reproduce" in cmds[0]
    assert "pytest" in cmds[1]
    test_cmd = cmds[1].split("&& pip install", 1)[1]
    ci = (ROOT / ".ci" / "run").read_text()
    assert ("pip install" + test_cmd).strip() in ci
    # and the first command, install + reproduce, runs there too (issue 24), after the tests
    assert cmds[0].strip() in ci and ci.index(cmds[0].strip()) > ci.index(("pip install" + test_cmd).strip())
