"""The exception types the CLI prints as one line: bad input (exit 2), and what the machine
lacks (exit 1); and the hint a mistyped name gets."""

import difflib
import math
from collections.abc import Iterable


class BadInput(Exception):
    """Input a user can fix. The message names the file, the line and what is wrong."""


class EnvironmentFailure(RuntimeError):
    """Something the machine lacks, not the user's input: no display to open a window on."""


def did_you_mean(given: str, known: Iterable[str]) -> str:
    """ "; did you mean 'x'?" naming the known name nearest a mistyped one; empty if none is
    near (difflib's similarity of at least 0.6)."""
    near = difflib.get_close_matches(given, list(known), n=1)
    return f"; did you mean {near[0]!r}?" if near else ""


# Seeds are stored as 64-bit integers in logs and traces, and numpy takes no negative seed.
MAX_SEED = 2**63 - 1

# A simulated year: beyond any experiment (a day of wall time at 300x), and small enough that
# a step count is an exact integer and a progress bar's total stays finite.
MAX_SIMULATED_MINUTES = 525_600.0


def check_minutes(minutes: float, option: str = "--minutes", zero_allowed: bool = False) -> None:
    """Simulated durations the user gives must be positive (or 0 where that means none),
    finite, and at most a simulated year."""
    low = minutes >= 0.0 if zero_allowed else minutes > 0.0
    if not (math.isfinite(minutes) and low and minutes <= MAX_SIMULATED_MINUTES):
        least = "0 or more" if zero_allowed else "more than 0"
        raise BadInput(
            f"{option} {minutes:g} must be {least} and at most {MAX_SIMULATED_MINUTES:g} "
            "simulated minutes (a year)"
        )


# A run's simulated minutes when none are given (`tvl run`, a sweep's runs).
DEFAULT_RUN_MINUTES = 5.0


def check_run_minutes(minutes: float, control_period_s: float, option: str = "--minutes") -> None:
    """A run lasts at least one control step: a shorter one has nothing to measure."""
    check_minutes(minutes, option)
    if minutes * 60.0 < control_period_s:
        raise BadInput(
            f"{option} {minutes:g} is shorter than one control step ({control_period_s:g} s)"
        )
