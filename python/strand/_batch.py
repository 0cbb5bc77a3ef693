"""``strand batch`` from Python: :func:`batch`."""

from __future__ import annotations

import csv
import io
import os
import tempfile
from typing import Any, Dict, Iterable, List, Mapping, Optional, Union

from . import _strand
from ._case import Case
from ._values import Value, csv_cell as _cell, item_texts, values_text

#: Columns kept as text (the parameter columns, between ``id`` and ``status``, too).
_TEXT_COLUMNS = {"id", "status", "stage", "reason"}


def parse_summary(text: str) -> List[Dict[str, Any]]:
    """The rows of a batch's ``summary.csv`` as dicts (column name → value), with
    numbers as int/float, ``true``/``false`` as bool, empty cells as None; ``id``,
    ``status``, ``stage``, ``reason`` and the parameter columns (the values as
    written, e.g. ``+30mm``) stay text."""
    reader = csv.reader(io.StringIO(text))
    header = next(reader)
    status = header.index("status")
    text_columns = _TEXT_COLUMNS | set(header[1:status])
    return [
        {
            name: (cell if name in text_columns else _cell(cell)) if cell != "" else None
            for name, cell in zip(header, row)
        }
        for row in reader
    ]


def batch(
    case: Case,
    vary: Mapping[str, Union[Value, Iterable[Value]]],
    jobs: Optional[int] = None,
    segments: Optional[int] = None,
    out: Union[str, "os.PathLike[str]", None] = None,
    keep: str = "summary",
    as_frame: Optional[bool] = None,
):
    """Runs ``strand batch``: every combination of the varied parameters, solved in
    parallel (``jobs`` threads, default the available cores; GIL released) and
    warm-started along each parameter, and returns its summary — one row per variant
    in grid order with ``id``, the parameter values as written, ``status``,
    ``warm_start``, ``residual_N``, ``iterations``, ``time_s``, per rod peak ``|f|``
    (N) and ``|m|`` (N·m), per attachment the largest reaction (N), the minimum
    clearance (m) and bend radii (m).

    ``vary`` maps items to values in the grammar of ``--vary``: a range
    ``{"hose2.length": "+0mm..+100mm:10mm"}``, a list ``{"tee.mass": ["1kg", "2kg"]}``
    or one value. ``out``: the batch directory (kept, and resumed when run again);
    default a temporary one, removed afterwards. ``keep``: files kept per variant
    (``"summary"``, ``"results"``, ``"all"``). Returns a pandas DataFrame when pandas
    is installed (``as_frame=None``) or ``as_frame`` is True, else a list of dicts.
    """
    texts = item_texts(vary, values_text)
    if out is None:
        with tempfile.TemporaryDirectory(prefix="strand-batch-") as folder:
            summary, _ = _strand._batch(
                case._case, texts, os.path.join(folder, "batch"), jobs, segments, keep
            )
    else:
        summary, _ = _strand._batch(case._case, texts, os.fspath(out), jobs, segments, keep)
    rows = parse_summary(summary)
    if as_frame is False:
        return rows
    try:
        import pandas
    except ImportError:
        if as_frame:
            raise
        return rows
    return pandas.DataFrame(rows)
