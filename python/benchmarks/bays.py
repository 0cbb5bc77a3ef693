"""Harness sizes: N copies of the cooler hoses, each in its own engine bay (a benchmark
case generator, not a test; needs only the Python standard library).

    python python/benchmarks/bays.py 64 /tmp/bays64.ron
    strand solve /tmp/bays64.ron --out /tmp/bays64

Run from the repository root. Copy k of `cases/cooler_hose_contact.ron` (three hoses,
a T-junction, three connectors, the five engine-bay meshes) is moved by
((k mod 8) m, (k div 8) m, 0) on an 8-wide grid, 1 m apart: the bays do not touch
each other, so the solved state of every bay is the single case's (each bay's hose 3
rests on its bracket: 2 contacts per bay), and what grows is only the size. Names get
the prefix `b<k>_`. The mesh paths are absolute, so the case can be written anywhere.
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

CASE = Path("cases/cooler_hose_contact.ron")
PITCH_MM = 1000.0
ROW = 8


def section(text: str, name: str) -> str:
    """The inside of the bracketed section `name: { … }` or `name: [ … ]`."""
    start = text.index(name + ":")
    opening = min(i for i in (text.find("{", start), text.find("[", start)) if i >= 0)
    depth = 0
    for k in range(opening, len(text)):
        if text[k] in "{[(":
            depth += 1
        elif text[k] in "}])":
            depth -= 1
            if depth == 0:
                return text[opening + 1 : k].rstrip().rstrip(",")
    raise ValueError(f"section {name} not closed")


def shift_positions(text: str, dx: float, dy: float) -> str:
    """Every `position: (x, y, …` moved by (dx, dy) mm."""
    return re.sub(
        r"position: \(\s*(-?[\d.]+),\s*(-?[\d.]+),",
        lambda m: f"position: ({float(m.group(1)) + dx:g}, {float(m.group(2)) + dy:g},",
        text,
    )


def bays(count: int) -> str:
    source = re.sub(r"(?m)^\s*//.*\n", "", CASE.read_text())
    connectors = section(source, "connectors")
    junction = section(source, "junctions")
    rods = section(source, "rods")
    environment = section(source, "environment")
    parts: dict[str, list[str]] = {"c": [], "j": [], "r": [], "e": []}
    for k in range(count):
        dx, dy, tag = (k % ROW) * PITCH_MM, (k // ROW) * PITCH_MM, f"b{k}_"
        c = shift_positions(connectors, dx, dy)
        for name in ["radiator_outlet", "oil_cooler", "engine_stub"]:
            c = c.replace(f'"{name}"', f'"{tag}{name}"')
        parts["c"].append(c)
        # The T's own position (its initial guess) moves; its ports are in its frame.
        j = junction.replace('"tee": (', f'"{tag}tee": (')
        j = re.sub(r"position: \(0, 0, 0\),\s*//[^\n]*", f"position: ({dx:g}, {dy:g}, 0),", j, count=1)
        parts["j"].append(j)
        r = rods
        for name in ["hose1", "hose2", "hose3"]:
            r = r.replace(f'name: "{name}"', f'name: "{tag}{name}"')
        r = r.replace('Connector("', f'Connector("{tag}').replace('Port("tee"', f'Port("{tag}tee"')
        parts["r"].append(r)
        e = environment.replace('name: "', f'name: "{tag}')
        e = e.replace("position: (0, 0, 0)", f"position: ({dx:g}, {dy:g}, 0)")
        parts["e"].append(e)
    head = source[: source.index("connectors:")]
    assets = str(Path("assets").resolve()) + "/"
    text = (
        head
        + "connectors: {" + ",".join(parts["c"]) + "},\n"
        + "junctions: {" + ",".join(parts["j"]) + "},\n"
        + "rods: [" + ",".join(parts["r"]) + "],\n"
        + "environment: [" + ",".join(parts["e"]) + "],\n"
        + "gravity: (0, 0, -9.81),\n)\n"
    )
    return text.replace('"../assets/', f'"{assets}')


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("count", type=int, help="number of bays (1..)")
    parser.add_argument("out", type=Path, help="the case file to write (RON)")
    args = parser.parse_args()
    if args.count < 1:
        parser.error("count must be at least 1")
    args.out.write_text(bays(args.count))


if __name__ == "__main__":
    main()
