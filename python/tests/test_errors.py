"""Bad input raises the exception of the CLI's exit status, with the CLI's message."""

from __future__ import annotations

import pytest

import strand

from conftest import REPO, error_message, run_cli

COOLER = "cases/cooler_hose.ron"


def cli_error(strand_bin, *args):
    code, _, stderr = run_cli(strand_bin, *args, check_codes=(1, 2, 3))
    return code, error_message(stderr)


def test_missing_file(strand_bin):
    code, message = cli_error(strand_bin, "solve", "cases/no_such_case.ron")
    with pytest.raises(strand.InputError) as raised:
        strand.Case.load("cases/no_such_case.ron")
    assert str(raised.value) == message and "no_such_case.ron" in message
    assert raised.value.exit_code == code == 2


def test_syntax_error_names_line_and_column(strand_bin, tmp_path):
    text = (REPO / COOLER).read_text().replace("length: 190,", "length: 190,,", 1)
    path = tmp_path / "broken.ron"
    path.write_text(text)
    code, message = cli_error(strand_bin, "solve", path)
    with pytest.raises(strand.InputError) as raised:
        strand.Case.load(path)
    assert str(raised.value) == message and f"{path}:" in message
    assert code == 2


def test_validation_error_names_the_item(strand_bin, tmp_path):
    text = (REPO / COOLER).read_text().replace("length: 190,", "length: -190,", 1)
    path = tmp_path / "negative.ron"
    path.write_text(text)
    code, message = cli_error(strand_bin, "solve", path)
    case = strand.Case.load(path)  # parses; the build validates
    with pytest.raises(strand.InputError) as raised:
        case.solve()
    assert str(raised.value) == message and "hose2" in message and code == 2
    with pytest.raises(strand.InputError) as checked:
        case.check()
    assert str(checked.value) == message


def test_unknown_variant(strand_bin):
    code, message = cli_error(strand_bin, "solve", COOLER, "--variant", "no_such")
    with pytest.raises(strand.InputError) as raised:
        strand.Case.load(COOLER).variant("no_such")
    assert str(raised.value) == message and "hose2_plus50" in message and code == 2


def test_bad_change_item_has_the_batch_message(strand_bin, tmp_path):
    code, message = cli_error(
        strand_bin, "batch", COOLER, "--vary", "hose2.lenght=+30mm", "--out", tmp_path / "b"
    )
    case = strand.Case.load(COOLER)
    with pytest.raises(strand.InputError) as raised:
        case.with_changes({"hose2.lenght": "+30mm"})
    assert str(raised.value) == message and "hose2.lenght" in message and code == 2
    with pytest.raises(strand.InputError) as batched:
        strand.batch(case, vary={"hose2.lenght": "+30mm"}, as_frame=False)
    assert str(batched.value) == message


def test_bad_change_value(strand_bin, tmp_path):
    code, message = cli_error(
        strand_bin, "batch", COOLER, "--vary", "hose2.length=+30kg", "--out", tmp_path / "b"
    )
    with pytest.raises(strand.InputError) as raised:
        strand.Case.load(COOLER).with_changes({"hose2.length": "+30kg"})
    assert str(raised.value) == message and "+30kg" in message


def test_change_that_breaks_the_case_names_the_change(strand_bin, tmp_path):
    # Hose 2 shorter than the distance of its ends: the build fails, naming the change.
    case = strand.Case.load(COOLER).with_changes({"hose2.length": "-180mm"})
    with pytest.raises(strand.InputError) as raised:
        case.solve()
    assert "hose2.length=-180mm" in str(raised.value)
    # The batch records the same variant as failed at the build stage, not an error.
    rows = strand.batch(strand.Case.load(COOLER), vary={"hose2.length": "-180mm"}, as_frame=False)
    assert rows[0]["status"] == "failed" and rows[0]["stage"] == "build"


def test_type_errors_are_python_errors():
    case = strand.Case.load(COOLER)
    with pytest.raises(TypeError):
        case.with_changes({"hose2.length": True})
    with pytest.raises(strand.InputError):
        strand.batch(case, vary={"hose2.length": "+0mm"}, keep="everything")


def test_warm_start_from_another_kind_of_case_is_an_input_error():
    other = strand.Case.load("cases/elastica_fig3.ron").solve()
    with pytest.raises(strand.InputError) as raised:
        strand.Case.load(COOLER).solve(warm_start=other)
    assert "warm_start" in str(raised.value) and "junction" in str(raised.value)


def test_a_warm_start_that_did_not_converge_falls_back_with_the_cli_warning(tmp_path):
    text = (REPO / COOLER).read_text().replace(
        "units: (length: \"mm\"),", "units: (length: \"mm\"),\n    solver: (max_iterations: 1),", 1)
    limited = strand.Case.from_str(text, base_dir=REPO / "cases", name="cooler_hose")
    unconverged = limited.solve()
    assert not unconverged.converged
    with pytest.raises(strand.NotConvergedError) as raised:
        unconverged.check()
    assert "not converged" in str(raised.value) and raised.value.exit_code == 3
    with pytest.warns(strand.StrandWarning, match="did not converge"):
        result = strand.Case.load(COOLER).solve(warm_start=unconverged)
    assert result.converged and not result.warm_start
