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
def shared(tmp_path_factory):
    """A :class:`session_store.SessionStore`: a long computation several test files check, run once per session
    however many pytest-xdist workers ask for it (in the session's temporary folder, which the workers share)."""
    from session_store import SessionStore

    base = tmp_path_factory.getbasetemp()
    return SessionStore(base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base)


@pytest.fixture(scope="session")
def overcentre():
    from mechcont.models import build_overcentre

    return build_overcentre()


#: The longest files, longest first as far as it matters (most others take a few seconds of CPU), collected
#: first. With ``--dist loadfile`` (run.sh) each pytest-xdist worker takes the next file in collection order,
#: so a long file collected last ran alone on one core at the end while the other idled. Measured 2026-11-28/29
#: (the whole suite on two workers, moderately loaded machine): the documentation's commands (README 146 s,
#: docs/*.md 190 s: two files, so that they run side by side), test_dsopt (its first build of the generated
#: dual-sidestay gear, 106 s, and the optimum), test_figure_review (the paper sections, the freefall's 47-102 s
#: run once per session for it and test_freefall_paper: the ``shared`` fixture), then 45-60 s each. Most of the
#: dual-sidestay files start by building the generated dual-sidestay gear (one disk-cache entry; a second process
#: waits for the first's build): test_doc_examples_docs, which needs it only in its last document
#: (reliability.md), is second, so the other worker starts on work of its own while the first builds the gear.
#: test_freefall_paper right after test_figure_review: both ask for the freefall section, which test_figure_review
#: reviews last, so that the other worker computes it meanwhile. test_paper, test_dynamics_paper and
#: test_paper_animation read the runs test_figure_review makes (sections, the paper's GIF): later, in name order.
LONGEST_FIRST = ["test_dsopt.py", "test_doc_examples_docs.py", "test_doc_examples.py", "test_figure_review.py",
                 "test_freefall_paper.py", "test_freefall_more.py", "test_dynamics_inertial.py",
                 "test_dual_sidestay_generated.py", "test_dual_sidestay.py",
                 "test_assembly_compliance.py", "test_freefall.py", "test_doc_numbers.py",
                 "test_spatial_planar.py", "test_redundancy_switch.py", "test_study_cli.py",
                 "test_reliability.py", "test_spatial_cli.py", "test_nose_gear_paper.py",
                 "test_model.py"]


def pytest_configure(config):
    """Keep the collection order (LONGEST_FIRST) for ``--dist loadfile``: pytest-xdist (3.6 and later) otherwise
    sorts the files by their number of tests (``--loadscope-reorder``, on by default), which put long files of one
    to six tests (the freefall section, the paper's animation) last, where one ran alone on one core while the
    other idled."""
    if hasattr(config.option, "loadscopereorder"):
        config.option.loadscopereorder = False


@pytest.hookimpl(trylast=True)  # after pytest's own reordering for shared fixtures
def pytest_collection_modifyitems(session, config, items):
    rank = {name: i for i, name in enumerate(LONGEST_FIRST)}
    items[:] = sorted(items, key=lambda item: rank.get(item.path.name, len(rank)))  # stable: each file's order kept
