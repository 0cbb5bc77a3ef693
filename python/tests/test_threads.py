"""Solves release the GIL: two solves in two threads take clearly less wall time than
one after the other (CI has 2 cores)."""

from __future__ import annotations

import os
import threading
import time

import pytest

import strand

# About 0.5 s per solve here.
SEGMENTS = 2000


def wall(function) -> float:
    started = time.perf_counter()
    function()
    return time.perf_counter() - started


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="needs two cores")
def test_two_solves_in_two_threads_run_concurrently():
    cases = [strand.Case.load("cases/cooler_hose.ron"),
             strand.Case.load("cases/cooler_hose.ron").with_changes({"hose2.length": "+20mm"})]
    results = [None, None]

    def solve(k):
        results[k] = cases[k].solve(segments=SEGMENTS)

    ratios = []
    for attempt in range(3):  # the best of three: the machine may be busy
        one_after_other = wall(lambda: (solve(0), solve(1)))
        threads = [threading.Thread(target=solve, args=(k,)) for k in (0, 1)]
        together = wall(lambda: ([t.start() for t in threads], [t.join() for t in threads]))
        ratios.append(together / one_after_other)
        if ratios[-1] < 0.8:
            break
    assert all(r is not None and r.converged for r in results)
    assert min(ratios) < 0.8, f"two threads / one after the other = {ratios}"
