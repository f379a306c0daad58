"""Shared fixtures: the `tvl` command line run in this process (`invoke_tvl`, most command-line
tests) or as the real console script in a subprocess (`run_tvl`, for what only a process shows:
exit at a signal, a crash at exit, the script itself); and the fast tier's rules.

The fast tier (`pytest -m "not slow"`) leaves out the tests marked `slow`: those that start a
real `tvl` process (one costs about 0.15 s of CPU just to start) or run for more than about a
second. A test that asks for `run_tvl` is marked here; any other test that starts `tvl`
itself, or a shell (the experiments' and the example logs' scripts run `tvl`), carries
`@pytest.mark.slow` or its module's `pytestmark`. A test left unmarked that starts one anyway
fails, naming itself: always in the fast tier, where no slow test can have started it first
for a fixture they share.
"""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, settings

pytest_plugins = ["pytester"]  # tests/test_fast_tier.py runs an inner pytest

# The console script installed beside the interpreter running the tests.
TVL = str(Path(sys.executable).with_name("tvl"))

# Hypothesis times each example on the wall clock, which parallel workers on a shared CPU make
# run at random: no test here is about time (the fuzz tests keep their own deadline for a hang).
settings.register_profile("tvl", deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("tvl")

# Fixtures that start a real `tvl` process: a test that asks for one is slow.
PROCESS_FIXTURES = frozenset({"run_tvl"})

# Real `tvl` processes kept in the fast tier. Each costs about 0.15 s of CPU and guards what
# every other command-line test rests on: the installed console script starts, does a whole
# command and exits 0, and refuses bad input in one line with exit status 2.
FAST_PROCESS_TESTS = frozenset(
    {
        "tests/cli/test_world_cli.py::test_check_reports_ok_with_the_counts",
        "tests/cli/test_world_cli.py::test_missing_world_file_is_one_error_line_and_exit_2",
    }
)


@pytest.fixture
def run_tvl() -> Callable[..., subprocess.CompletedProcess[str]]:
    """Run `tvl ARGS...` and return the finished process (text output, never raises)."""

    def run(*args: str | Path) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [TVL, *map(str, args)], capture_output=True, text=True, timeout=120, check=False
        )

    return run


def invoke(*args: str | Path) -> subprocess.CompletedProcess[str]:
    """Run `tvl ARGS...` in this process through click's CliRunner, and return what a real
    process would have: exit status, stdout and stderr apart (never raises for a refusal).

    For what the command line parses, says and writes. A real process is still what checks
    a signal, a crash at exit or the console script itself (`run_tvl`). An exception that
    escapes the command, which a real process would print as a traceback, fails the test."""
    from click.testing import CliRunner

    from tvl_cli.cli.main import main

    argv = list(map(str, args))
    done = CliRunner().invoke(main, argv, prog_name="tvl")
    if done.exception is not None and not isinstance(done.exception, SystemExit):
        raise done.exception
    return subprocess.CompletedProcess(["tvl", *argv], done.exit_code, done.stdout, done.stderr)


@pytest.fixture
def unwritable_folder() -> Path:
    """A folder no file can be made in, not even by root: /sys on Linux (skipped where it
    takes files, or is not there)."""
    folder = Path("/sys")
    probe = folder / ".tvl-probe"
    try:
        probe.touch()
    except OSError:
        return folder
    probe.unlink()
    pytest.skip(f"{folder} takes new files here")


@pytest.fixture
def invoke_tvl() -> Callable[..., subprocess.CompletedProcess[str]]:
    """`invoke`: `tvl ARGS...` in this process (the fast tier's command line)."""
    return invoke


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    for item in items:
        if item.nodeid in FAST_PROCESS_TESTS:
            continue
        if PROCESS_FIXTURES.intersection(getattr(item, "fixturenames", ())):
            item.add_marker(pytest.mark.slow)


def starts_tvl(args: Any, shell: bool = False) -> bool:
    """Whether a command line runs `tvl`: the console script, or a shell (which may)."""
    if isinstance(args, bytes):
        args = args.decode()
    first = (args.split() or [""])[0] if isinstance(args, str) else next(iter(args), "")
    program = Path(first.decode() if isinstance(first, bytes) else str(first)).name
    return shell or program in ("tvl", "sh", "bash") or program.endswith(".sh")


@contextmanager
def no_tvl_process(nodeid: str) -> Iterator[None]:
    """Refuse to start a `tvl` process for the test `nodeid` (from its fixtures too)."""

    class Guarded(subprocess.Popen):  # type: ignore[type-arg]
        def __init__(self, args: Any, *rest: Any, **options: Any) -> None:
            if starts_tvl(args, options.get("shell", False)):
                raise AssertionError(
                    f"{nodeid} starts a real `tvl` process ({args!r}) but is not marked "
                    "slow: add @pytest.mark.slow (see tests/conftest.py)"
                )
            super().__init__(args, *rest, **options)

    unguarded = subprocess.Popen
    subprocess.Popen = Guarded  # type: ignore[misc]
    try:
        yield
    finally:
        subprocess.Popen = unguarded  # type: ignore[misc]


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item: pytest.Item) -> Iterator[None]:
    if item.get_closest_marker("slow") or item.nodeid in FAST_PROCESS_TESTS:
        yield
    else:
        with no_tvl_process(item.nodeid):
            yield
