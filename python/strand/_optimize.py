"""``strand optimize`` from Python: :class:`Optimum`."""

from __future__ import annotations

import json
from typing import Any, Dict

from ._result import Result


class Optimum:
    """The best design found by ``strand optimize``'s optimiser (a trust-region SQP
    with exact gradients).

    :meth:`to_dict` is ``optimum.json`` (``converged``, ``termination``,
    ``parameters`` with each variable's ``value``, ``unit``, ``lower``, ``upper``,
    ``objective`` with ``name``, ``value``, ``unit``, ``attained_by``,
    ``active_constraints``, ``outputs``, ``history``, ``solves``, ``time_s`` …);
    :attr:`case_text` is the optimal case file (``case_file``,
    ``<case>_optimum.ron``; paths absolute), :attr:`case` that case read, and
    :attr:`result` the optimum's :class:`Result` (variant ``optimum``).
    """

    __slots__ = ("_json", "_doc", "case_file", "case_text", "case", "result")

    def __init__(self, output) -> None:
        from ._case import Case

        json_text, case_file, case_text, case, solved = output
        self._json: str = json_text
        self._doc: Dict[str, Any] = json.loads(json_text)
        self.case_file: str = case_file
        self.case_text: str = case_text
        self.case = Case(case)
        self.result = Result(solved)

    @property
    def converged(self) -> bool:
        """Whether the run met its convergence test (``strand optimize`` exits 0)."""
        return self._doc["converged"]

    @property
    def values(self) -> Dict[str, float]:
        """The optimal value of each variable, in its unit (``parameters[*].unit``)."""
        return {name: p["value"] for name, p in self._doc["parameters"].items()}

    @property
    def objective(self) -> float:
        """The objective at the optimum, in ``objective.unit`` (N for ``peak_force``)."""
        return self._doc["objective"]["value"]

    def to_dict(self) -> Dict[str, Any]:
        """``optimum.json`` as a dict (a new one on every call)."""
        return json.loads(self._json)

    def to_json(self) -> str:
        """``optimum.json`` as compact JSON text."""
        return self._json

    def __repr__(self) -> str:
        values = ", ".join(
            f"{name} = {p['value']:.6g} {p['unit']}" for name, p in self._doc["parameters"].items()
        )
        o = self._doc["objective"]
        return (
            f"<strand.Optimum {values}: {o['name']} {o['value']:.5g} {o['unit']}"
            f"{'' if self.converged else ' (NOT converged)'}>"
        )
