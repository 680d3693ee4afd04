"""Every command example of docs/*.md runs clean (issue 25): tests/test_doc_examples.py's check of the README's
tour and the reference's examples (:func:`~test_doc_examples.check_examples`, the convention in its docstring), on
the other documents."""

from __future__ import annotations

import pytest
from test_doc_examples import DOCUMENTS, HERE, check_examples, examples


@pytest.mark.slow
@pytest.mark.parametrize("path", [d for d in DOCUMENTS if d not in HERE and examples(d)],
                         ids=lambda p: p.name)
def test_every_command_example_runs_clean(path, shared):
    check_examples(path, shared)
