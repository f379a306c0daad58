"""The exception types a user meets: bad input (the CLI prints its message as one line and
exits 2) and a failure of what the command relies on, such as a service that does not answer
or a display that is not there (one line, exit 1); and the hint a mistyped name gets."""

import difflib
import math
from collections.abc import Sequence


class BadInput(Exception):
    """Input a user can fix. The message names the file, the line and what is wrong."""


class EnvironmentFailure(Exception):
    """What the command relies on beyond the user's input fails: a service that does not
    answer or answers as something else, a display to open a window on that is not there.
    The message names it and what happened."""


def did_you_mean(word: str, choices: Sequence[str]) -> str:
    """What to say after a word that is none of `choices`: the nearest one (by spelling, else
    the first that holds the word: `speed` for `mean_speed_mps`), else them all."""
    close = difflib.get_close_matches(word, choices, n=1)
    close = close or [choice for choice in choices if word and word in choice][:1]
    return f"did you mean {close[0]!r}?" if close else f"known: {', '.join(choices)}"


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


def check_in_range(
    value: object, label: str, low: float, high: float, unit: str, low_allowed: bool = True
) -> None:
    """A number a user gives (a flag's, a file's key's) must be one: not a bool or text,
    finite, and from `low` (or above it, without `low_allowed`) to `high`; BadInput naming it
    by `label` otherwise."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise BadInput(f"{label} {value!r} must be a number")
    above = value >= low if low_allowed else value > low
    if not (math.isfinite(value) and above and value <= high):
        least = f"{low:g} or more" if low_allowed else f"more than {low:g}"
        raise BadInput(f"{label} {value:g} must be {least} and at most {high:g} {unit}")


# A run's simulated minutes when none are given (`tvl run`, a sweep's runs).
DEFAULT_RUN_MINUTES = 5.0


def check_run_minutes(minutes: float, control_period_s: float, option: str = "--minutes") -> None:
    """A run lasts at least one control step: a shorter one has nothing to measure."""
    check_minutes(minutes, option)
    if minutes * 60.0 < control_period_s:
        raise BadInput(
            f"{option} {minutes:g} is shorter than one control step ({control_period_s:g} s)"
        )
