"""The command line keeps click's conventions: its hint on a usage error (on the one line),
`--learn` a flag beside `--learn-log LOG`, typed X,Y and INPUT=METRES options, completions
for every choice, "did you mean" for mistyped keys and names, and ranges on every speed;
through the real command, in-process (CliRunner)."""

from __future__ import annotations

import json
from pathlib import Path

import click
import pytest
from click.shell_completion import ShellComplete
from click.testing import CliRunner
from method_samples import LIVE_RING

from tvl_cli.agent.reflexes import STACK_ORDER
from tvl_cli.cli import main
from tvl_cli.cli.main import COMMANDS
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import BUILTIN_FAM_CONFIGS, SINGLE
from tvl_cli.core.method import PRESETS
from tvl_cli.core.robot_config import FASTEST_MPS, RobotConfig
from tvl_cli.io.famfile import write_fam
from tvl_cli.io.json_documents import SCHEMA_COMMANDS
from tvl_cli.io.logreader import read_log
from tvl_cli.render.experiment_figures import FIGURES

ROOT = Path(__file__).resolve().parents[2]
SQUARE = ROOT / "worlds" / "square.txt"
OBSTACLES = ROOT / "worlds" / "obstacles.txt"
BRIEF = ["--behaviour", "avoid", "--minutes", "0.05"]


