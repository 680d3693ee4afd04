"""A branch continued across variants (a model with a ``reselect``) that stops at a user event labelled ``RC``
after its choice became final: it ends there, as any stop event ends a branch.

The model is written here by hand: ``x - p = 0`` (so the branch is ``x = p``), with a choice whose quality turns
negative at ``p = 0.5`` and whose re-choice there keeps the one in use (``switch`` returns None): the rest of the
branch is one system without a reselect."""

import pytest

from mechcont import Model, Variable
from mechcont.continuation import ContinuationOptions, ValueEvent, continuation


class _KeepsItsChoice:
    """A reselect whose choice stops suiting the branch at ``p = 0.5`` and is chosen again unchanged there."""

    def quality(self, x):
        return 0.5 - float(x[1])

    def switch(self, model, x, force=False):
        return (model, x) if force else None


def _line():
    vs = [Variable("x", "state", 0.0, "m"), Variable("p", "parameter", 0.0, "m")]
    x, p = (v.symbol for v in vs)
    return Model("line", vs, [x - p], reselect=_KeepsItsChoice())


def test_a_user_stop_labelled_rc_ends_the_branch_after_the_choice_is_final():
    model = _line()
    branch = continuation(model, {"x": 0.0, "p": 0.0}, "p", direction=1,
                          options=ContinuationOptions(bounds={"p": (-1.0, 2.0)}, ds=0.05, dsmax=0.1),
                          events=[ValueEvent("p", 0.8, label="RC", stop=True)])
    rc = branch.special("RC")
    # the choice's end at p = 0.5 (quality zero), then the user's stop at p = 0.8 (exactly: p is continued)
    assert [pt["p"] for pt in rc] == pytest.approx([0.5, 0.8], abs=1e-9)
    assert branch.column("p")[-1] == pytest.approx(0.8, abs=1e-12)
    assert branch.column("x") == pytest.approx(branch.column("p"), abs=1e-12)  # the branch is x = p
    assert branch.success
