"""The command examples of README.md and docs/*.md, each document's run once per test session and shared.

Three tests check the documented commands: each runs clean (tests/test_doc_examples.py and
tests/test_doc_examples_docs.py), the numbers the docs quote from them are what they print
(tests/test_doc_numbers.py, on the same run) and every figure they draw passes the review
(tests/test_figure_review.py). They ran the commands two or three times; :func:`document_run` runs a document's
commands once per session (the ``shared`` fixture: in whichever pytest-xdist worker asks first, the other waiting
for it) and records what each printed, its exit status and the review of its figures.

Every command runs in a process of its own, in the document's scratch folder, as a reader runs it from a shell:
the first of each document that draws no figure as ``python -c "...main()"`` started afresh (as the tests ran
every command), the others forked from a server process (:class:`ForkServer`) that has imported what nearly every command imports
(NumPy, SciPy, Matplotlib, mechcont's engine and commands: about 0.4 s of CPU per command, a fifth of the README
tour's). A forked command is a process started from that state: its own working folder, standard streams (files),
exit status, signal handlers and interpreter exit (atexit, Dask's worker processes), nothing of another command's
run (models, caches, Matplotlib figures or settings, environment) left in it.

A command's figures are reviewed in its own process after it returns (each figure it saved through Matplotlib,
:func:`figure_checks.review_problems`, drawn at its own dpi; the saved files are the reader's, at the command's
dpi), an animation's sampled frames as drawn (test_figure_review's ``reviewing_animations``).
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

TESTS = Path(__file__).resolve().parent
ROOT = TESTS.parent
#: Seconds a command may take (the longest documented command takes about 30 s of CPU).
TIMEOUT = 900
#: Runs ``mechcont ARGS`` in this interpreter with this checkout's mechcont first on the path.
MECHCONT = [sys.executable, "-c", "import sys; sys.argv[0] = 'mechcont'; from mechcont.cli import main; main()"]
#: What the server imports before it forks a command: what nearly every command imports (a command imports the
#: rest itself; importing one a command would not is harmless, the import order of mechcont's lazy names being
#: checked on fresh processes by tests/test_lazy_imports.py).
PRELOAD = ("mechcont", "numpy", "scipy.linalg", "scipy.optimize", "scipy.integrate", "scipy.sparse", "scipy.stats",
           "matplotlib", "matplotlib.pyplot", "mechcont.cli", "mechcont.equations", "mechcont.continuation",
           "mechcont.models", "mechcont.mechanism", "mechcont.analysis", "mechcont.dynamics", "mechcont.outputs",
           "figure_checks")


@dataclass(frozen=True)
class CommandRun:
    """One documented command as it ran: its ``text`` (as the document shows it, joined), ``args``,
    ``returncode``, ``stdout``, ``stderr``, whether it was started afresh (``fresh``; else forked), and
    ``figures``: ``{file name: review problems}`` of every figure it saved through Matplotlib and every animation
    whose sampled frames were reviewed."""

    text: str
    args: tuple[str, ...]
    returncode: int
    stdout: str
    stderr: str
    fresh: bool
    figures: dict[str, list[str]] = field(default_factory=dict)


@dataclass(frozen=True)
class DocumentRun:
    """A document's examples run in order in ``folder`` (a copy of ``examples/`` and the files its ``# file:``
    blocks write): ``commands[k]`` is the run of ``steps[k]`` when that step is a command (``None`` for a file
    block, and for the commands after one that failed, which are not run); ``in_repository``: files a command
    named as its output that appeared in the repository's root."""

    name: str
    folder: Path
    steps: list[tuple[str, str]]
    commands: list[CommandRun | None]
    in_repository: list[str]

    def ran(self) -> list[CommandRun]:
        """The commands that ran, in order."""
        return [c for c in self.commands if c is not None]


def document_run(path: Path, shared) -> DocumentRun:
    """The run of ``path``'s examples in this session (:func:`run_document` in the session's shared folder, once)."""
    return shared.get(f"doc-{re.sub(r'[^A-Za-z0-9_-]', '_', path.name)}",
                      lambda: run_document(path, shared.root / f"doc-{path.stem}"))


