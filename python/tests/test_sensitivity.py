"""`case.sensitivity` gives `strand sensitivity`'s document."""

from __future__ import annotations

import json

import numpy as np

import strand

from conftest import run_cli
from test_results import assert_same

COOLER = "cases/cooler_hose.ron"


def test_sensitivity_equals_cli_and_finite_differences(strand_bin, tmp_path):
    run_cli(strand_bin, "sensitivity", COOLER, "--param", "hose2.length", "--param", "tee.mass",
            "--out", tmp_path)
    expected = json.loads((tmp_path / "sensitivity.json").read_text())
    case = strand.Case.load(COOLER)
    got = case.sensitivity(["hose2.length", "tee.mass"])
    assert_same(got, expected)
    # Against central differences of full solves (±0.5 mm).
    d = {o["name"]: o["d"]["hose2.length"] for o in got["outputs"]}
    base = case.solve()

    def peak(change):
        r = case.with_changes({"hose2.length": change}).solve(warm_start=base)
        return np.linalg.norm(r.rods["hose2"]["force_N"], axis=1).max()

    fd = (peak("+0.5mm") - peak("-0.5mm")) / 1.0  # N per mm
    assert abs(d["hose2.peak_force_N"] - fd) <= 1e-3 * abs(fd)
