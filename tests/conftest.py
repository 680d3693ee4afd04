import atexit
import os
import shutil
import tempfile

# one BLAS thread, as `import mechcont` sets when it comes first (matplotlib below imports NumPy)
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import matplotlib  # noqa: E402
import pytest  # noqa: E402

matplotlib.use("Agg")
os.environ.setdefault("MPLBACKEND", "Agg")
# compiled code is cached in a throw-away directory for the session (and the subprocesses
# tests start), never in the user's cache (~/.cache/mechcont)
if "MECHCONT_CACHE_DIR" not in os.environ:
    _cache = tempfile.mkdtemp(prefix="mechcont-test-cache-")
    os.environ["MECHCONT_CACHE_DIR"] = _cache
    atexit.register(shutil.rmtree, _cache, ignore_errors=True)


@pytest.fixture(scope="session")
def overcentre():
    from mechcont.models import build_overcentre

    return build_overcentre()
