#!/usr/bin/env bash
# One entry point for a fresh machine: sets up .venv on first use, then runs the job.
#   bash run.sh paper [--dir DIR]   reproduce the paper's analyses (figures + summary)
#   bash run.sh test  [pytest args] run the test suite, in parallel on every core (slow tests too;
#                                   add -m "not slow" for the quick set, -n 0 for one process)
#   bash run.sh bench               run the benchmarks (median of repeated runs)
#   bash run.sh lint                ruff on the sources, tests and benchmarks
#   bash run.sh typecheck           mypy on src/ (configured in pyproject.toml)
#   bash run.sh mechcont ARGS...    any CLI command, run in the folder you call it from (so that the README's
#                                   tour, run in a scratch folder, writes its files there, not in the repository)
set -euo pipefail
here=$PWD
cd "$(dirname "$0")"
root=$PWD
PY=${PYTHON:-python3}
if [ ! -x .venv/bin/python ]; then
  echo "run.sh: creating .venv and installing mechcont with its dependencies and compiling its corrector (first use only: about 1-3 minutes)" >&2
  "$PY" -m venv .venv
fi
stamp=.venv/.mechcont-installed
kernel=src/mechcont/continuation/_ckernel.pyx  # the compiled corrector, built by the install (setup.py)
kernel2=src/mechcont/continuation/_ccondense.pyx  # the collocation's condensation, built beside it
if [ ! -f "$stamp" ] || [ pyproject.toml -nt "$stamp" ] || [ setup.py -nt "$stamp" ] || [ "$kernel" -nt "$stamp" ] ||
   [ "$kernel2" -nt "$stamp" ]; then
  [ -f "$stamp" ] && echo "run.sh: pyproject.toml, setup.py, $kernel or $kernel2 changed: updating .venv" >&2
  .venv/bin/python -m pip install --quiet --upgrade pip
  .venv/bin/python -m pip install --quiet -e ".[test]"
  touch "$stamp"
  echo "run.sh: .venv ready" >&2
fi
# bytecode of mechcont's modules, written here because an editable install gets none where
# PYTHONDONTWRITEBYTECODE is set, and every command would then compile them again (about a
# third of a short command's time)
pyc=.venv/.mechcont-bytecode
if [ ! -f "$pyc" ] || [ -n "$(find src/mechcont -name '*.py' -newer "$pyc" -print -quit)" ]; then
  .venv/bin/python -m compileall -q src/mechcont >/dev/null && touch "$pyc"
fi
cmd=${1:-test}; shift || true
export MPLBACKEND=Agg
# one BLAS thread (mechcont's matrices are small; see src/mechcont/__init__.py), also for test
# processes that import NumPy before mechcont
export OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1}
case "$cmd" in
  test) exec .venv/bin/python -m pytest -q -n "${MECHCONT_TEST_WORKERS:-auto}" --dist loadfile "$@" ;;
  paper) exec .venv/bin/mechcont paper "$@" ;;
  bench) exec .venv/bin/python benchmarks/run.py "$@" ;;
  lint) exec .venv/bin/ruff check src tests benchmarks "$@" ;;
  typecheck) exec .venv/bin/mypy "$@" ;;
  mechcont) cd "$here" && exec "$root/.venv/bin/mechcont" "$@" ;;
  *) echo "run.sh: unknown command '$cmd' (use: paper, test, bench, lint, typecheck, mechcont)" >&2; exit 2 ;;
esac
