"""Shared fixtures: the repository, the `strand` binary and running it."""

from __future__ import annotations

import json
import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
CASES = sorted((REPO / "cases").glob("*.ron"))


def binary() -> pathlib.Path:
    """The release `strand` binary (`STRAND_BIN`, else target/release/strand, built
    when missing)."""
    path = pathlib.Path(os.environ.get("STRAND_BIN", REPO / "target" / "release" / "strand"))
    if not path.exists():
        subprocess.run(
            ["cargo", "build", "--release", "-p", "strand-cli"], cwd=REPO, check=True
        )
    return path


@pytest.fixture(scope="session")
def strand_bin() -> pathlib.Path:
    return binary()


def run_cli(strand_bin, *args, check_codes=(0, 3)):
    """Runs the binary from the repository root; returns (exit code, stdout, stderr)."""
    done = subprocess.run(
        [str(strand_bin), *map(str, args)],
        cwd=REPO,
        capture_output=True,
        text=True,
        stdin=subprocess.DEVNULL,
    )
    assert done.returncode in check_codes, done.stderr
    return done.returncode, done.stdout, done.stderr


def cli_result(strand_bin, tmp_path, *args) -> dict:
    """`strand solve ARGS --out DIR` and its result.json."""
    out = tmp_path / "out"
    run_cli(strand_bin, "solve", *args, "--out", out)
    return json.loads((out / "result.json").read_text())


def error_message(stderr: str) -> str:
    """The message of `error: <message>` on stderr (it may span lines)."""
    assert stderr.startswith("error: "), stderr
    return stderr[len("error: ") :].rstrip("\n")


def strip_run(doc: dict) -> dict:
    """`doc` without what differs between two runs of the same solve: the wall-clock
    times and the time of day in the provenance."""
    doc = dict(doc)
    doc.pop("timing_s")
    if doc.get("provenance") is not None:
        doc["provenance"] = {k: v for k, v in doc["provenance"].items() if k != "created_utc"}
    return doc


@pytest.fixture(autouse=True)
def at_repository_root(monkeypatch):
    """Case paths as the CLI is given them: relative to the repository root."""
    monkeypatch.chdir(REPO)
