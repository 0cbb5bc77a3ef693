"""Overhead of the Python package over the Rust engine (a benchmark, not a test).

    python python/benchmarks/bench.py [--repeats 30] [--strand target/release/strand]

Run from the repository root after `pip install ./python` and `cargo build --release`.

1. `case.solve()` of the cooler hoses: the wall time of the Python call against the
   time the Rust code spends inside it (`result.timing_s["total"]`: build, solve,
   result document, measured in Rust): the difference is the binding's overhead
   (argument conversion, GIL release and re-acquisition, the result object).
2. A 100-variant batch (`hose2.length=+0mm..+99mm:1mm`, 2 threads) from Python
   against `strand batch` (both `--keep summary`, and the CLI's default `--keep all`).
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import tempfile
import time

import strand


def solve_overhead(case: strand.Case, repeats: int) -> None:
    walls, inside, kept = [], [], []
    case.solve()  # warm-up
    for _ in range(repeats):
        started = time.perf_counter()
        result = case.solve()
        walls.append(time.perf_counter() - started)
        inside.append(result.timing_s["total"])
        # Kept alive: freeing the previous result (its model and document) is not
        # part of a solve.
        kept.append(result)
    overheads = [w - i for w, i in zip(walls, inside)]
    med_wall, med_in, med_over = (statistics.median(x) for x in (walls, inside, overheads))
    print(f"case.solve() of {case.origin}, median of {repeats}:")
    print(f"  Python wall {med_wall * 1e3:.3f} ms, Rust inside {med_in * 1e3:.3f} ms, "
          f"overhead {med_over * 1e6:.1f} µs ({100 * med_over / med_in:.2f} %)")
    result = case.solve()
    print(f"  first result.to_dict() {1e3 * timed(result.to_dict):.3f} ms (writes the JSON), "
          f"then {1e3 * timed(result.to_dict):.3f} ms; result.rods "
          f"{1e3 * timed(lambda: result.rods):.3f} ms")
    del kept
    started = time.perf_counter()
    for _ in range(repeats):
        case.solve()
    print(f"  solves freeing the previous result: {1e3 * (time.perf_counter() - started) / repeats:.3f} ms each")


def timed(function) -> float:
    started = time.perf_counter()
    function()
    return time.perf_counter() - started


def batch_times(case: strand.Case, binary: str, repeats: int) -> None:
    vary = "hose2.length=+0mm..+99mm:1mm"
    rows = []
    for label, run in [
        ("Python strand.batch (keep summary)",
         lambda: strand.batch(case, vary={"hose2.length": "+0mm..+99mm:1mm"}, jobs=2,
                              as_frame=False)),
        ("strand batch --keep summary", lambda: cli(binary, case.origin, vary, "summary")),
        ("strand batch (--keep all)", lambda: cli(binary, case.origin, vary, "all")),
    ]:
        times = [timed(run) for _ in range(repeats)]
        rows.append((label, statistics.median(times), min(times)))
    print(f"100-variant batch ({vary}, 2 threads), median / best of {repeats}:")
    for label, median, best in rows:
        print(f"  {label:<38} {median:.3f} s / {best:.3f} s")


def cli(binary: str, case: str, vary: str, keep: str) -> None:
    with tempfile.TemporaryDirectory() as folder:
        subprocess.run([binary, "batch", case, "--vary", vary, "--jobs", "2", "--keep", keep,
                        "--out", f"{folder}/b"], check=True, capture_output=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", default="cases/cooler_hose.ron")
    parser.add_argument("--strand", default="target/release/strand")
    parser.add_argument("--repeats", type=int, default=30)
    args = parser.parse_args()
    case = strand.Case.load(args.case)
    solve_overhead(case, args.repeats)
    batch_times(case, args.strand, max(3, args.repeats // 10))


if __name__ == "__main__":
    main()
