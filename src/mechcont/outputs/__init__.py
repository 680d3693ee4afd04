"""Outputs: drawings, plots and tables. Submodules import matplotlib lazily."""

from __future__ import annotations

import importlib
from typing import Any

_LAZY = {
    "draw_scene": "drawing", "draw": "drawing", "animate": "animation", "branch_frames": "animation",
    "BranchFrames": "animation", "draw_scene3d": "drawing3d", "draw3d": "drawing3d", "project": "drawing3d",
    "plot_branch": "plotting", "plot_surface": "plotting", "new_figure": "plotting", "save_figure": "plotting",
    "plot_design_region": "plotting", "downlock_figure": "design_plots", "design_figure": "design_plots",
    "branch_figure": "plotting", "plot_sweep": "sweep_plots", "sweep_figure": "sweep_plots",
    "history_figure": "history_plots", "amplitude_figure": "cycle_plots", "plot_amplitude": "cycle_plots",
    "phase_portrait": "cycle_plots", "animate_cycle": "cycle_plots",
}

__all__ = list(_LAZY)  # noqa: PLE0605 - the lazily exported names


def __getattr__(name: str) -> Any:  # any of the lazily exported functions and classes
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'mechcont.outputs' has no attribute {name!r}")
    return getattr(importlib.import_module(f".{module}", __name__), name)
