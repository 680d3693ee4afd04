"""Wall time of the paper's analyses, for the timings table of ``mechcont paper``."""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def timed(timings: dict, key: str) -> Iterator[None]:
    """Set ``timings[key]`` to the wall time (s) the block took (nothing when it raises)."""
    t0 = time.perf_counter()
    yield
    timings[key] = time.perf_counter() - t0
