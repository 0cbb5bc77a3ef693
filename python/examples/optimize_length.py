"""scipy.optimize on full solves: the added length of cooler hose 2 at which its peak
internal force falls to a target (default 10 N), found by Brent's method, every solve
warm-started from the previous one.

    python python/examples/optimize_length.py [--target-force 10]

Run from the repository root; needs scipy (pip install scipy).
"""

from __future__ import annotations

import argparse

import numpy as np

import strand


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", default="cases/cooler_hose.ron")
    parser.add_argument("--target-force", type=float, default=10.0, help="N")
    args = parser.parse_args()
    try:
        from scipy.optimize import brentq
    except ImportError:
        print("scipy is not installed (pip install scipy)")
        return

    case = strand.Case.load(args.case)
    last = case.solve().check()
    solves = []

    def excess_force_N(added_mm: float) -> float:
        """Peak |f| of hose 2 minus the target, N, with hose 2 `added_mm` longer
        (a signed value is an offset: `+12.5mm`)."""
        nonlocal last
        result = case.with_changes({"hose2.length": f"{added_mm:+}mm"}).solve(warm_start=last)
        last = result.check()
        solves.append((added_mm, result.iterations))
        peak = np.linalg.norm(result.rods["hose2"]["force_N"], axis=1).max()
        return peak - args.target_force

    added = brentq(excess_force_N, 0.0, 100.0, xtol=1e-3)
    print(f"hose 2 needs {added:.3f} mm more for a peak force of {args.target_force} N "
          f"({len(solves)} solves, {sum(i for _, i in solves)} Newton iterations)")


if __name__ == "__main__":
    main()
