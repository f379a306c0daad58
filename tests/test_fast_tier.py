"""The fast tier's rules in tests/conftest.py: a test that asks for `run_tvl` is marked slow,
and a test that starts a real `tvl` process unmarked fails instead of slipping into the fast
tier. Each is checked on a few tests of its own, run by an inner pytest."""

from __future__ import annotations

from pathlib import Path

import conftest as tiers
import pytest

ROOT = Path(__file__).resolve().parent.parent

INNER_TESTS = """
import subprocess

import pytest
from conftest import TVL


@pytest.fixture(scope="module")
def learnt():
    subprocess.run([TVL, "learn", "square.txt", "--log", "log.h5"], check=True)


def test_asks_for_run_tvl(run_tvl):
    pass


def test_starts_tvl_itself():
    subprocess.run([TVL, "--help"], capture_output=True)


def test_runs_a_script():
    subprocess.run(["logs/make_examples.sh"], capture_output=True)


def test_runs_a_shell():
    subprocess.run("tvl --help", shell=True, capture_output=True)


def test_shares_a_fixture_that_starts_tvl(learnt):
    pass


@pytest.mark.slow
def test_marked():
    pass


def test_starts_another_program():
    assert subprocess.run(["true"]).returncode == 0
"""


@pytest.fixture
def inner(pytester: pytest.Pytester) -> pytest.Pytester:
    pytester.makeini("[pytest]\nmarkers =\n    slow: slow\naddopts = -p no:cacheprovider\n")
    pytester.makepyfile(test_inner=INNER_TESTS)
    return pytester


def test_a_test_asking_for_run_tvl_is_marked_slow(inner: pytest.Pytester) -> None:
    result = inner.runpytest_inprocess("--collect-only", "-q", "-m", "slow", plugins=[tiers])
    assert sorted(line for line in result.outlines if "::" in line) == [
        "test_inner.py::test_asks_for_run_tvl",
        "test_inner.py::test_marked",
    ]


@pytest.mark.slow
def test_an_unmarked_test_that_starts_tvl_fails_naming_itself(inner: pytest.Pytester) -> None:
    result = inner.runpytest_inprocess("-m", "not slow", plugins=[tiers])
    result.assert_outcomes(passed=1, failed=3, errors=1, deselected=2)
    for name in (
        "starts_tvl_itself",
        "runs_a_script",
        "runs_a_shell",
        "shares_a_fixture_that_starts_tvl",
    ):
        result.stdout.fnmatch_lines([f"*test_{name} starts a real `tvl` process*not marked slow*"])


def test_the_real_processes_kept_in_the_fast_tier_are_tests_that_exist() -> None:
    for nodeid in tiers.FAST_PROCESS_TESTS:
        path, name = nodeid.split("::")
        assert f"\ndef {name}(" in (ROOT / path).read_text(encoding="utf-8"), nodeid
