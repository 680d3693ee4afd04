"""Every command example of README.md and docs/*.md runs clean (issue 25).

The convention (also in docs/development.md):

- a fenced block opened with ```` ```sh ```` holds commands a reader runs from the repository's
  root; each of its lines (joined over trailing backslashes, a comment after `` #`` dropped)
  starts with ``mechcont `` (or ``bash run.sh mechcont ``), and every one is run here;
- a block opened with ```` ```bash ```` is shown, not run: the set-up commands
  (``bash run.sh paper``, ``bash run.sh test``) and long runs (the whole paper);
- a ```` ```toml ```` block whose first line is ``# file: NAME.toml`` is written to NAME.toml
  before the commands after it run.

A document's commands run in order in one temporary folder holding a copy of ``examples/`` (once per test
session, each command a process of its own: tests/doc_runs.py, whose run the numbers quoted from the commands and
the review of their figures are checked on too), so a
later command reads an earlier one's output (``branch.csv``), as the README tells a reader to run its
tour (in a scratch folder: the tour must leave the repository as it was, issue 37): every file a
command names as its output is relative, stays inside that folder, and is written there, none in the
repository. A command fails the test on a
non-zero exit status, a traceback, or warning text on stdout or stderr (``warning``, a branch
``stopped after max_steps``, ``give bounds``).
"""

from __future__ import annotations

import re
import shlex
import shutil
import subprocess
from pathlib import Path

import pytest

from mechcont.paper.doc_numbers import COMMANDS, QUOTES, mismatches, quoted, transcript_mismatches

ROOT = Path(__file__).resolve().parent.parent
DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
WARNING = re.compile(r"(?i)\bwarning\b|traceback|stopped after max_steps|give bounds")
FENCE = re.compile(r"^```(\w*)[^\n]*\n(.*?)^```", re.S | re.M)


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


#: The options whose value is a file or folder a command writes.
OUTPUT_OPTIONS = ("--out", "--plot", "--dir")


def outputs(words: list[str]) -> list[str]:
    """The paths ``words`` (a command's arguments) name as outputs (``--out F``, ``--plot=F``, ``--dir D``)."""
    out = []
    for k, w in enumerate(words):
        name, eq, value = w.partition("=")
        if name in OUTPUT_OPTIONS:
            out.append(value if eq else words[k + 1])
    return out


def _arguments(command: str) -> list[str]:
    """The argument list of one example command; refuses anything that is not a plain mechcont call."""
    words = shlex.split(command)
    if words[:3] == ["bash", "run.sh", "mechcont"]:
        words = words[2:]
    assert words[0] == "mechcont", f"not a mechcont command (fence it as ```bash to show it unrun): {command}"
    assert not set(words) & {"|", "&&", ";", ">", "<"}, f"shell syntax in an example run without a shell: {command}"
    return words[1:]


def quoted_here(path: Path) -> dict[int, str]:
    """``{k: source}``: the commands of ``path``'s examples (``examples(path)[k]``) that are a command of
    :data:`~mechcont.paper.doc_numbers.COMMANDS` (the same arguments), whose printed numbers the docs quote."""
    sources = {args: source for source, args in COMMANDS.items()}
    return {k: sources[tuple(_arguments(text))] for k, (kind, text) in enumerate(examples(path))
            if kind == "run" and tuple(_arguments(text)) in sources}


def quoted_wrong(printed: dict[str, str]) -> list[tuple]:
    """The marked numbers and transcript lines of the documents from the sources in ``printed`` (``{source: what it
    printed}``) that are not what they print (tests/test_doc_numbers.py)."""
    names = {n for n, q in QUOTES.items() if q.source in printed}
    texts = {path.name: path.read_text(encoding="utf-8") for path in DOCUMENTS}
    return [(name, *m) for name, text in texts.items() for m in mismatches(text, printed) if m[0] in names] \
        + [(name, *m) for name, text in texts.items() for m in transcript_mismatches(text, printed) if m[0] in printed]


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


