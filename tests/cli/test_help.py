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


def test_the_top_level_help_loads_no_heavy_library() -> None:
    code = (
        "import sys; from tvl_cli.cli import main\n"
        "try:\n    main(['--help'])\nexcept SystemExit:\n    pass\n"
        "heavy = ('numpy', 'h5py', 'pymunk', 'matplotlib', 'rich')\n"
        "print(sorted(m for m in heavy if m in sys.modules), file=sys.stderr)"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=60
    )
    assert "run" in result.stdout and "baseline" in result.stdout
    assert result.stderr.strip() == "[]"


def test_no_commands_help_loads_the_compiler() -> None:
    # Kernels compile (or load from numba's cache) when first used, never for a --help.
    code = (
        "import sys; from tvl_cli.cli.main import COMMANDS, main\n"
        "for name in COMMANDS:\n"
        "    try:\n        main([name, '--help'])\n    except SystemExit:\n        pass\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] == 'numba'), file=sys.stderr)"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120
    )
    assert "Perform a behaviour in WORLD" in result.stdout  # every help was printed
    assert result.stderr.strip() == "[]"
