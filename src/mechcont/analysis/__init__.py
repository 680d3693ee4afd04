"""Analyses built on continuation: families of equilibria (surfaces), downlock, design maps."""

from .surface import equilibrium_family

__all__ = ["equilibrium_family"]
