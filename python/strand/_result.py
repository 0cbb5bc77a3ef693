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

    # The convergence report.
    @property
    def converged(self) -> bool:
        """Whether the solve converged (``residual_N`` at most ``tolerance_N``)."""
        return self._report[0]

    @property
    def residual_N(self) -> float:
        """The final residual (KKT, in force units), N."""
        return self._report[3]

    @property
    def tolerance_N(self) -> float:
        """The convergence tolerance, N."""
        return self._report[4]

    @property
    def stable(self) -> bool:
        """Whether the equilibrium is stable (reduced Hessian positive definite)."""
        return self._report[1]

    @property
    def iterations(self) -> int:
        """Newton iterations, all levels and fallbacks included."""
        return self._report[2]

    @property
    def termination(self) -> str:
        """Why the solve stopped (``converged``, ``max_iterations``, ``stagnated``, …)."""
        return self._report[6]

    @property
    def energy_J(self) -> float:
        """Total potential energy at the equilibrium, J."""
        return self._report[5]

    @property
    def warm_start(self) -> bool:
        """Whether the solve started from another solution."""
        return self._report[7]

    @property
    def variant(self) -> Optional[str]:
        """The variant and changes solved (``None``: the case as read)."""
        return self._report[8]

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
