"""Imports every command module so that each registers itself on the group."""
from . import (  # noqa: F401,E401  (mechcont models, continue, folds)
    check,  # noqa: F401  (mechcont check)
    continue_,
    design,  # noqa: F401  (mechcont design)
    downlock,  # noqa: F401  (mechcont downlock)
    draw,  # noqa: F401  (mechcont draw, mechcont animate)
    equations,  # noqa: F401  (mechcont equations)
    explore,  # noqa: F401  (mechcont explore)
    folds,
    freefall,  # noqa: F401  (mechcont freefall)
    models,
    optimize,  # noqa: F401  (mechcont optimize)
    paper,  # noqa: F401  (mechcont paper)
    sensitivity,  # noqa: F401  (mechcont sensitivity)
    simulate,  # noqa: F401  (mechcont simulate)
    study,  # noqa: F401  (mechcont study)
    sweep,  # noqa: F401  (mechcont sweep)
)
