"""Type hints of the Python package ``strand`` (units in every name: m, N, N·m, J, s)."""

import os
from typing import Any, Dict, Iterable, List, Literal, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

Value = Union[str, int, float]
PathLike = Union[str, "os.PathLike[str]"]
Array = npt.NDArray[np.float64]

class StrandError(Exception):
    """Base class of Strand's errors; ``exit_code`` as the command line (1)."""

    exit_code: int

class InputError(StrandError, ValueError):
    """Invalid input (exit 2): message names the file, line:column or item, and a hint."""

class SolveError(StrandError, RuntimeError):
    """The solver could not start (exit 1)."""

class NotConvergedError(SolveError):
    """A converged solve was required (exit 3)."""

class StrandWarning(UserWarning):
    """A warning of the command line (a warm start that fell back to a cold one)."""

class Result:
    """One equilibrium, as ``strand solve``'s ``result.json`` (SI units)."""

    @property
    def converged(self) -> bool: ...
    @property
    def residual_N(self) -> float:
        """Final residual, N."""
    @property
    def tolerance_N(self) -> float:
        """Convergence tolerance, N."""
    @property
    def stable(self) -> bool: ...
    @property
    def iterations(self) -> int: ...
    @property
    def termination(self) -> str: ...
    @property
    def energy_J(self) -> float:
        """Total potential energy, J."""
    @property
    def warm_start(self) -> bool: ...
    @property
    def variant(self) -> Optional[str]: ...
    @property
    def timing_s(self) -> Dict[str, float]:
        """build, solve, post, total in s."""
    @property
    def rods(self) -> Dict[str, Dict[str, Any]]:
        """Per rod: ``s_m`` (N+1,), ``position_m``/``force_N``/``moment_Nm`` (N+1, 3) …
        as float64 arrays."""
    @property
    def reactions(self) -> List[Dict[str, Any]]:
        """``position_m``, ``force_N`` (N), ``moment_Nm`` (N·m) as arrays of 3."""
    @property
    def contacts(self) -> List[Dict[str, Any]]: ...
    @property
    def clearance(self) -> List[Dict[str, Any]]: ...
    @property
    def findings(self) -> List[Dict[str, Any]]: ...
    @property
    def bodies(self) -> List[Dict[str, Any]]: ...
    def to_dict(self) -> Dict[str, Any]:
        """``result.json`` as a dict."""
    def to_json(self) -> str: ...
    def check(self) -> "Result":
        """Self, or NotConvergedError."""

class Pose:
    """One solved pose of a followed motion."""

    id: str
    """Its folder under ``steps/`` in ``strand motion``'s output (``000``, …)."""
    value: float
    """The motion's parameter, in the motion's unit (deg, or the case's length unit)."""
    solves: int
    iterations: int
    result: Result
    """``steps/<id>/result.json`` (SI units)."""

class Motion:
    """A case followed over a range of one of its motions (``strand motion``)."""

    motion: str
    unit: str
    """The motion parameter's unit (``deg``, ``mm``)."""
    poses: List[Pose]
    """Solved poses in order of the value."""
    events: List[Dict[str, Any]]
    """``events.csv``: ``kind``, ``what``, ``between`` [from, to], ``at`` (motion's unit), ``detail``."""
    failed: List[Dict[str, Any]]
    """Directions that ended early: ``value``, ``reached`` (motion's unit), ``reason``."""
    complete: bool
    following_s: float
    """Wall time of the path following, s."""
    csv: str
    """``motion.csv`` (lengths in the case's unit)."""
    @property
    def values(self) -> List[float]: ...
    @property
    def results(self) -> List[Result]: ...
    def rows(self) -> List[Dict[str, Any]]:
        """``motion.csv``'s rows as dicts."""

class Optimum:
    """The best design of ``strand optimize``."""

    case_file: str
    """``<case>_optimum.ron``."""
    case_text: str
    """The optimal case file's text (paths absolute)."""
    case: "Case"
    result: Result
    """The optimum's ``result.json`` (variant ``optimum``)."""
    @property
    def converged(self) -> bool: ...
    @property
    def values(self) -> Dict[str, float]:
        """Optimal value per variable, in its unit (mm, kg, N, m/s²)."""
    @property
    def objective(self) -> float:
        """The objective at the optimum (N, N·m, J, m as named)."""
    def to_dict(self) -> Dict[str, Any]:
        """``optimum.json`` as a dict."""
    def to_json(self) -> str: ...

class Case:
    """A case file, possibly with a named variant and changes applied (immutable)."""

    @classmethod
    def load(cls, path: PathLike) -> "Case": ...
    @classmethod
    def from_str(cls, text: str, base_dir: Optional[PathLike] = None, name: Optional[str] = None) -> "Case": ...
    @property
    def name(self) -> str: ...
    @property
    def origin(self) -> str: ...
    @property
    def label(self) -> Optional[str]: ...
    @property
    def variant_names(self) -> List[str]: ...
    def variant(self, name: str) -> "Case": ...
    def with_changes(self, changes: Mapping[str, Value]) -> "Case":
        """``{"hose2.length": "+30mm"}``: the grammar of ``strand batch --vary``."""
    def check(self, segments: Optional[int] = None) -> None: ...
    def solve(self, warm_start: Optional[Result] = None, segments: Optional[int] = None) -> Result: ...
    def sensitivity(self, params: Sequence[str]) -> Dict[str, Any]:
        """``sensitivity.json``: derivatives per unit of each parameter."""
    def at_pose(self, motion: str, value: Value) -> "Case":
        """The case at a pose of a motion (``strand solve --motion engine_roll=4deg``);
        ``value`` as ``"4deg"`` or a number in the motion's unit."""
    def motion(
        self,
        motion: str,
        range: str,
        predictor: Literal["secant", "tangent", "last"] = ...,
        segments: Optional[int] = ...,
    ) -> Motion:
        """``strand motion --motion NAME --range FROM..TO:STEP`` (motion's unit)."""
    def optimize(
        self,
        vary: Mapping[str, str],
        minimize: str = ...,
        subject_to: Sequence[str] = ...,
    ) -> Optimum:
        """``strand optimize``: ``vary={"hose2.length": "150mm..300mm"}``,
        ``minimize="peak_force"`` (N), ``subject_to=["bend_radius:hose2>=60mm"]``."""

def batch(
    case: Case,
    vary: Mapping[str, Union[Value, Iterable[Value]]],
    jobs: Optional[int] = ...,
    segments: Optional[int] = ...,
    out: Optional[PathLike] = ...,
    keep: Literal["summary", "results", "all"] = ...,
    as_frame: Optional[bool] = ...,
) -> Any:
    """The summary of ``strand batch``: a pandas DataFrame if pandas is installed (and
    ``as_frame`` is not False), else a list of dicts (one per variant)."""

def parse_summary(text: str) -> List[Dict[str, Any]]: ...
def parse_motion_csv(text: str) -> List[Dict[str, Any]]: ...
