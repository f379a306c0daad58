"""`tvl --help` lists every command without importing it, in the command's own words."""

from __future__ import annotations

import shlex
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
    assert " ".join(first_paragraph.split()) == COMMANDS[name]


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


def test_the_run_commands_help_loads_neither_numpy_nor_the_progress_bars() -> None:
    # Each takes a tenth of a second or more to import, the most of `tvl run --help`'s
    # start-up: the options name numpy-free constants, and a bar is built when one runs.
    printed, loaded = helps_in_a_fresh_interpreter(
        "[['run', '--help']]", "('numpy', 'rich.progress')"
    )
    assert "Perform a behaviour in WORLD" in printed
    assert loaded == "[]"


@pytest.mark.slow  # about half a second
def test_the_run_commands_help_loads_neither_hdf5_nor_the_physics() -> None:
    # What `tvl run --help` prints needs the options alone (cli/run.py says so); the JSON
    # documents and the replay's tables load h5py, so they load when a command runs.
    helps = "[[name, '--help'] for name in ('run', 'replay', 'explain', 'demo')]"
    printed, loaded = helps_in_a_fresh_interpreter(helps, "('h5py', 'pymunk', 'matplotlib')")
    assert "Perform a behaviour in WORLD" in printed
    assert loaded == "[]"


@pytest.mark.slow  # over a second
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


def every_command() -> list[tuple[str, click.Command]]:
    """The group and each command and subcommand, by the words that call it ("" the group)."""
    found: list[tuple[str, click.Command]] = [("", main)]
    for name in COMMANDS:
        command = main.get_command(click.Context(main), name)
        assert command is not None
        found.append((name, command))
        if isinstance(command, click.Group):
            for sub in command.list_commands(click.Context(command)):
                found.append((f"{name} {sub}", command.commands[sub]))
    return found


@pytest.mark.parametrize(("name", "command"), every_command(), ids=lambda x: str(x) or "tvl")
def test_every_help_ends_with_examples_that_parse(invoke_tvl, name: str, command) -> None:
    from tvl_cli.cli.examples import EXAMPLES

    shown = invoke_tvl(*name.split(), "-h")
    assert shown.returncode == 0, shown.stderr
    listed = shown.stdout.split("\n  Examples:\n")
    assert len(listed) == 2, shown.stdout
    assert [line.strip() for line in listed[1].splitlines()] == list(EXAMPLES[name])
    for example in EXAMPLES[name]:
        words = shlex.split(example.partition(" > ")[0])
        assert words[0] == "tvl"
        # Each parses with the command it names: its options exist and take its values.
        try:
            target, args = resolved(words[1:])
            # Under the group's context, as the command line calls it (its -h among them).
            parent = click.Context(main, info_name="tvl", help_option_names=["-h", "--help"])
            target.make_context(target.name, args, parent=parent)
        except click.exceptions.Exit:
            pass  # a help asked for


def resolved(words: list[str]) -> tuple[click.Command, list[str]]:
    """The command a command line names, and the arguments left for it."""
    command: click.Command = main
    while isinstance(command, click.Group) and words and not words[0].startswith("-"):
        found = command.get_command(click.Context(command), words[0])
        assert found is not None, words
        command, words = found, words[1:]
    return command, words


def test_seed_says_what_it_seeds_in_words_and_no_range_of_digits(invoke_tvl) -> None:
    for name in ("learn", "run", "baseline dwa", "baseline qlearn", "world new", "design"):
        shown = invoke_tvl(*name.split(), "-h").stdout
        seed = " ".join(shown.split("--seed N", 1)[1].split("\n  -", 1)[0].split())
        assert seed.startswith(("Seed of", "Layout seed")) and "[default: 1]" in seed, name
        assert "9223372036854775807" not in shown and "<=" not in seed
    refused = invoke_tvl("run", "f.h5", "w.txt", "--behaviour", "avoid", "--seed", "-1")
    assert refused.returncode == 2
    assert "-1 is not a seed: a whole number from 0 to 2^63 - 1" in refused.stderr


@pytest.mark.parametrize("group", ["baseline", "world"])
def test_a_groups_help_lists_each_commands_first_line_whole(invoke_tvl, group: str) -> None:
    shown = invoke_tvl(group, "-h").stdout
    commands = " ".join(shown.split("\nCommands:\n")[1].split("\n\n")[0].split())
    assert "..." not in commands
    group_command = main.get_command(click.Context(main), group)
    assert isinstance(group_command, click.Group)
    for command in group_command.commands.values():
        assert command.help is not None
        first = " ".join(command.help.split("\n\n")[0].split())
        assert first.split(". ")[0] in commands


def test_a_subcommands_usage_names_its_argument_not_its_choices(invoke_tvl) -> None:
    usage = invoke_tvl("world", "new", "-h").stdout.splitlines()[0]
    assert usage == "Usage: tvl world new [OPTIONS] KIND"
