"""The one exception type for bad input: the CLI prints its message as one line and exits 2."""


class BadInput(Exception):
    """Input a user can fix. The message names the file, the line and what is wrong."""
