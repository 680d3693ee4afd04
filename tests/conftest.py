import os

import matplotlib
import pytest

matplotlib.use("Agg")
os.environ.setdefault("MPLBACKEND", "Agg")


@pytest.fixture(scope="session")
def overcentre():
    from mechcont.models import build_overcentre

    return build_overcentre()
