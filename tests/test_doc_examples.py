"""Every command example of README.md and docs/*.md runs clean (issue 25).

The convention (also in docs/development.md):

- a fenced block opened with ```` ```sh ```` holds commands a reader runs from the repository's
  root; each of its lines (joined over trailing backslashes, a comment after `` #`` dropped)
  starts with ``mechcont `` (or ``bash run.sh mechcont ``), and every one is run here;
- a block opened with ```` ```bash ```` is shown, not run: the set-up commands
  (``bash run.sh paper``, ``bash run.sh test``) and long runs (the whole paper);
- a ```` ```toml ```` block whose first line is ``# file: NAME.toml`` is written to NAME.toml
  before the commands after it run.

A document's commands run in order in one temporary folder holding a copy of ``examples/``, so a
later command reads an earlier one's output (``branch.csv``). A command fails the test on a
non-zero exit status, a traceback, or warning text on stdout or stderr (``warning``, a branch
``stopped after max_steps``, ``give bounds``).
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import mechcont

ROOT = Path(__file__).resolve().parent.parent
DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
WARNING = re.compile(r"(?i)\bwarning\b|traceback|stopped after max_steps|give bounds")
FENCE = re.compile(r"^```(\w*)[^\n]*\n(.*?)^```", re.S | re.M)
#: Runs ``mechcont ARGS`` in this interpreter with this checkout's mechcont first on the path.
MECHCONT = [sys.executable, "-c", "import sys; sys.argv[0] = 'mechcont'; from mechcont.cli import main; main()"]


def examples(path: Path) -> list[tuple[str, str]]:
    """``[("file", "NAME.toml\\n<text>"), ("run", "mechcont ...")]`` in document order (see the module docstring)."""
    out = []
    for lang, body in FENCE.findall(path.read_text(encoding="utf-8")):
        if lang == "toml" and (m := re.match(r"# file: (\S+\.toml)\n", body)):
            out.append(("file", m.group(1) + "\n" + body))
        elif lang == "sh":
            for line in re.sub(r"\\\n\s*", " ", body).splitlines():
                command = line.split(" #")[0].strip()
                if command and not command.startswith("#"):
                    out.append(("run", command))
    return out


def _arguments(command: str) -> list[str]:
    """The argument list of one example command; refuses anything that is not a plain mechcont call."""
    words = shlex.split(command)
    if words[:3] == ["bash", "run.sh", "mechcont"]:
        words = words[2:]
    assert words[0] == "mechcont", f"not a mechcont command (fence it as ```bash to show it unrun): {command}"
    assert not set(words) & {"|", "&&", ";", ">", "<"}, f"shell syntax in an example run without a shell: {command}"
    return words[1:]


def test_the_readme_tours_every_command_in_runnable_blocks():
    """Cheap guard on the convention: the README's tour is in ```sh blocks and names every command."""
    commands = {_arguments(c)[0] for kind, c in examples(ROOT / "README.md") if kind == "run"}
    from mechcont.cli import _commands  # noqa: F401  (registers every command on the group)
    from mechcont.cli._app import cli

    every = set(cli.commands) - {"paper"}  # paper: the README's main job, a bash block
    assert commands >= every, f"not in the README's tour: {sorted(every - commands)}"
    for path in DOCUMENTS:  # every runnable line parses as a mechcont call
        for kind, text in examples(path):
            if kind == "run":
                _arguments(text)


@pytest.mark.slow
@pytest.mark.parametrize("path", [d for d in DOCUMENTS if examples(d)], ids=lambda p: p.name)
def test_every_command_example_runs_clean(path, tmp_path):
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    env = dict(os.environ, MPLBACKEND="Agg",
               PYTHONPATH=os.pathsep.join([str(Path(mechcont.__file__).parent.parent), os.environ.get("PYTHONPATH", "")]))
    for kind, text in examples(path):
        if kind == "file":
            name, body = text.split("\n", 1)
            (tmp_path / name).write_text(body, encoding="utf-8")
            continue
        r = subprocess.run(MECHCONT + _arguments(text), cwd=tmp_path, env=env, capture_output=True, text=True,
                           timeout=900)
        said = r.stdout + r.stderr
        assert r.returncode == 0, f"{path.name}: `{text}` exited {r.returncode}:\n{said[-3000:]}"
        bad = [ln for ln in said.splitlines() if WARNING.search(ln)]
        assert not bad, f"{path.name}: `{text}` printed:\n" + "\n".join(bad[:10])
