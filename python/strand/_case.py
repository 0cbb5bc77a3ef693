"""A case: :class:`Case`."""

from __future__ import annotations

import json
import os
import warnings
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

from . import _strand
from ._errors import StrandWarning
from ._motion import Motion
from ._optimize import Optimum
from ._result import Result
from ._values import Value, item_texts, value_text


class Case:
    """A Strand case (one RON file: units, sections, rods, junctions, clips,
    connectors, environment meshes, gravity, solver settings, variants), possibly with
    a named variant and changes applied. Cases are immutable: :meth:`variant` and
    :meth:`with_changes` return new ones. Lengths in case files are in the file's unit
    (``units: (length: "mm")``); results are SI.
    """

    __slots__ = ("_case",)

    def __init__(self, _case: "_strand._Case") -> None:
        self._case = _case

    @classmethod
    def load(cls, path: Union[str, "os.PathLike[str]"]) -> "Case":
        """Reads and checks the case file ``path`` (mesh paths are relative to its
        folder). Raises :class:`strand.InputError` with the command line's message."""
        return cls(_strand._Case.load(os.fspath(path)))

    @classmethod
    def from_str(
        cls,
        text: str,
        base_dir: Union[str, "os.PathLike[str]", None] = None,
        name: Optional[str] = None,
    ) -> "Case":
        """Parses case text (RON). Mesh paths are relative to ``base_dir`` (default:
        the current directory); messages name the text ``<base_dir>/<string>``;
        ``name`` (default ``"case"``) is the case name in results."""
        base = None if base_dir is None else os.fspath(base_dir)
        return cls(_strand._Case.from_str(text, base, name))

    @property
    def name(self) -> str:
        """The case name (the file stem)."""
        return self._case.name

    @property
    def origin(self) -> str:
        """The case file as named (every message names it)."""
        return self._case.origin

    @property
    def label(self) -> Optional[str]:
        """The named variant and changes applied (``result.json``'s ``variant``), or
        ``None`` for the case as read."""
        return self._case.label

    @property
    def variant_names(self) -> List[str]:
        """The case's named variants, in file order."""
        return self._case.variant_names

    def variant(self, name: str) -> "Case":
        """The case with its named variant ``name`` applied (``strand solve
        --variant``)."""
        return Case(self._case.variant(name))

    def with_changes(self, changes: Mapping[str, Value]) -> "Case":
        """The case with ``changes`` applied, in the grammar of ``strand batch
        --vary``: ``{"hose2.length": "+30mm"}`` adds 30 mm, ``{"tee.mass": "1.5kg"}``
        sets a value, ``{"oil_cooler.position.z": "-5mm"}`` moves one component; a
        plain number sets a value in the case's unit. Items as in ``cases/README.md``
        (Variants) with the short forms of ``--vary``."""
        return Case(self._case.with_changes(item_texts(changes, value_text)))

    def check(self, segments: Optional[int] = None) -> None:
        """Validates the case as ``strand check`` does: it builds, and no hose starts
        inside a part or another hose. Raises :class:`strand.InputError`."""
        self._case.check(segments)

    def solve(self, warm_start: Optional[Result] = None, segments: Optional[int] = None) -> Result:
        """Solves the case (the GIL is released meanwhile, so threads run solves in
        parallel). ``warm_start``: a converged result of this case or of another
        version of it (another length, …), resampled onto this one's rods as ``strand
        solve --variant`` does; a result that did not converge gives a cold start and
        a :class:`strand.StrandWarning`. ``segments`` overrides every rod's number of
        segments (``--segments``). A solve that does not converge returns a result
        with ``converged`` False (see :meth:`Result.check`); errors raise
        :class:`strand.InputError` or :class:`strand.SolveError`."""
        solved, warning = self._case.solve(
            None if warm_start is None else warm_start._solved, segments
        )
        if warning is not None:
            warnings.warn(warning, StrandWarning, stacklevel=2)
        return Result(solved)

    def sensitivity(self, params: Sequence[str]) -> Dict[str, Any]:
        """``strand sensitivity``'s document (``sensitivity.json``): the derivative of
        every output (peak forces N, moments N·m, reactions, clearances m, …) of the
        equilibrium with respect to each parameter in ``params`` (``"hose2.length"``,
        ``"tee.mass"``, ``"gravity.z"``), per unit of the parameter (the case's length
        unit, kg, N, m/s²), by the implicit function theorem. The case is solved cold
        with its own segments; raises :class:`strand.NotConvergedError` if it does not
        converge."""
        if isinstance(params, str):
            params = [params]
        return json.loads(self._case.sensitivity(list(params)))

    def at_pose(self, motion: str, value: Value) -> "Case":
        """The case with the parts riding on motion ``motion`` moved to its parameter
        ``value`` (``"4deg"``, or a number in the motion's unit: deg or the case's
        length unit), as ``strand solve --motion motion=value`` solves it and
        ``strand batch --motion`` varies it: every later solve, change, batch,
        sensitivity and optimisation of the returned case is at that pose. Its label
        is ``engine_roll=4deg``. Raises :class:`strand.InputError` with the command
        line's message (an unknown motion lists the defined ones; a value outside the
        keyframes or out of a held end's reach names the pose)."""
        return Case(self._case.at_pose(f"{motion}={value_text(value)}"))

    def motion(
        self,
        motion: str,
        range: str,
        predictor: str = "secant",
        segments: Optional[int] = None,
    ) -> Motion:
        """Follows the case over ``range`` (``"-8deg..8deg:2deg"``: FROM..TO:STEP in
        the motion's unit, the grammar of ``strand motion --range``) of its motion
        ``motion`` from its own pose in both directions, warm-started pose to pose, as
        ``strand motion`` does (GIL released). ``predictor``: where each step starts,
        ``"secant"`` (of the last two poses, the default), ``"tangent"`` (the exact
        path tangent, second order) or ``"last"`` (the last pose). ``segments``
        overrides every rod's number of segments. Returns a :class:`strand.Motion`:
        the poses' results (each the ``result.json`` of ``steps/<id>/``), the events,
        ``motion.csv``. A direction that cannot be followed ends there (``failed``;
        ``complete`` False) rather than raising; a bad motion name or range raises
        :class:`strand.InputError` with the command line's message."""
        return Motion(self._case.motion(motion, range, segments, predictor))

    def optimize(
        self,
        vary: Mapping[str, str],
        minimize: str = "peak_force",
        subject_to: Sequence[str] = (),
    ) -> Optimum:
        """Finds the best design within bounds with exact gradients, as ``strand
        optimize`` does (GIL released). ``vary``: design variables and their bounds in
        the grammar of ``--vary NAME=LO..HI``, ``{"hose2.length": "150mm..300mm"}``
        (values; signed bounds such as ``"-60mm..+20mm"`` are offsets from the case).
        ``minimize``: ``"peak_force"`` (the largest peak |f| over all rods, N),
        ``"peak_force:<rod>"``, ``"max_reaction"`` (N), ``"energy"`` (J) or an output
        name of ``sensitivity.json``. ``subject_to``: constraints such as
        ``"bend_radius:hose2>=60mm"``, ``"clearance>=10mm"``, ``"bend_radius>=min"``.
        Returns a :class:`strand.Optimum` (``to_dict()`` is ``optimum.json``; a run
        that did not converge has ``converged`` False). Bad options raise
        :class:`strand.InputError` with the command line's message (naming
        ``--vary``, ``--minimize`` or ``--subject-to``); a starting design without an
        equilibrium :class:`strand.NotConvergedError`."""
        if isinstance(subject_to, str):
            subject_to = [subject_to]
        texts = item_texts(vary, value_text)
        return Optimum(self._case.optimize(texts, minimize, list(subject_to)))

    def __reduce__(self):
        return (_from_state, (self._case.state(),))

    def __repr__(self) -> str:
        label = f" ({self.label})" if self.label else ""
        return f"<strand.Case {self.name}{label} from {self.origin}>"


def _from_state(state) -> Case:
    """A pickled :class:`Case` back: its text parsed and its changes applied again."""
    return Case(_strand._Case.from_state(state))
