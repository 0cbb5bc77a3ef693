"""`case.optimize` gives `strand optimize`'s optimum.json, optimal case and optimum
result; bad options raise with the CLI's message."""

from __future__ import annotations

import json
import pickle

import pytest

import strand

from conftest import error_message, run_cli, strip_run
from test_results import assert_same

COOLER = "cases/cooler_hose.ron"
VARY = {"hose2.length": "150mm..300mm"}
BEND = "bend_radius:hose2>=60mm"


def without_time(doc):
    return {k: v for k, v in doc.items() if k != "time_s"}


def test_optimum_equals_cli_optimum_json(strand_bin, tmp_path):
    out = tmp_path / "opt"
    run_cli(strand_bin, "optimize", COOLER, "--vary", "hose2.length=150mm..300mm",
            "--minimize", "peak_force", "--subject-to", BEND, "--out", out)
    expected = json.loads((out / "optimum.json").read_text())
    optimum = strand.Case.load(COOLER).optimize(vary=VARY, minimize="peak_force",
                                                subject_to=[BEND])
    got = optimum.to_dict()
    assert_same(without_time(got), without_time(expected))
    assert optimum.converged and got["converged"]
    # The README's worked example: 280.3 mm, hose 2 and hose 3 at the same peak.
    assert optimum.values["hose2.length"] == pytest.approx(280.3, abs=0.05)
    assert optimum.objective == pytest.approx(6.601, abs=5e-4)
    assert optimum.case_file == "cooler_hose_optimum.ron"
    assert optimum.case_text == (out / optimum.case_file).read_text()
    result = json.loads((out / "result.json").read_text())
    assert_same(strip_run(optimum.result.to_dict()), strip_run(result))
    # The optimal case solves to the optimum.
    again = optimum.case.solve()
    assert again.energy_J == pytest.approx(optimum.result.energy_J, rel=1e-9)
    assert pickle.loads(pickle.dumps(optimum.result)).to_dict() == optimum.result.to_dict()


def test_bad_objective_raises_the_cli_message(strand_bin, tmp_path):
    code, _, stderr = run_cli(strand_bin, "optimize", COOLER, "--vary",
                              "hose2.length=150mm..300mm", "--minimize", "peak_force:",
                              "--out", tmp_path / "o", check_codes=(2,))
    with pytest.raises(strand.InputError) as raised:
        strand.Case.load(COOLER).optimize(vary=VARY, minimize="peak_force:")
    assert str(raised.value) == error_message(stderr) and "--minimize" in str(raised.value)
    assert raised.value.exit_code == code == 2


def test_bad_bounds_raise_the_cli_message(strand_bin, tmp_path):
    _, _, stderr = run_cli(strand_bin, "optimize", COOLER, "--vary", "hose2.lenght=1mm..2mm",
                           "--out", tmp_path / "o", check_codes=(2,))
    with pytest.raises(strand.InputError) as raised:
        strand.Case.load(COOLER).optimize(vary={"hose2.lenght": "1mm..2mm"})
    assert str(raised.value) == error_message(stderr) and "hose2.lenght" in str(raised.value)
