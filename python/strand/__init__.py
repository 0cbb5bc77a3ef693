"""Strand from Python: static equilibria of cables and hoses as discrete quaternionic
Cosserat rods, with the engine and messages of the ``strand`` command line.

>>> import strand
>>> case = strand.Case.load("cases/cooler_hose.ron")
>>> result = case.solve()
>>> result.converged, result.residual_N < 1e-9
(True, True)
>>> longer = case.with_changes({"hose2.length": "+50mm"}).solve(warm_start=result)
>>> rows = strand.batch(case, vary={"hose2.length": "+0mm..+90mm:10mm"}, as_frame=False)
>>> best = case.optimize(vary={"hose2.length": "150mm..300mm"}, minimize="peak_force",
...                      subject_to=["bend_radius:hose2>=60mm"])
>>> roll = strand.Case.load("cases/cooler_hose_engine_roll.ron")
>>> motion = roll.motion("engine_roll", range="-8deg..8deg:2deg")
>>> tilted = roll.at_pose("engine_roll", "4deg").solve()

Units: case files in their own length unit (``units: (length: "mm")``), results in SI
with the unit in every key (``position_m``, ``force_N``, ``moment_Nm``).
"""

from ._errors import InputError, NotConvergedError, SolveError, StrandError, StrandWarning
from ._result import Result
from ._case import Case
from ._motion import Motion, Pose, parse_motion_csv
from ._optimize import Optimum
from ._batch import batch, parse_summary
from ._strand import __version__

__all__ = [
    "Case",
    "Result",
    "Motion",
    "Pose",
    "Optimum",
    "parse_motion_csv",
    "batch",
    "parse_summary",
    "StrandError",
    "InputError",
    "SolveError",
    "NotConvergedError",
    "StrandWarning",
    "__version__",
]