@pytest.fixture(scope="module")
def fam(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A FAM that has learnt nothing: it runs, and learns while it runs."""
    path = tmp_path_factory.mktemp("click") / "fam.h5"
    robot = RobotConfig()
    write_fam(path, Fam(SINGLE, [t.name for t in robot.trajectories]), robot_config=robot,
              method=LIVE_RING,
              provenance={})  # fmt: skip
    return path


def tvl(*args: str | Path) -> tuple[int, str, str]:
    done = CliRunner().invoke(main, [str(a) for a in args], prog_name="tvl")
    return done.exit_code, done.stdout, done.stderr


def test_a_usage_error_ends_with_clicks_hint_on_its_one_line(fam: Path) -> None:
    code, _, err = tvl("run", fam)
    assert code == 2
    assert err == "tvl: error: tvl run: Missing argument 'WORLD'. Try 'tvl run -h' for help.\n"


def test_learn_is_a_flag_that_takes_no_fam_for_its_log(fam: Path, tmp_path: Path) -> None:
    code, out, err = tvl("run", "--learn", fam, SQUARE, *BRIEF, "--json")
    assert code == 0, err
    assert json.loads(out)["learnt"]["session"] is None  # in memory
    log = tmp_path / "log.h5"
    code, out, err = tvl("run", fam, SQUARE, *BRIEF, "--learn-log", log, "--json")
    assert code == 0, err
    assert json.loads(out)["learnt"]["session"] == "0000"
    # A FAM that knows nothing finds nothing fast: a session of spins, no episode in it.
    assert [s.kind for s in read_log(log, empty_allowed=True).sessions] == ["behaving"]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["run", "FAM", SQUARE, "--behaviour", "goal", "--goal", "9"],
         "Invalid value for '--goal': '9' is not X,Y in metres, e.g. 3.5,2.0"),
        (["run", "FAM", SQUARE, "--behaviour", "goal", "--goal", "nan,1"],
         "Invalid value for '--goal': 'nan,1' is not X,Y in metres"),
        (["baseline", "dwa", SQUARE, "--goal", "1;2"],
         "Invalid value for '--goal': '1;2' is not X,Y in metres"),
        (["inspect", "FAM", "--over", "front"],
         "Invalid value for '--over': 'front' is not two input names A,B"),
        (["inspect", "FAM", "--fix", "front-left=near"],
         "Invalid value for '--fix': 'front-left=near' is not INPUT=METRES"),
        (["learn", SQUARE, "--log", "LOG", "--learn-speed", "100"],
         f"Invalid value for '--learn-speed': 100.0 is not in the range 0.0<x<={FASTEST_MPS}"),
        (["learn", SQUARE, "--log", "LOG", "--learn-speed", "0"],
         "Invalid value for '--learn-speed': 0.0 is not in the range"),
        (["train", "LOG", "-o", "OUT", "--init-velocity", "0.5"],
         "Invalid value for '--init-velocity': 0.5 is not in the range 0.0<=x<0.35"),
        (["diff", "FAM", "FAM", "--tolerance", "-0.1"],
         "Invalid value for '--tolerance': -0.1 is not in the range x>=0.0"),
    ],
)  # fmt: skip
def test_typed_and_ranged_options_refuse_in_one_line(
    fam: Path, tmp_path: Path, args: list[str | Path], message: str
) -> None:
    named = {"FAM": fam, "LOG": tmp_path / "log.h5", "OUT": tmp_path / "out.h5"}
    code, out, err = tvl(*(named.get(str(a), a) for a in args))
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and message in err, err
    assert not (tmp_path / "log.h5").exists() and not (tmp_path / "out.h5").exists()


@pytest.mark.parametrize("given", [("--over", "front,front-right"), ("--fix", "front-left=0.6")])
def test_inspect_refuses_picture_options_without_a_picture(
    fam: Path, given: tuple[str, str]
) -> None:
    code, out, err = tvl("inspect", fam, *given)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "give --png PATH" in err, err


def test_a_goal_is_read_as_two_numbers(fam: Path) -> None:
    code, _, err = tvl("run", fam, OBSTACLES, "--behaviour", "goal", "--goal", "5.875, 3.875",
                         "--minutes", "0.05", "--json")  # fmt: skip
    assert code == 0, err
    code, _, err = tvl("run", fam, SQUARE, *BRIEF, "--goal", "1,1")
    assert code == 2 and "--goal is for --behaviour goal only" in err


def _completions(args: list[str], incomplete: str) -> list[str]:
    completer = ShellComplete(main, {}, "tvl", "_TVL_COMPLETE")
    return [item.value for item in completer.get_completions(args, incomplete)]


def test_every_named_choice_completes() -> None:
    assert _completions(["learn", "square.txt", "--config"], "") == [*BUILTIN_FAM_CONFIGS, ""]
    assert _completions(["learn", "square.txt", "--config"], "mu") == ["multi", "mu"]
    assert _completions(["figure"], "fig2") == [n for n in FIGURES if n.startswith("fig2")]
    assert _completions(["inspect", "fam.h5", "--trajectory"], "T1") == ["T1L", "T1R"]
    assert _completions(["run", "f", "w", "--reflex"], "") == ["all", "none", *STACK_ORDER]
    first, second = STACK_ORDER[:2]
    assert _completions(["run", "f", "w", "--reflex"], f"{first},") == [
        f"{first},{name}" for name in STACK_ORDER[1:]
    ]
    assert f"{first},{second}" in _completions(["baseline", "dwa", "w", "--reflex"], f"{first},")
    assert _completions(["learn", "square.txt", "--method"], "pa") == ["paper", "pa"]
    assert _completions(["train", "log.h5", "--method"], "") == [*PRESETS, ""]
    # A world: a bundled one by name, a generated one begun as KIND:, else a file (the shell's).
    for command in (["run", "fam.h5"], ["learn"], ["baseline", "dwa"], ["world", "render"]):
        assert _completions(command, "ro") == ["rooms", "rooms:", "ro"], command


def test_schema_completes_the_commands_a_word_at_a_time() -> None:
    assert _completions(["schema"], "wo") == ["world"]
    assert _completions(["schema", "world"], "") == [
        c.split()[1] for c in SCHEMA_COMMANDS if c.startswith("world ")
    ]
    assert _completions(["schema", "baseline"], "q") == ["qlearn"]
    assert "run" in _completions(["schema"], "") and "new" not in _completions(["schema"], "")


def test_every_choice_option_of_every_command_completes_its_choices() -> None:
    ctx = click.Context(main)
    commands = []
    for name in COMMANDS:
        command = main.get_command(ctx, name)
        group = command if isinstance(command, click.Group) else None
        subs = [(name, command)] if group is None else [
            (f"{name} {sub}", group.get_command(ctx, sub)) for sub in group.list_commands(ctx)
        ]  # fmt: skip
        commands += subs
    checked = 0
    for path, command in commands:
        for param in command.params:
            if isinstance(param.type, click.Choice):
                found = param.shell_complete(click.Context(command), "")
                assert [item.value for item in found] == list(param.type.choices), (path, param)
                checked += 1
    assert checked >= 12  # --behaviour, --sonar, --memory, --explore, --event, --view, ...


def test_a_mistyped_configuration_or_key_is_told_the_name_it_missed(
    fam: Path, tmp_path: Path
) -> None:
    code, _, err = tvl("train", "log.h5", "-o", tmp_path / "f.h5", "--config", "singel")
    assert code == 2 and err.rstrip().endswith("(did you mean 'single'?)")
    config = tmp_path / "mine.json"
    config.write_text(json.dumps({"name": "mine", "tabels": []}))
    code, _, err = tvl("learn", SQUARE, "--log", tmp_path / "l.h5", "--config", config)
    assert code == 2 and err.rstrip().endswith("unknown key 'tabels' (did you mean 'tables'?)")
    grid = tmp_path / "grid.toml"
    grid.write_text('world = "square"\nseed = 1\nbehaviour = "avoid"\nlearn_minute = 1\n')
    code, _, err = tvl("sweep", grid, "--out", tmp_path / "sweep")
    assert code == 2 and err.rstrip().endswith("(did you mean 'learn_minutes'?)")
    grid.write_text('world = "square"\nseed = 1\nbehaviour = "avoid"\ncolour = 1\n')
    code, _, err = tvl("sweep", grid, "--out", tmp_path / "sweep")
    assert code == 2 and "unknown key 'colour'" in err and "did you mean" not in err
