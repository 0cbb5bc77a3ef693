"""``strand motion`` from Python: :class:`Motion` and :class:`Pose`."""

from __future__ import annotations

import csv
import io
import json
from typing import Any, Dict, List

from ._result import Result
from ._values import csv_cell as _number


def parse_motion_csv(text: str) -> List[Dict[str, Any]]:
    """The rows of ``motion.csv`` as dicts (column name → value): numbers as int or
    float, ``true``/``false`` as bool, empty cells as None, ``id`` as written."""
    reader = csv.reader(io.StringIO(text))
    header = next(reader)
    return [
        {name: (cell if name == "id" else _number(cell)) for name, cell in zip(header, row)}
        for row in reader
    ]


class Pose:
    """One solved pose of a followed motion: ``value`` (the motion's unit), ``id``
    (its folder under ``steps/`` in ``strand motion``'s output, ``000``, …),
    ``solves`` and ``iterations`` it took (more than one solve: the step was refined),
    and its :class:`Result` (``result.json`` of ``steps/<id>/``)."""

    __slots__ = ("id", "value", "solves", "iterations", "result")

    def __init__(self, id: str, value: float, solves: int, iterations: int, result: Result):
        self.id = id
        self.value = value
        self.solves = solves
        self.iterations = iterations
        self.result = result

    def __repr__(self) -> str:
        return f"<strand.Pose {self.id}: {self.value!r}, {self.result!r}>"


class Motion:
    """A case followed over a range of one of its motions, as ``strand motion`` does:
    from the case's own pose in both directions, warm-started pose to pose.

    ``motion`` and ``unit`` (the parameter's, ``deg``, ``mm``); ``poses``, the solved
    poses in order of the value (:class:`Pose`); ``events`` (``events.csv``'s rows:
    ``kind``, ``what``, ``between`` [from, to] and ``at`` in the motion's unit,
    ``detail``); ``failed``, the directions that ended early (``value`` that could not
    be solved, ``reached``: the last one solved, ``reason``); ``complete``: every pose
    of the range solved and converged (``strand motion`` exits 0, else 3);
    ``following_s``: wall time of the path following, s. :meth:`rows` and
    :attr:`csv` are ``motion.csv`` (lengths in the case's unit).
    """

    __slots__ = ("motion", "unit", "poses", "events", "failed", "complete", "following_s", "csv")

    def __init__(self, followed) -> None:
        motion, unit, poses, events, failed, csv_text, complete, following_s = followed
        self.motion: str = motion
        self.unit: str = unit
        self.poses: List[Pose] = [
            Pose(id, value, solves, iterations, Result(solved))
            for id, value, solves, iterations, solved in poses
        ]
        self.events: List[Dict[str, Any]] = json.loads(events)
        self.failed: List[Dict[str, Any]] = [
            {"value": value, "reached": reached, "reason": reason}
            for value, reached, reason in failed
        ]
        self.complete: bool = complete
        self.following_s: float = following_s
        self.csv: str = csv_text

    @property
    def values(self) -> List[float]:
        """The solved poses' values, in the motion's unit."""
        return [p.value for p in self.poses]

    @property
    def results(self) -> List[Result]:
        """The solved poses' results, in order of the value."""
        return [p.result for p in self.poses]

    def rows(self) -> List[Dict[str, Any]]:
        """``motion.csv``'s rows as dicts (one per pose, failed ones included)."""
        return parse_motion_csv(self.csv)

    def __repr__(self) -> str:
        return (
            f"<strand.Motion {self.motion}: {len(self.poses)} pose(s), "
            f"{len(self.events)} event(s){'' if self.complete else ', INCOMPLETE'}>"
        )