def run_document(path: Path, folder: Path) -> DocumentRun:
    """Run the examples of ``path`` in order in ``folder`` (made afresh): the first command that writes no figure
    started afresh, the others forked from :func:`server`; stops after a command that fails."""
    from test_doc_examples import _arguments, examples, outputs

    if folder.exists():
        shutil.rmtree(folder)
    folder.mkdir(parents=True)
    shutil.copytree(ROOT / "examples", folder / "examples")
    before = set(os.listdir(ROOT))
    steps = examples(path)
    runs = [k for k, (kind, text) in enumerate(steps) if kind == "run"]
    fresh = next((k for k in runs if not writes_figure(_arguments(steps[k][1]))), runs[0] if runs else None)
    commands: list[CommandRun | None] = []
    named: list[str] = []
    for k, (kind, text) in enumerate(steps):
        if kind == "file":
            name, body = text.split("\n", 1)
            (folder / name).write_text(body, encoding="utf-8")
        if kind == "file" or any(c is not None and c.returncode for c in commands):
            commands.append(None)
            continue
        args = tuple(_arguments(text))
        commands.append(run_fresh(text, args, folder) if k == fresh else server().run(text, args, folder))
        named += outputs(list(args))
    in_repository = sorted({out for out in named if Path(out).parts[0] not in before and (ROOT / out).exists()})
    return DocumentRun(path.name, folder, steps, commands, in_repository)


def writes_figure(args: list[str]) -> bool:
    """Whether the command of arguments ``args`` draws a figure (``--plot``, ``draw``, ``animate``)."""
    return "--plot" in args or any(a.startswith("--plot=") for a in args) or args[0] in ("draw", "animate")


def _environment() -> dict[str, str]:
    """The environment of a command: this checkout's mechcont first on the path, Matplotlib's Agg backend."""
    import mechcont

    return dict(os.environ, MPLBACKEND="Agg",
                PYTHONPATH=os.pathsep.join([str(Path(mechcont.__file__).parent.parent), os.environ.get("PYTHONPATH", "")]))


def run_fresh(text: str, args: tuple[str, ...], folder: Path) -> CommandRun:
    """``mechcont ARGS`` in a new interpreter in ``folder`` (figures not reviewed: see :func:`_reviewed_run`)."""
    r = subprocess.run(MECHCONT + list(args), cwd=folder, env=_environment(), capture_output=True, text=True,
                       timeout=TIMEOUT)
    return CommandRun(text, args, r.returncode, r.stdout, r.stderr, True)


class ForkServer:
    """A process that has imported :data:`PRELOAD` and forks one child per command (:func:`serve`)."""

    def __init__(self) -> None:
        import tempfile

        # started in an empty folder (a ``-c`` process imports from its working folder first), the tests' folder
        # last on its path (figure_checks, the review)
        self.folder = tempfile.mkdtemp(prefix="mechcont-fork-server-")
        self.process = subprocess.Popen(
            [sys.executable, "-c", f"import sys; sys.path.append({str(TESTS)!r}); import doc_runs; doc_runs.serve()"],
            cwd=self.folder, env=_environment(), stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)

    def run(self, text: str, args: tuple[str, ...], folder: Path) -> CommandRun:
        """``mechcont ARGS`` in a child forked in ``folder``, its figures reviewed."""
        names = {s: folder / f".doc-run-{s}" for s in ("stdout", "stderr", "figures")}
        request = {"args": list(args), "cwd": str(folder), **{k: str(v) for k, v in names.items()}}
        assert self.process.stdin is not None and self.process.stdout is not None
        self.process.stdin.write(json.dumps(request) + "\n")
        self.process.stdin.flush()
        answer = self.process.stdout.readline()
        if not answer:
            raise RuntimeError(f"the fork server ended (exit {self.process.wait()}) running `{text}`")
        said = {k: names[k].read_text(encoding="utf-8") if names[k].exists() else "" for k in names}
        for p in names.values():
            p.unlink(missing_ok=True)
        figures = json.loads(said["figures"]) if said["figures"] else {}
        return CommandRun(text, args, json.loads(answer)["returncode"], said["stdout"], said["stderr"], False, figures)

    def close(self) -> None:
        """End the server (it ends when its input does)."""
        assert self.process.stdin is not None
        self.process.stdin.close()
        self.process.wait(timeout=60)
        shutil.rmtree(self.folder, ignore_errors=True)


