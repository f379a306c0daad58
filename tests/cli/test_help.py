"""`tvl --help` lists every command without importing it, in the command's own words."""

from __future__ import annotations

import subprocess
import sys

import click
import pytest

from tvl_cli.cli.main import COMMANDS, main


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_the_listed_line_is_the_first_paragraph_of_the_commands_help(name: str) -> None:
    command = main.get_command(click.Context(main), name)
    assert command is not None and command.help is not None
    first_paragraph = command.help.split("\n\n")[0]
    assert " ".join(first_paragraph.split()) == COMMANDS[name][2]


def helps_in_a_fresh_interpreter(helps: str, loaded: str) -> tuple[str, str]:
    """What a new python prints showing each help `helps` names (an expression of argument
    lists), and the sorted modules named `loaded` (an expression of module names) it then
    holds."""
    code = (
        "import sys; from tvl_cli.cli.main import COMMANDS, main\n"
        f"for arguments in {helps}:\n"
        "    try:\n        main(arguments)\n    except SystemExit:\n        pass\n"
        f"print(sorted(m for m in {loaded} if m in sys.modules), file=sys.stderr)"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120
    )
    return result.stdout, result.stderr.strip()


def test_the_top_level_help_loads_no_heavy_library() -> None:
    heavy = "('numpy', 'h5py', 'pymunk', 'matplotlib', 'rich')"
    printed, loaded = helps_in_a_fresh_interpreter("[['--help']]", heavy)
    assert "run" in printed and "baseline" in printed
    assert loaded == "[]"


def test_no_commands_help_loads_the_compiler() -> None:
    # Kernels compile (or load from numba's cache) when first used, never for a --help.
    helps = "[[name, '--help'] for name in COMMANDS]"
    numba = "[m for m in sys.modules if m.split('.')[0] == 'numba']"
    printed, loaded = helps_in_a_fresh_interpreter(helps, numba)
    assert "Perform a behaviour in WORLD" in printed  # every help was printed
    assert loaded == "[]"


def test_h_is_help_for_the_group_and_for_a_command(invoke_tvl) -> None:
    for command in ([], ["run"], ["world", "new"]):
        short, long = invoke_tvl(*command, "-h"), invoke_tvl(*command, "--help")
        assert short.returncode == long.returncode == 0, short.stderr
        assert short.stdout == long.stdout and short.stdout.startswith("Usage: tvl")
    assert "-h, --help" in invoke_tvl("run", "-h").stdout


def test_a_usage_error_of_the_group_itself_is_one_line_with_clicks_hint(invoke_tvl) -> None:
    # Click would put its hint on a line of its own, after a blank one: bad input is one line.
    done = invoke_tvl("--no-such-option")
    assert done.returncode == 2
    assert done.stderr == (
        "tvl: error: tvl: No such option '--no-such-option'. Try 'tvl -h' for help.\n"
    )


def test_a_group_given_no_command_shows_its_help_not_an_error(invoke_tvl) -> None:
    done = invoke_tvl("world")
    assert "Usage: tvl world" in done.stdout + done.stderr and "tvl: error" not in done.stderr
