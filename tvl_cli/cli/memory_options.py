"""The echo memory's options, shared by every command that perceives through a memory."""

from __future__ import annotations

from collections.abc import Callable

import click

from tvl_cli.core.memory import (
    CLEARED_ABOVE_M,
    CLEARINGS,
    DEFAULT_MEMORY,
    DEFAULT_PATCH_M,
    DEFAULT_RANGE_M,
    DEFAULT_WINDOW_S,
    MEMORY_KINDS,
)


def memory_options(base: str) -> Callable[[Callable[..., None]], Callable[..., None]]:
    """--memory, --memory-window, --memory-range, --memory-patch and --memory-clearing,
    settings of the method's echo memory (cli.options.method_options) over `base` (said in the
    help). The paper's method keeps no memory."""

    def decorate(command: Callable[..., None]) -> Callable[..., None]:
        options = (
            click.option(
                "--memory",
                type=click.Choice(MEMORY_KINDS),
                default=None,
                help=f"What the FAM reads: the live ring (none), or with echoes remembered as "
                f"points or patches (default: the method's; without one, {base}).",
            ),
            click.option(
                "--memory-window",
                type=float,
                default=None,
                help=f"Seconds of echoes remembered (default {DEFAULT_WINDOW_S:g} with a memory).",
            ),
            click.option(
                "--memory-range",
                type=float,
                default=None,
                help=f"Echoes farther than this are not remembered, m (default "
                f"{DEFAULT_RANGE_M:g}).",
            ),
            click.option(
                "--memory-patch",
                type=float,
                default=None,
                help=f"Patches are at least this wide, m (default {DEFAULT_PATCH_M:g}).",
            ),
            click.option(
                "--memory-clearing",
                type=click.Choice(CLEARINGS),
                default=None,
                help="When a beam that hears an echo leaves out the remembered patches wider "
                f"than {2 * CLEARED_ABOVE_M:g} m in it: never, while seeking a goal, the same "
                "with the beams facing the goal leaving out every patch (toward-goal), or "
                f"always (default {DEFAULT_MEMORY.clearing} with a memory).",
            ),
        )
        for option in reversed(options):
            command = option(command)
        return command

    return decorate
