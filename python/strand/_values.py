"""Python values as written on the command line (``--vary ITEM=VALUES``)."""

from __future__ import annotations

from typing import Any, Iterable, Mapping, Union

Value = Union[str, int, float]


def value_text(value: Value) -> str:
    """One value: a string as written (``"+30mm"``, ``"1.5kg"``), a number as itself
    (in the case's unit; ``repr`` keeps every digit of a float)."""
    if isinstance(value, bool) or not isinstance(value, (str, int, float)):
        raise TypeError(f"a value is a string such as '+30mm' or a number, not {value!r}")
    return value if isinstance(value, str) else repr(value)


def values_text(values: Union[Value, Iterable[Value]]) -> str:
    """Values: one value, a range string (``"+0mm..+100mm:10mm"``) or a list of values."""
    if isinstance(values, (str, int, float)):
        return value_text(values)
    return ",".join(value_text(v) for v in values)


def item_texts(items: Mapping[str, object], one) -> list:
    """``ITEM=VALUE`` for every entry of ``items``, each value written by ``one``."""
    return [f"{item}={one(v)}" for item, v in items.items()]


def csv_cell(text: str) -> Any:
    """A cell of a CSV Strand writes (``summary.csv``, ``motion.csv``): empty → None,
    ``true``/``false`` → bool, a number → int or float (``inf`` included), else the
    text."""
    if text == "":
        return None
    if text in ("true", "false"):
        return text == "true"
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        return text
