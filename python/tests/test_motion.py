"""`case.motion` gives `strand motion`'s poses, motion.csv and events; `case.at_pose`
gives `strand solve --motion`'s result and, batched, `strand batch --motion`'s
summary; bad motions raise with the CLI's message."""

from __future__ import annotations

import csv
import json
import pickle

import pytest

import strand

from conftest import cli_result, error_message, run_cli, strip_run
from test_batch import without_times
from test_results import assert_same

ROLL = "cases/cooler_hose_engine_roll.ron"
RANGE = "-8deg..8deg:2deg"


@pytest.fixture(scope="module")
def cli_motion(strand_bin, tmp_path_factory):
    out = tmp_path_factory.mktemp("motion") / "roll"
    run_cli(strand_bin, "motion", ROLL, "--motion", "engine_roll", "--range", RANGE,
            "--out", out)
    return out


@pytest.fixture(scope="module")
def motion():
    return strand.Case.load(ROLL).motion("engine_roll", range=RANGE)


def test_poses_equal_the_cli_steps(cli_motion, motion):
    steps = sorted(p.name for p in (cli_motion / "steps").iterdir())
    assert motion.complete and motion.unit == "deg" and motion.motion == "engine_roll"
    assert [p.id for p in motion.poses] == steps
    assert motion.values == [-8.0, -6.0, -4.0, -2.0, 0.0, 2.0, 4.0, 6.0, 8.0]
    for pose in motion.poses:
        expected = json.loads((cli_motion / "steps" / pose.id / "result.json").read_text())
        got = pose.result.to_dict()
        assert_same(strip_run(got), strip_run(expected))
        assert got["variant"] == f"engine_roll={pose.value:g}deg"
    assert [p.result.warm_start for p in motion.poses].count(False) == 1  # the case's pose


def test_motion_csv_and_events_equal_the_cli(cli_motion, motion):
    assert motion.csv == (cli_motion / "motion.csv").read_text()
    rows = motion.rows()
    assert len(rows) == 9 and rows[0]["id"] == "000" and rows[0]["status"] == "ok"
    with open(cli_motion / "events.csv", newline="") as f:
        expected = list(csv.reader(f))[1:]
    got = [
        [e["kind"], e["what"], repr(e["between"][0]), repr(e["between"][1]), repr(e["at"]),
         e["detail"]]
        for e in motion.events
    ]
    assert [[r[0], r[1], float(r[2]), float(r[3]), float(r[4]), r[5]] for r in expected] == [
        [g[0], g[1], float(g[2]), float(g[3]), float(g[4]), g[5]] for g in got
    ]


def test_a_pose_result_pickles_and_warm_starts(motion):
    pose = motion.poses[6]  # 4 deg
    again = pickle.loads(pickle.dumps(pose.result))
    assert again.to_dict() == pose.result.to_dict()
    tilted = strand.Case.load(ROLL).at_pose("engine_roll", "4.5deg")
    warm = tilted.solve(warm_start=again)
    assert warm.converged and warm.warm_start


def test_at_pose_equals_cli_solve_motion(strand_bin, tmp_path):
    expected = cli_result(strand_bin, tmp_path, ROLL, "--motion", "engine_roll=4deg")
    case = strand.Case.load(ROLL).at_pose("engine_roll", "4deg")
    assert case.label == "engine_roll=4deg"
    got = case.solve().to_dict()
    assert_same(strip_run(got), strip_run(expected))
    # A number is in the motion's unit; the pose pickles as written.
    assert strand.Case.load(ROLL).at_pose("engine_roll", 4).label == "engine_roll=4deg"
    assert pickle.loads(pickle.dumps(case)).solve().to_dict()["energy_J"] == got["energy_J"]


def test_batch_of_a_pose_equals_cli_batch_motion(strand_bin, tmp_path):
    out = tmp_path / "cli"
    run_cli(strand_bin, "batch", ROLL, "--vary", "hose2.length=+0mm,+10mm", "--motion",
            "engine_roll=4deg", "--out", out)
    expected = strand.parse_summary((out / "summary.csv").read_text())
    posed = strand.Case.load(ROLL).at_pose("engine_roll", "4deg")
    rows = strand.batch(posed, vary={"hose2.length": "+0mm,+10mm"}, as_frame=False)
    assert without_times(rows) == without_times(expected)
    # A change after the pose: the batch's +10mm variant, solved alone.
    longer = posed.with_changes({"hose2.length": "+10mm"})
    assert longer.label == "engine_roll=4deg, hose2.length=+10mm"
    single = pickle.loads(pickle.dumps(longer)).solve()
    peak = max(sum(c * c for c in f) ** 0.5 for f in single.rods["hose2"]["force_N"])
    assert rows[1]["hose2 peak |f| [N]"] == pytest.approx(peak, rel=1e-8)
    unposed = strand.batch(strand.Case.load(ROLL), vary={"hose2.length": "+0mm"},
                           as_frame=False)
    assert unposed[0]["hose2 peak |f| [N]"] != rows[0]["hose2 peak |f| [N]"]


def test_unknown_motion_raises_the_cli_message(strand_bin, tmp_path):
    code, _, stderr = run_cli(strand_bin, "motion", ROLL, "--motion", "no_such", "--range",
                              RANGE, "--out", tmp_path / "m", check_codes=(2,))
    message = error_message(stderr)
    case = strand.Case.load(ROLL)
    with pytest.raises(strand.InputError) as raised:
        case.motion("no_such", range=RANGE)
    assert str(raised.value) == message and "engine_roll" in message
    assert raised.value.exit_code == code == 2
    code, _, stderr = run_cli(strand_bin, "solve", ROLL, "--motion", "no_such=4deg",
                              "--out", tmp_path / "s", check_codes=(2,))
    with pytest.raises(strand.InputError) as posed:
        case.at_pose("no_such", "4deg")
    assert str(posed.value) == error_message(stderr)


def test_bad_range_and_predictor(strand_bin, tmp_path):
    _, _, stderr = run_cli(strand_bin, "motion", ROLL, "--motion", "engine_roll", "--range",
                           "-8mm..8mm:2mm", "--out", tmp_path / "m", check_codes=(2,))
    case = strand.Case.load(ROLL)
    with pytest.raises(strand.InputError) as raised:
        case.motion("engine_roll", range="-8mm..8mm:2mm")
    assert str(raised.value) == error_message(stderr) and "--range" in str(raised.value)
    with pytest.raises(strand.InputError, match="tangent, secant or last"):
        case.motion("engine_roll", range=RANGE, predictor="newton")
