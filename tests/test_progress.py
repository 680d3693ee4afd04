"""The progress line: on a terminal only, after a delay, cleared at the end; silent in pipes and with quiet."""

import io

from mechcont._progress import Progress


class Tty(io.StringIO):
    def isatty(self):
        return True


def test_writes_on_a_terminal_and_clears():
    out = Tty()
    with Progress("frames", total=10, unit="frames", stream=out, delay=0.0, interval=0.0) as bar:
        for _ in range(10):
            bar.update()
    text = out.getvalue()
    assert "frames: 10/10 frames (100 %)" in text
    assert text.endswith("\r")  # the line is wiped at the end


def test_silent_when_not_a_terminal_quiet_or_short():
    for stream, quiet, delay in ((io.StringIO(), False, 0.0), (Tty(), True, 0.0), (Tty(), False, 60.0)):
        with Progress("x", total=3, stream=stream, quiet=quiet, delay=delay, interval=0.0) as bar:
            bar.update(3)
        assert stream.getvalue() == ""


def test_as_callback_and_without_total():
    out = Tty()
    bar = Progress("steps", unit="steps", stream=out, delay=0.0, interval=0.0)
    bar()
    bar(4)
    assert bar.value == 5 and "steps: 5 steps" in out.getvalue()
    bar.set(12.5)
    assert bar.value == 12.5
    bar.close()
