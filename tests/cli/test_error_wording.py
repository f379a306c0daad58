"""Errors a newcomer meets say what is wrong in the user's words: a binary file is not text
(not the codec's complaint), a file where a folder should be is named as a file, a mistyped
command gets the one it may have meant, a data output must be named for its format, and
Ctrl-C where nothing catches it exits 130, not click's "Aborted!". Through the real
commands, in-process."""

from __future__ import annotations

from pathlib import Path

import pytest
from test_bad_numbers import assert_one_line_refusal

ROOT = Path(__file__).resolve().parents[2]
SQUARE = ROOT / "worlds" / "square.txt"
EXAMPLE_LOG = ROOT / "logs" / "square-s1.h5"
PNG_START = b"\x89PNG\r\n\x1a\n"
NOT_TEXT = "not a text file (byte 0x89 is not UTF-8"


@pytest.fixture
def binary(tmp_path: Path) -> Path:
    """A picture, under a name of the text file a command reads."""
    return tmp_path / "picture"


@pytest.mark.parametrize(
    ("suffix", "args"),
    [
        (".txt", ("world", "check", "{}")),
        (".txt", ("learn", "{}", "--log", "{dir}/log.h5")),
        (".json", ("learn", SQUARE, "--log", "{dir}/log.h5", "--config", "{}")),
        (".toml", ("learn", SQUARE, "--log", "{dir}/log.h5", "--method", "{}")),
        (".toml", ("sweep", "{}", "--out", "{dir}/out")),
        (".jsonl", ("figure", "fig19", "{}", "-o", "{dir}/f.png")),
    ],
)
def test_a_binary_file_given_for_text_is_called_not_text(
    invoke_tvl, tmp_path: Path, suffix: str, args: tuple[object, ...]
) -> None:
    picture = tmp_path / f"picture{suffix}"
    picture.write_bytes(PNG_START + bytes(range(256)))
    given = [str(a).format(picture, dir=tmp_path) for a in args]
    done = invoke_tvl(*given)
    assert_one_line_refusal(done, f"{picture}:1:1: {NOT_TEXT}")
    assert "codec" not in done.stderr and "position" not in done.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == [picture.name]


@pytest.mark.parametrize(
    "args",
    [
        ("learn", SQUARE, "--log", "{}/log.h5"),
        ("train", EXAMPLE_LOG, "-o", "{}/fam.h5"),
        ("world", "new", "square", "-o", "{}/square.txt"),
        ("world", "render", SQUARE, "-o", "{}/square.png"),
    ],
)
def test_a_file_where_a_folder_should_be_is_named_a_file(
    invoke_tvl, tmp_path: Path, args: tuple[object, ...]
) -> None:
    file = tmp_path / "square.txt"
    file.write_text("not a folder\n")
    done = invoke_tvl(*(str(a).format(file) for a in args))
    assert_one_line_refusal(done, f"cannot write, {file} is a file, not a directory")
    missing = tmp_path / "nowhere"
    done = invoke_tvl(*(str(a).format(missing) for a in args))
    assert_one_line_refusal(done, f"cannot write, directory {missing} does not exist")


@pytest.mark.parametrize(
    ("typed", "meant"), [("rn", "run"), ("lern", "learn"), ("replya", "replay")]
)
def test_a_mistyped_command_is_told_the_command_it_may_have_meant(
    invoke_tvl, typed: str, meant: str
) -> None:
    done = invoke_tvl(typed, "anything")
    assert_one_line_refusal(done, f"No such command '{typed}'. Did you mean '{meant}'?")
    far = invoke_tvl("xyzzy")
    assert_one_line_refusal(far, "No such command 'xyzzy'.")
    assert "Did you mean" not in far.stderr


@pytest.mark.parametrize(
    ("args", "option", "written_as"),
    [
        (("learn", SQUARE, "--log", "{}/log.txt"), "--log", "HDF5"),
        (("learn", SQUARE, "--log", "{}/log.h5", "--fam", "{}/fam.fam"), "--fam", "HDF5"),
        (("train", EXAMPLE_LOG, "-o", "{}/fam.txt"), "-o", "HDF5"),
        (("run", "{}/fam.h5", SQUARE, "--behaviour", "avoid", "--log", "{}/run.txt"),
         "--log", "HDF5"),
        (("run", "{}/fam.h5", SQUARE, "--behaviour", "avoid", "--learn-log", "{}/l.txt"),
         "--learn-log", "HDF5"),
        (("export", "{}/run.h5", "--mcap", "{}/run.txt"), "--mcap", "MCAP"),
        (("design", EXAMPLE_LOG, "-o", "{}/config.txt"), "-o", "JSON"),
        (("figure", "fig19", "{}/r.jsonl", "-o", "{}/f.png", "--table", "{}/t.txt"),
         "--table", "Markdown"),
    ],
)  # fmt: skip
def test_a_data_output_is_named_for_its_format(
    invoke_tvl, tmp_path: Path, args: tuple[object, ...], option: str, written_as: str
) -> None:
    done = invoke_tvl(*(str(a).format(tmp_path) for a in args))
    assert_one_line_refusal(done, f"Invalid value for '{option}", f"written as {written_as}")
    assert list(tmp_path.iterdir()) == []  # refused on parsing, before any work


def test_ctrl_c_where_no_command_catches_it_exits_130(
    invoke_tvl, monkeypatch: pytest.MonkeyPatch
) -> None:
    from tvl_cli.commands import world

    def interrupted(*args: object) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(world, "load_world", interrupted)
    done = invoke_tvl("world", "check", SQUARE)
    assert done.returncode == 130
    assert done.stderr == "tvl: interrupted\n" and "Aborted" not in done.stdout


def test_a_grid_of_two_worlds_of_one_name_asks_for_another_name(invoke_tvl, tmp_path: Path) -> None:
    (tmp_path / "copy.txt").write_text(SQUARE.read_text())
    grid = tmp_path / "grid.toml"
    grid.write_text('world = ["square", "copy.txt"]\nseed = 1\nbehaviour = "avoid"\n')
    done = invoke_tvl("sweep", grid, "--out", tmp_path / "out")
    assert_one_line_refusal(done, "worlds 'square' and 'copy.txt' are both named 'square'")
    assert done.stderr.endswith("so give one of them another name\n")
