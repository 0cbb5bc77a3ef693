"""Every bundled case solved from Python gives the CLI's result.json, number for
number (bit-identical: both are the same code; JSON floats round-trip exactly)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import strand

from conftest import CASES, REPO, cli_result, strip_run


def assert_same(a, b, path="$"):
    """`a == b` recursively, floats bit for bit, saying where they differ."""
    assert type(a) is type(b), f"{path}: {type(a).__name__} vs {type(b).__name__}"
    if isinstance(a, dict):
        assert a.keys() == b.keys(), f"{path}: keys {sorted(a.keys() ^ b.keys())}"
        for k in a:
            assert_same(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        assert len(a) == len(b), f"{path}: lengths {len(a)} vs {len(b)}"
        for i, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, f"{path}[{i}]")
    elif isinstance(a, float):
        assert a == b or (math.isnan(a) and math.isnan(b)), f"{path}: {a!r} vs {b!r}"
        assert math.copysign(1.0, a) == math.copysign(1.0, b), f"{path}: sign of zero"
    else:
        assert a == b, f"{path}: {a!r} vs {b!r}"


@pytest.mark.parametrize("path", CASES, ids=lambda p: p.stem)
def test_bundled_case_equals_cli_result_json(strand_bin, tmp_path, path):
    rel = path.relative_to(REPO)
    expected = cli_result(strand_bin, tmp_path, rel)
    result = strand.Case.load(rel).solve()
    got = result.to_dict()
    assert_same(strip_run(got), strip_run(expected))
    # The attributes are the document's.
    assert result.converged == expected["converged"]
    assert result.residual_N == expected["residual_N"]
    assert result.stable == expected["stable"]
    assert result.iterations == expected["iterations"]
    # Arrays: float64, shaped per vertex / per edge, the same numbers.
    for rod in expected["rods"]:
        arrays = result.rods[rod["name"]]
        n = rod["segments"]
        assert arrays["position_m"].shape == (n + 1, 3)
        assert arrays["force_N"].dtype == np.float64
        assert arrays["edge_force_N"].shape == (n, 3)
        for key in ("s_m", "position_m", "force_N", "moment_Nm", "bending_moment_Nm",
                    "torsion_Nm", "curvature_1pm", "edge_force_N"):
            assert np.array_equal(arrays[key], np.array(rod[key], dtype=float)), key
    for reaction, row in zip(result.reactions, expected["reactions"]):
        assert np.array_equal(reaction["force_N"], np.array(row["force_N"]))
    assert len(result.contacts) == len(expected.get("contacts", []))
    assert result.findings == expected.get("findings", [])


VARIANTS = [
    ("cooler_hose", "hose2_plus50"),
    ("cooler_hose_contact", "hose2_plus50"),
    ("study_demo", "plus50"),
]


@pytest.mark.parametrize("case,variant", VARIANTS)
def test_named_variant_warm_started_equals_solve_variant(strand_bin, tmp_path, case, variant):
    rel = f"cases/{case}.ron"
    expected = cli_result(strand_bin, tmp_path, rel, "--variant", variant)
    base = strand.Case.load(rel)
    result = base.variant(variant).solve(warm_start=base.solve())
    assert result.warm_start and result.variant == variant
    assert_same(strip_run(result.to_dict()), strip_run(expected))


def test_segments_equal_cli_segments(strand_bin, tmp_path):
    expected = cli_result(strand_bin, tmp_path, "cases/elastica_fig3.ron", "--segments", "152")
    got = strand.Case.load("cases/elastica_fig3.ron").solve(segments=152).to_dict()
    assert_same(strip_run(got), strip_run(expected))
    # The paper's Fig. 3 load (17.8, -12.8) N up to the discretisation error.
    end = [r for r in got["reactions"] if r["end"] == "end"][0]
    assert abs(end["force_N"][0] - 17.78) < 0.01 and abs(end["force_N"][1] + 12.79) < 0.01


def test_from_str_equals_load():
    text = (REPO / "cases/cooler_hose.ron").read_text()
    loaded = strand.Case.load("cases/cooler_hose.ron").solve().to_dict()
    parsed = strand.Case.from_str(text, name="cooler_hose").solve().to_dict()
    for doc in (loaded, parsed):
        doc.pop("timing_s")
        doc.pop("provenance")
    assert_same(parsed, loaded)


def test_with_changes_is_the_longer_hose():
    case = strand.Case.load("cases/cooler_hose.ron")
    base = case.solve()
    longer = case.with_changes({"hose2.length": "+50mm"})
    assert longer.label == "hose2.length=+50mm"
    result = longer.solve(warm_start=base)
    hose2 = result.rods["hose2"]
    assert result.converged and result.warm_start
    assert hose2["s_m"][-1] == pytest.approx(base.rods["hose2"]["s_m"][-1] + 0.050, abs=1e-12)
    # The paper's Fig. 7: 50 mm more lowers the internal force of hose 2 markedly.
    peak = lambda r: np.linalg.norm(r.rods["hose2"]["force_N"], axis=1).max()
    assert peak(result) < 0.8 * peak(base)
    # The same change written as the named variant gives the same equilibrium.
    named = case.variant("hose2_plus50").solve(warm_start=base)
    assert np.array_equal(named.rods["hose2"]["position_m"], hose2["position_m"])
