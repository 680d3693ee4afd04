"""Built-in models: the paper's own formulations, kept as references."""

from .overcentre import build_overcentre

__all__ = ["build_overcentre"]
