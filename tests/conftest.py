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


#: The longest files (measured alone with a fresh cache on the 2-core machine: 20-100 s of CPU each, most
#: others a few seconds), collected first. With ``--dist loadfile`` (run.sh) each pytest-xdist worker takes
#: the next file in collection order, so a long file collected last ran alone on one core at the end while
#: the other idled. All but test_doc_examples start by building the generated dual-sidestay gear (one
#: disk-cache entry; a second process waits for the first's build): it is second, so the other worker
#: starts on work of its own while the first builds the gear.
LONGEST_FIRST = ["test_dsopt.py", "test_doc_examples.py", "test_dual_sidestay.py", "test_physical_limits.py",
                 "test_freefall_paper.py", "test_dual_sidestay_generated.py", "test_freefall_more.py",
                 "test_assembly_compliance.py", "test_dynamics_inertial.py", "test_freefall.py"]


@pytest.hookimpl(trylast=True)  # after pytest's own reordering for shared fixtures
def pytest_collection_modifyitems(session, config, items):
    rank = {name: i for i, name in enumerate(LONGEST_FIRST)}
    items[:] = sorted(items, key=lambda item: rank.get(item.path.name, len(rank)))  # stable: each file's order kept
