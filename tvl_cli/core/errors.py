"""The one exception type for bad input: the CLI prints its message as one line and exits 2."""

import math


class BadInput(Exception):
    """Input a user can fix. The message names the file, the line and what is wrong."""


def check_minutes(minutes: float) -> None:
    """Simulated durations the user gives must be positive and finite."""
    if not (math.isfinite(minutes) and minutes > 0):
        raise BadInput(f"--minutes {minutes:g} must be a positive number of simulated minutes")
