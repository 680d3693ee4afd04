"""The events of a continuation with stops (:func:`~mechcont.analysis.stops.continuation_with_stops`): a stop's
contact or release, which ends a piece, and the first fold, which ends the run."""

from __future__ import annotations

from ..continuation import ContinuationProblem, FoldEvent, PointState, ValueEvent
from ..equations import StopLimit

__all__ = ["StopEvent", "FirstFold"]


class StopEvent(ValueEvent):
    """Contact (``SC``: a free condition reaches its limit) or release (``SR``: a reaction reaches 0); ends a piece."""

    def __init__(self, stop: StopLimit, in_contact: bool):
        if in_contact:
            super().__init__(stop.reaction, 0.0, label="SR", stop=True)
        else:
            super().__init__(stop.condition, stop.limit, label="SC", stop=True)
        self.stop_name, self.side = stop.name, (1 if in_contact else stop.side)

    def value(self, problem: ContinuationProblem, state: PointState) -> float:
        # positive on the allowed side (reaction >= 0, condition on its side of the limit), so a piece
        # that starts at a switch and leaves the allowed side at once ends as "start on a bound"
        return self.side * super().value(problem, state)

    def point_info(self) -> dict:
        return {"stop": self.stop_name}


class FirstFold(FoldEvent):
    """A fold that ends the run (``stop_at_fold``)."""

    stop = True
