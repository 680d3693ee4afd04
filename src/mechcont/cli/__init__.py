"""The ``mechcont`` command line. Each command lives in its own module of this package."""

from ._app import main

__all__ = ["main"]
