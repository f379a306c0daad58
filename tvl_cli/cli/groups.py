"""A group of subcommands (`tvl world`, `tvl baseline`) whose help lists each one's first
line whole, folded to the terminal, where click would cut it at about 45 characters."""

from __future__ import annotations

import click


class Subcommands(click.Group):
    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        rows = []
        for name in self.list_commands(ctx):
            command = self.get_command(ctx, name)
            if command is not None and not command.hidden:
                # A limit no first line reaches: the formatter folds it instead.
                rows.append((name, command.get_short_help_str(limit=10_000)))
        if rows:
            with formatter.section("Commands"):
                formatter.write_dl(rows)
