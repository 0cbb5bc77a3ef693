"""Cases and results pickle (for multiprocessing, Dask, Ray): back bit for bit."""

from __future__ import annotations

import multiprocessing
import pickle
from concurrent.futures import ProcessPoolExecutor

import numpy as np

import strand

from test_results import assert_same

COOLER = "cases/cooler_hose.ron"


def test_result_survives_pickling():
    result = strand.Case.load(COOLER).with_changes({"hose2.length": "+20mm"}).solve()
    back = pickle.loads(pickle.dumps(result))
    assert_same(back.to_dict(), result.to_dict())
    assert (back.converged, back.residual_N, back.variant) == (
        result.converged, result.residual_N, "hose2.length=+20mm")
    for name, rod in result.rods.items():
        assert np.array_equal(back.rods[name]["position_m"], rod["position_m"])


def without_times(doc):
    doc = dict(doc)
    doc.pop("timing_s")
    doc["provenance"].pop("created_utc")
    return doc


def test_unpickled_result_warm_starts_exactly_as_the_original():
    case = strand.Case.load(COOLER)
    base = case.solve()
    longer = case.with_changes({"hose2.length": "+30mm"})
    direct = longer.solve(warm_start=base)
    # The state comes back bit for bit and its case is rebuilt from the pickled text.
    via_pickle = pickle.loads(pickle.dumps(longer)).solve(
        warm_start=pickle.loads(pickle.dumps(base)))
    assert direct.warm_start and via_pickle.warm_start
    assert_same(without_times(via_pickle.to_dict()), without_times(direct.to_dict()))


def test_case_survives_pickling_with_its_changes():
    case = strand.Case.load("cases/study_demo.ron").variant("plus50").with_changes(
        {"hose.length": "+5mm"})
    back = pickle.loads(pickle.dumps(case))
    assert back.label == case.label == "plus50, hose.length=+5mm"
    assert_same(without_times(back.solve().to_dict()), without_times(case.solve().to_dict()))


def solve_length(args):
    case, change = args
    return case.with_changes({"hose2.length": change}).solve()


def test_variants_solved_in_worker_processes():
    case = strand.Case.load(COOLER)
    changes = ["+10mm", "+20mm"]
    with ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("fork")) as pool:
        remote = list(pool.map(solve_length, [(case, c) for c in changes]))
    for change, result in zip(changes, remote):
        local = solve_length((case, change))
        assert_same(without_times(result.to_dict()), without_times(local.to_dict()))
