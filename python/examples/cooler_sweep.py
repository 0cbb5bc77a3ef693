"""The cooler-hose length sweep (paper, section 4 and Fig. 7): hose 2 from its
reference length to 99 mm longer, as a batch, and the peak internal force and moment
of every hose against the added length.

    python python/examples/cooler_sweep.py [--out sweep.png]

Run from the repository root. Plots with matplotlib when it is installed (else prints
the table only).
"""

from __future__ import annotations

import argparse

import strand


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", default="cases/cooler_hose.ron")
    parser.add_argument("--out", default="cooler_sweep.png", help="plot file (PNG)")
    args = parser.parse_args()

    case = strand.Case.load(args.case)
    rows = strand.batch(case, vary={"hose2.length": "+0mm..+99mm:1mm"}, as_frame=False)
    added_mm = [float(r["hose2.length [mm]"].removesuffix("mm")) for r in rows]
    hoses = ["hose1", "hose2", "hose3"]
    failed = [r["id"] for r in rows if r["status"] != "ok"]
    print(f"{len(rows)} variants, {len(failed)} failed {failed if failed else ''}")
    print(f"{'added [mm]':>10} " + " ".join(f"{h + ' |f| [N]':>14}" for h in hoses))
    for x, r in list(zip(added_mm, rows))[::10]:
        print(f"{x:>10.0f} " + " ".join(f"{r[h + ' peak |f| [N]']:>14.3f}" for h in hoses))

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no plot (pip install matplotlib)")
        return
    fig, (forces, moments) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    for h in hoses:
        forces.plot(added_mm, [r[h + " peak |f| [N]"] for r in rows], label=h)
        moments.plot(added_mm, [r[h + " peak |m| [N·m]"] for r in rows], label=h)
    forces.set(xlabel="hose 2 added length [mm]", ylabel="peak |f| [N]",
               title="internal force")
    moments.set(xlabel="hose 2 added length [mm]", ylabel="peak |m| [N·m]",
                title="internal moment")
    forces.legend()
    fig.savefig(args.out, dpi=120)
    print(f"written {args.out}")


if __name__ == "__main__":
    main()
