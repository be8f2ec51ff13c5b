"""Shared fixtures: the default case's branch, solved once, and the
`cyclorub` command of the main workspace."""

import os
import shutil
from pathlib import Path

import pytest

import cyclorub

REPOSITORY = Path(__file__).resolve().parents[2]


def small_case(**changes):
    """The default case with its branch cut into many small steps: a run of
    about a second that is long enough to time and to interrupt."""
    case = cyclorub.Case.default()
    # The first step too: it may not exceed the largest.
    case.continuation.initial_step = 0.004
    case.continuation.max_step = 0.004
    return case.replace(changes)


@pytest.fixture(scope="session")
def default_result():
    """The default case without the stability check (`cyclorub run
    --no-stability`)."""
    return cyclorub.Case.default().run(stability=False, progress=False)


@pytest.fixture(scope="session")
def cli():
    """The `cyclorub` command: $CYCLORUB_CLI (CI sets it; the test fails if
    it does not exist), else the workspace's build, else skip."""
    given = os.environ.get("CYCLORUB_CLI")
    if given:
        assert Path(given).is_file(), f"CYCLORUB_CLI={given} does not exist"
        return given
    for candidate in (REPOSITORY / "target/release/cyclorub",
                      REPOSITORY / "target/debug/cyclorub"):
        if candidate.is_file():
            return str(candidate)
    found = shutil.which("cyclorub")
    if found:
        return found
    pytest.skip("no cyclorub command: build it (cargo build -p cyclorub-cli) or set CYCLORUB_CLI")
