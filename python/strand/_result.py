"""A solved case: :class:`Result`."""

from __future__ import annotations

import json
from typing import Any, Dict, List, Optional

import numpy as np

from . import _strand
from ._errors import NotConvergedError


def _array_or_value(value: Any) -> Any:
    """A list of numbers (or of lists of numbers) as a float64 numpy array (JSON null,
    a non-finite number, as NaN); anything else as it is."""
    if isinstance(value, list) and value:
        first = value[0]
        if isinstance(first, list) or (
            isinstance(first, (int, float)) and not isinstance(first, bool)
        ) or first is None:
            try:
                return np.array(value, dtype=np.float64)
            except (TypeError, ValueError):
                return value
    return value


def _with_arrays(entry: Dict[str, Any]) -> Dict[str, Any]:
    """``entry`` with every numeric list as a float64 numpy array."""
    return {k: _array_or_value(v) for k, v in entry.items()}


def _reported(index: int, doc: str) -> property:
    """A read-only attribute: entry ``index`` of the solve's convergence report."""
    return property(lambda self: self._report[index], doc=doc)


class Result:
    """The equilibrium of a case: convergence report, per rod sectional quantities
    (numpy arrays), reactions, contacts, clearances and findings, exactly as the
    ``strand solve`` command writes them to ``result.json``.

    Units are SI and in every key: ``position_m`` (m), ``force_N`` (N), ``moment_Nm``
    (N·m), ``curvature_1pm`` (1/m), ``s_m`` (reference arc length, m).
    """

    __slots__ = ("_solved", "_doc", "_report")

    def __init__(self, solved: "_strand._Solved") -> None:
        self._solved = solved
        self._doc: Optional[Dict[str, Any]] = None
        self._report = solved.report()

    @property
    def _d(self) -> Dict[str, Any]:
        if self._doc is None:
            self._doc = json.loads(self._solved.json())
        return self._doc

    # The convergence report (typed values kept by the solve; no JSON needed).
    converged = _reported(0, "Whether the solve converged (``residual_N`` at most ``tolerance_N``).")
    stable = _reported(1, "Whether the equilibrium is stable (reduced Hessian positive definite).")
    iterations = _reported(2, "Newton iterations, all levels and fallbacks included.")
    residual_N = _reported(3, "The final residual (KKT, in force units), N.")
    tolerance_N = _reported(4, "The convergence tolerance, N.")
    energy_J = _reported(5, "Total potential energy at the equilibrium, J.")
    termination = _reported(
        6, "Why the solve stopped (``converged``, ``max_iterations``, ``stagnated``, …)."
    )
    warm_start = _reported(7, "Whether the solve started from another solution.")
    variant = _reported(8, "The variant and changes solved (``None``: the case as read).")

    @property
    def timing_s(self) -> Dict[str, float]:
        """Build, solve and post-processing times, s (``read`` is 0: read before)."""
        return dict(self._d["timing_s"])

    # Per rod and per support.
    @property
    def rods(self) -> Dict[str, Dict[str, Any]]:
        """Per rod (by name): per vertex ``s_m``, ``position_m`` (N+1, 3),
        ``force_N``, ``moment_Nm`` (N+1, 3), ``tangential_force_N``,
        ``shear_force_N``, ``bending_moment_Nm``, ``torsion_Nm``, ``curvature_1pm``,
        ``total_moment_Nm``, ``hamiltonian_N``; per edge ``edge_force_N`` (N, 3) and
        ``section_frames_wxyz`` (N, 4); ``length_m``, ``segments``. New arrays on
        every access."""
        return {rod["name"]: _with_arrays(rod) for rod in self._d["rods"]}

    @property
    def reactions(self) -> List[Dict[str, Any]]:
        """Support reactions on the rods: ``name``, ``kind``, ``rod``, ``end``,
        ``position_m``, ``force_N``, ``moment_Nm`` (about the end vertex, N·m)."""
        return [_with_arrays(r) for r in self._d["reactions"]]

    @property
    def contacts(self) -> List[Dict[str, Any]]:
        """Active contacts: ``rod``, ``s_m``, ``point_m``, ``normal``, ``force_N``,
        ``with``."""
        return [_with_arrays(c) for c in self._d.get("contacts", [])]

    @property
    def clearance(self) -> List[Dict[str, Any]]:
        """Smallest distances per rod and obstacle: ``rod``, ``with``, ``distance_m``,
        ``s_m``."""
        return [dict(c) for c in self._d.get("clearance", [])]

    @property
    def findings(self) -> List[Dict[str, Any]]:
        """Violations of the case's limits (bend radius, clearance, connector loads)."""
        return [dict(f) for f in self._d.get("findings", [])]

    @property
    def bodies(self) -> List[Dict[str, Any]]:
        """Junction poses: ``position_m``, ``orientation_quaternion_wxyz``, …"""
        return [_with_arrays(b) for b in self._d.get("bodies", [])]

    def to_dict(self) -> Dict[str, Any]:
        """``result.json`` as a dict (a new one on every call): the same document,
        made by the same code, with the same numbers as ``strand solve`` writes."""
        return json.loads(self._solved.json())

    def to_json(self) -> str:
        """``result.json`` as compact JSON text."""
        return self._solved.json()

    def check(self) -> "Result":
        """This result, or :class:`NotConvergedError` if the solve did not converge."""
        message = self._solved.not_converged()
        if message is not None:
            raise NotConvergedError(message)
        return self

    def __reduce__(self):
        return (_from_state, (self._solved.state(),))

    def __repr__(self) -> str:
        variant = f" ({self.variant})" if self.variant else ""
        return (
            f"<strand.Result{variant}: {'converged' if self.converged else 'NOT converged'}, "
            f"residual {self.residual_N:.3g} N, {self.iterations} iterations, "
            f"{'stable' if self.stable else 'unstable'}>"
        )


def _from_state(state) -> Result:
    """A pickled :class:`Result` back (its case is read again from the pickled text)."""
    return Result(_strand._Solved.from_state(state))