def test_every_output_of_the_examples_stays_in_the_folder_they_run_in():
    """Each output path is relative and never climbs out (no ``..``): run in a scratch folder, as the README's
    tour says (its set-up block makes one with ``mktemp -d`` before the first command), nothing lands in the
    repository."""
    for path in DOCUMENTS:
        for kind, text in examples(path):
            if kind == "run":
                for out in outputs(_arguments(text)):
                    assert not Path(out).is_absolute() and ".." not in Path(out).parts, f"{path.name}: {text}"
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    tour = readme.index("```sh\nmechcont models")
    setup = [body for lang, body in FENCE.findall(readme[:tour]) if lang == "bash"][-1]
    assert "mktemp -d" in setup and 'cp -r "$repo/examples" .' in setup


def test_run_sh_runs_mechcont_in_the_callers_folder(tmp_path):
    """``bash run.sh mechcont ...`` from a scratch folder writes there: run.sh (copied beside a stand-in .venv whose
    mechcont prints its working folder) runs the command in the folder it was called from, not its own."""
    repo, scratch = tmp_path / "repo", tmp_path / "scratch"
    (repo / ".venv" / "bin").mkdir(parents=True)
    (repo / "src" / "mechcont" / "continuation").mkdir(parents=True)
    scratch.mkdir()
    for name in ("run.sh", "pyproject.toml", "setup.py", "src/mechcont/continuation/_ckernel.pyx"):
        (repo / name).write_bytes((ROOT / name).read_bytes())
    stub = repo / ".venv" / "bin" / "mechcont"
    stub.write_text('#!/bin/sh\necho "in $PWD: $*"\n')
    stub.chmod(0o755)
    (repo / ".venv" / "bin" / "python").symlink_to(shutil.which("true") or "/bin/true")
    for stamp in (".mechcont-installed", ".mechcont-bytecode"):
        (repo / ".venv" / stamp).touch()
    r = subprocess.run(["bash", str(repo / "run.sh"), "mechcont", "check", "x.toml"], cwd=scratch,
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == f"in {scratch}: check x.toml"


#: The documents whose examples this file runs: the README's tour and the reference's (the others:
#: tests/test_doc_examples_docs.py, a file of its own so that the two run side by side on two pytest-xdist workers;
#: these two documents' runs take about as long as the other five's: 155 s and 209 s, the five 316 s in all, run one
#: after another in one process on the loaded machine, warm disk cache, 2026-11-29).
HERE = [ROOT / "README.md", ROOT / "docs" / "reference.md"]


@pytest.mark.slow
@pytest.mark.parametrize("path", HERE, ids=lambda p: p.name)
def test_every_command_example_runs_clean(path, shared):
    """The README's tour and the reference's examples: :func:`check_examples`."""
    check_examples(path, shared)


def check_examples(path: Path, shared) -> None:
    """The examples of ``path`` as they ran in this session (:func:`doc_runs.document_run`, in a scratch folder):
    each command runs clean, writes its outputs in the scratch folder; and what a command of
    :data:`~mechcont.paper.doc_numbers.COMMANDS` prints is every number the docs quote from it and every line of its
    transcripts (tests/test_doc_numbers.py; checked on this run rather than on a second run of the same command)."""
    from doc_runs import document_run

    run = document_run(path, shared)
    named: list[str] = []
    printed: dict[str, str] = {}
    sources = quoted_here(path)
    for k, ((kind, text), command) in enumerate(zip(run.steps, run.commands)):
        if kind == "file":
            continue
        assert command is not None, f"{path.name}: `{text}` not run"
        said = command.stdout + command.stderr
        assert command.returncode == 0, f"{path.name}: `{text}` exited {command.returncode}:\n{said[-3000:]}"
        bad = [ln for ln in said.splitlines() if WARNING.search(ln)]
        assert not bad, f"{path.name}: `{text}` printed:\n" + "\n".join(bad[:10])
        named += outputs(list(command.args))
        if k in sources:
            printed[sources[k]] = command.stdout
    assert any(c.fresh for c in run.ran()) or not run.ran()   # at least one command of each started afresh
    # every output was written in the scratch folder, none in the repository
    assert all((run.folder / out).exists() for out in named), [out for out in named if not (run.folder / out).exists()]
    assert not run.in_repository, run.in_repository
    assert set(quoted(printed)) == {n for n, q in QUOTES.items() if q.source in printed}
    wrong = quoted_wrong(printed)
    assert not wrong, ("quoted numbers and transcript lines that are not the run's (fill the marks: "
                       f"python -m mechcont.paper.doc_numbers): {wrong}")