_SERVER: list[ForkServer] = []


def server() -> ForkServer:
    """This process's :class:`ForkServer` (started on first use, ended at exit)."""
    if not _SERVER:
        import atexit

        _SERVER.append(ForkServer())
        atexit.register(_SERVER[0].close)
    return _SERVER[0]


def serve() -> None:
    """The server's loop (run as ``python -c``): import :data:`PRELOAD`, then for each request on stdin (a JSON line:
    ``args``, ``cwd`` and the files for the child's ``stdout``, ``stderr`` and ``figures``) fork a child that runs
    the command (:func:`_child`, never returning here) and answer ``{"returncode": ...}`` once it has ended."""
    import importlib

    for name in PRELOAD:
        importlib.import_module(name)
    requests, answers = sys.stdin, os.fdopen(os.dup(1), "w")
    for line in requests:
        request = json.loads(line)
        sys.stdout.flush()
        sys.stderr.flush()
        pid = os.fork()
        if pid == 0:
            answers.close()
            _child(request)   # ends the process
        _, status = os.waitpid(pid, 0)
        answers.write(json.dumps({"returncode": os.waitstatus_to_exitcode(status)}) + "\n")
        answers.flush()


def _child(request: dict) -> None:
    """Become the command's process: its folder, standard streams and arguments; run ``main()`` as the console
    script does, review the figures it saved, and exit as it exits (SystemExit through the interpreter's exit:
    atexit, the flush of its streams; an exception's traceback and status 1 as Python prints them)."""
    import signal

    os.chdir(request["cwd"])
    null = os.open(os.devnull, os.O_RDONLY)
    os.dup2(null, 0)
    os.close(null)
    for fd, name in ((1, "stdout"), (2, "stderr")):
        f = os.open(request[name], os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        os.dup2(f, fd)
        os.close(f)
    signal.alarm(TIMEOUT)   # SIGALRM ends a command that hangs
    sys.argv = ["mechcont", *request["args"]]
    try:
        _reviewed_run(Path(request["figures"]), request["args"][0] == "animate")
    except SystemExit:
        sys.stdout.flush()
        raise
    sys.exit(0)


def _reviewed_run(figures_file: Path, animates: bool) -> None:
    """``main()`` with every figure saved through Matplotlib recorded and reviewed once it returns (or exits): the
    problems written to ``figures_file`` as ``{file name: [problem, ...]}``, the animations' sampled frames
    included."""
    import contextlib

    import matplotlib.figure
    from figure_checks import review_problems

    from mechcont.cli import main

    saved: dict[str, object] = {}
    save = matplotlib.figure.Figure.savefig

    def savefig(self, fname, *args, **kwargs):
        name = Path(str(fname)).name
        m = re.match(r"^\.(.+)\.mechcont-\d+-", name)   # atomic_write's temporary file: .<stem>.mechcont-<pid>-…
        saved[(m.group(1) + Path(name).suffix) if m else name] = self
        return save(self, fname, *args, **kwargs)

    animations: dict[str, list[str]] = {}
    with contextlib.ExitStack() as stack:
        if animates:
            from test_figure_review import reviewing_animations

            animations = stack.enter_context(reviewing_animations())
        matplotlib.figure.Figure.savefig = savefig
        try:
            main()
        finally:
            matplotlib.figure.Figure.savefig = save
            problems: dict[str, list[str]] = {}
            for name, fig in sorted(saved.items()):
                try:
                    problems[name] = review_problems(fig, name)
                except Exception as exc:   # the review's failure, not the command's: its exit status stays its own
                    problems[name] = [f"{name}: the review failed: {exc!r}"]
            figures_file.write_text(json.dumps({**problems, **animations}), encoding="utf-8")
