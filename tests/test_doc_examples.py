"""Every `magrod ...` example in README.md and docs/*.md is a command line that parses (no unknown, misspelt or
duplicated option) and, for chaosmap, passes the whole validation (issue 17: "every example runs as a test");
the codimension-one continuation example of docs/howto.md, which used to fail with exit 1, runs (a few steps)."""
import json
import re
import shlex
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from magrod import cli

ROOT = Path(__file__).resolve().parent.parent
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def _blocks(text: str):
    """The shell code blocks of a Markdown text (fences with no language, bash, sh or console)."""
    block, lang = None, None
    for line in text.splitlines():
        if line.startswith("```"):
            if block is None:
                block, lang = [], line[3:].strip()
            else:
                if lang in ("", "bash", "sh", "console", "shell"):
                    yield "\n".join(block)
                block = None
        elif block is not None:
            block.append(line)


def _examples():
    out = []
    for path in DOCS:
        if not path.exists():
            continue
        for block in _blocks(path.read_text()):
            text = re.sub(r"\\\n\s*", " ", block)  # shell line continuations
            for line in text.splitlines():
                line = line.split(" #", 1)[0].strip()
                m = re.search(r"(?:^|&&\s*|^\$\s*)magrod\s+(\S.*)$", line)
                if not m or m.group(1).split()[0] not in cli.SUBCOMMANDS:
                    continue
                cmd = re.sub(r"\[[^\]]*\]", "", m.group(1)).strip()  # [--quick]: optional parts
                out.append((f"{path.name}: magrod {cmd}"[:90], cmd))
    return out


EXAMPLES = _examples()


def test_there_are_examples():
    assert len(EXAMPLES) >= 15, EXAMPLES


@pytest.mark.parametrize("where,cmd", EXAMPLES, ids=[w for w, _ in EXAMPLES])
def test_documented_command_parses(where, cmd):
    argv = shlex.split(cmd)
    args = cli.build_parser().parse_args(argv)  # UsageError (unknown / duplicated option, bad choice) fails here
    if argv[0] == "chaosmap":
        from magrod.chaos import maps
        from magrod.cli import chaosmap

        spec = chaosmap.spec_from_args(args)
        _, workers = chaosmap._cluster_from_args(args)
        maps.check_cost(spec, workers or 1)


def test_the_codimension_one_continuation_example_runs(tmp_path):
    line = next(c for _, c in EXAMPLES if c.startswith("continue --mu2lam"))
    argv = [a if a != "out/curve" else str(tmp_path / "curve") for a in shlex.split(line)]
    r = subprocess.run([sys.executable, "-m", "magrod.cli", *argv, "--steps", "1", "--json", "--quiet"],
                       capture_output=True, text=True, cwd=tempfile.gettempdir(), timeout=900)
    assert r.returncode == 0, r.stderr
    obj = json.loads(r.stdout)
    assert obj["ok"] and obj["points"] == 2 and obj["max_residual"] <= 1e-10
