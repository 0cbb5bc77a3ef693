"""`strand.batch` gives `strand batch`'s summary."""

from __future__ import annotations

import numpy as np
import pytest

import strand

from conftest import run_cli

COOLER = "cases/cooler_hose.ron"


def without_times(rows):
    return [{k: v for k, v in row.items() if k != "time_s"} for row in rows]


def test_two_parameter_batch_equals_cli_summary(strand_bin, tmp_path):
    out = tmp_path / "cli"
    run_cli(strand_bin, "batch", COOLER, "--vary", "hose2.length=+0mm..+40mm:10mm",
            "--vary", "tee.mass=1kg,1.5kg", "--jobs", "2", "--out", out)
    expected = strand.parse_summary((out / "summary.csv").read_text())
    rows = strand.batch(
        strand.Case.load(COOLER),
        vary={"hose2.length": "+0mm..+40mm:10mm", "tee.mass": ["1kg", "1.5kg"]},
        jobs=2,
        as_frame=False,
    )
    assert len(rows) == 10
    assert without_times(rows) == without_times(expected)
    assert all(row["status"] == "ok" for row in rows)
    assert isinstance(rows[0]["residual_N"], float) and isinstance(rows[0]["iterations"], int)


def test_batch_rows_are_the_equilibria_of_single_solves():
    case = strand.Case.load(COOLER)
    rows = strand.batch(case, vary={"hose2.length": "+0mm..+30mm:15mm"}, jobs=1, as_frame=False)
    base = case.solve()
    for row in rows:
        change = row["hose2.length [mm]"]
        single = case.with_changes({"hose2.length": change}).solve(warm_start=base)
        peak = np.linalg.norm(single.rods["hose2"]["force_N"], axis=1).max()
        # Warm-started along a different path: the same equilibrium to the tolerance.
        assert row["hose2 peak |f| [N]"] == pytest.approx(peak, rel=1e-8)


def test_batch_into_a_directory_resumes(tmp_path):
    case = strand.Case.load(COOLER)
    vary = {"hose2.length": ["+0mm", "+10mm"]}
    first = strand.batch(case, vary=vary, out=tmp_path / "b", as_frame=False)
    assert (tmp_path / "b" / "summary.csv").exists()
    again = strand.batch(case, vary=vary, out=tmp_path / "b", as_frame=False)
    # Nothing solved again: the same rows, times included.
    assert again == first


def test_batch_of_a_changed_case_varies_the_changed_case(strand_bin, tmp_path):
    changed = strand.Case.load(COOLER).with_changes({"tee.mass": "1.5kg"})
    rows = strand.batch(changed, vary={"hose2.length": "+0mm,+10mm"}, as_frame=False)
    out = tmp_path / "cli"
    run_cli(strand_bin, "batch", COOLER, "--vary", "tee.mass=1.5kg",
            "--vary", "hose2.length=+0mm,+10mm", "--out", out)
    expected = strand.parse_summary((out / "summary.csv").read_text())
    key = "hose2 peak |f| [N]"
    # Same equilibria (warm-start trees differ: one parameter vs two).
    for row, exp in zip(rows, expected):
        assert row[key] == pytest.approx(exp[key], rel=1e-8)


def test_dataframe_when_pandas_is_installed():
    pandas = pytest.importorskip("pandas")
    frame = strand.batch(strand.Case.load(COOLER), vary={"hose2.length": "+0mm,+10mm"})
    assert isinstance(frame, pandas.DataFrame) and list(frame["status"]) == ["ok", "ok"]
