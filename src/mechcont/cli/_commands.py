"""Imports every command module so that each registers itself on the group."""
from . import draw  # noqa: F401  (mechcont draw, mechcont animate)
from . import equations  # noqa: F401  (mechcont equations)
from . import sweep  # noqa: F401  (mechcont sweep)
from . import downlock  # noqa: F401  (mechcont downlock)
from . import design  # noqa: F401  (mechcont design)
from . import models, continue_, folds  # noqa: F401,E401  (mechcont models, continue, folds)
from . import paper  # noqa: F401  (mechcont paper)
