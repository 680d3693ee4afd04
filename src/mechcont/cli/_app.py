"""The click group and the error handling shared by every command.

Every failure the user can fix is one line ``error: ...`` on stderr and exit status 2;
Ctrl-C is ``error: interrupted`` (130), SIGTERM ``error: terminated`` (143) and SIGHUP
``error: hung up`` (129), never a
traceback, and both unwind the stack so that no temporary output file is left behind.
"""

from __future__ import annotations

import errno
import gc
import importlib
import os
import signal
import sys
import threading
from collections.abc import Callable, Sequence
from typing import Any, NoReturn

import click

from .._signals import TERMINATING, Terminated, clear, install, pending, raise_held, raise_pending
from ..errors import MechcontError, one_line


def _fail(message: str, status: int) -> NoReturn:
    click.echo(f"error: {one_line(message)}", err=True)
    sys.exit(status)


def _fail_for_signal() -> NoReturn:
    signum = pending()
    if signum in TERMINATING:
        _fail_terminated(signum)
    _fail("interrupted", 130)


def _fail_terminated(signum: int) -> NoReturn:
    """``error: terminated`` (SIGTERM) or ``error: hung up`` (SIGHUP), exit status 128 + the signal."""
    _fail("hung up" if signum == getattr(signal, "SIGHUP", None) else "terminated", 128 + signum)


#: Command name -> the module of this package that defines it. A command's module (and what it
#: imports) is loaded only when that command runs or the command list is shown: a process that
#: runs ``mechcont continue`` does not import the other fifteen (about 25 ms of its start-up).
#: tests/test_cli.py checks that this map names every command where it is defined.
COMMAND_MODULES = {
    "animate": "draw", "check": "check", "continue": "continue_", "design": "design", "downlock": "downlock",
    "draw": "draw", "equations": "equations", "explore": "explore", "folds": "folds", "freefall": "freefall",
    "models": "models", "optimize": "optimize", "paper": "paper", "sensitivity": "sensitivity",
    "simulate": "simulate", "study": "study", "sweep": "sweep",
    "cycles": "cycles",
}


class _Group(click.Group):
    """Every failure the user can fix is one line on stderr and exit status 2; each command's
    module is imported on first use (:data:`COMMAND_MODULES`)."""

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        module = COMMAND_MODULES.get(cmd_name)
        if cmd_name not in self.commands and module is not None:
            importlib.import_module(f"{__package__}.{module}")
        return super().get_command(ctx, cmd_name)

    def list_commands(self, ctx: click.Context) -> list[str]:
        _register()
        return super().list_commands(ctx)

    def main(self, args: Sequence[str] | None = None, prog_name: str | None = None, complete_var: str | None = None,
             standalone_mode: bool = True, **extra: Any) -> Any:
        if not standalone_mode:
            return super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
        try:
            rv = super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
            raise_pending()
            raise_held()
        except click.exceptions.Exit as exc:
            sys.exit(exc.exit_code)
        except click.exceptions.Abort as exc:
            if isinstance(exc.__cause__, KeyboardInterrupt):  # click turns Ctrl-C into Abort
                _fail("interrupted", 130)
            _fail("aborted", 1)
        except KeyboardInterrupt:
            _fail("interrupted", 130)
        except Terminated as exc:
            _fail_terminated(exc.signum)
        except click.UsageError as exc:
            where = f"{exc.ctx.command_path} --help" if exc.ctx else "mechcont --help"
            _fail(f"{exc.format_message()} (see '{where}')", 2)
        except MechcontError as exc:
            _fail(str(exc), 2)
        except BrokenPipeError:
            # the reader of our output went away (mechcont models | head): stop quietly
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            sys.exit(1)
        except OSError as exc:
            if pending() is not None:
                _fail_for_signal()
            # the file system refused (disk full, permissions changed during the run, ...)
            what = f"'{exc.filename}'" if exc.filename else "a file"
            _fail(f"cannot write or read {what}: {exc.strerror or errno.errorcode.get(exc.errno or -1, exc)}", 2)
        except Exception:
            # a signal that arrived while a library was mid-update (Matplotlib's transforms)
            # can surface as that library's error when it goes on: the signal is the cause
            if pending() is None:
                raise
            _fail_for_signal()
        sys.exit(rv if isinstance(rv, int) else 0)


@click.group(cls=_Group)
@click.version_option(package_name="mechcont")
@click.option("--no-cache", is_flag=True,
              help="Neither read nor write the disk cache of compiled equations (as MECHCONT_NO_CACHE=1).")
def cli(no_cache: bool) -> None:
    """mechcont: numerical continuation for quasi-static mechanisms (landing gear).

    Models are built-in names (see `mechcont models`) or mechanism description files
    (.toml). Values are SI units (or the units a file declares, [mechanism] units, which
    every header then names), angles in radians. Compiled equations are cached on disk
    (MECHCONT_CACHE_DIR, default the user cache folder) so the next run starts fast.
    """
    if no_cache:
        os.environ["MECHCONT_NO_CACHE"] = "1"


def _register() -> None:
    """Import every command module (each adds itself to ``cli`` on import): for the command list
    and for tests that look commands up in ``cli.commands``."""
    for module in sorted(set(COMMAND_MODULES.values())):
        importlib.import_module(f"{__package__}.{module}")


def _signal_aware_unraisable_hook(
        previous: Callable[[sys.UnraisableHookArgs], object]) -> Callable[[sys.UnraisableHookArgs], None]:
    """A ``sys.unraisablehook`` that stays quiet about the signal exceptions of :func:`main`.

    A signal that lands in a callback whose exceptions Python cannot raise (a weakref
    callback of Matplotlib's transforms, a ``__del__``) would print "Exception ignored in"
    with a traceback. The handler has recorded the signal, and :func:`raise_pending` raises
    it again at the next safe point, so nothing is lost by not printing it; every other
    unraisable exception goes to ``previous``."""

    def hook(unraisable: sys.UnraisableHookArgs) -> None:
        if isinstance(unraisable.exc_value, (Terminated, KeyboardInterrupt)):
            return
        previous(unraisable)

    return hook


#: Seconds from the start of :func:`main` with Python's cyclic garbage collector paused (see :func:`_pause_gc`).
GC_PAUSE = 1.0


def _pause_gc() -> None:
    """Pause the cyclic garbage collector for the start-up; a daemon timer resumes it.

    Start-up (the imports, the model from the disk cache) creates some 40,000 objects that live as
    long as the process and no garbage cycles; the collector scanned them 40 times, 10-15 ms of a
    0.2 s ``mechcont continue``. The timer turns it back on :data:`GC_PAUSE` seconds later, also
    when :func:`main` is called in a longer-lived process, so a long command (a study, the paper)
    collects as usual; a short command exits first (turning it back on as it returns would cost
    one collection of everything the start-up made, 7 ms). Nothing changes when it was already off."""
    if not gc.isenabled():
        return
    gc.disable()
    timer = threading.Timer(GC_PAUSE, gc.enable)
    timer.daemon = True
    timer.start()


def main(argv: Sequence[str] | None = None) -> None:
    """Entry point of the ``mechcont`` console script (SIGTERM and SIGHUP unwind as :class:`Terminated`)."""
    _pause_gc()
    clear()
    restore = install()
    previous_hook = sys.unraisablehook
    sys.unraisablehook = _signal_aware_unraisable_hook(previous_hook)
    try:
        cli.main(args=argv, prog_name="mechcont")
    finally:
        restore()
        sys.unraisablehook = previous_hook
