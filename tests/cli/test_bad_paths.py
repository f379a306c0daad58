"""Output paths the system refuses, on the command line, run in process: one line, no traceback."""

from __future__ import annotations

from pathlib import Path

from test_bad_numbers import assert_one_line_refusal


def test_demo_under_a_file_is_one_line_naming_the_path(invoke_tvl, tmp_path: Path) -> None:
    a_file = tmp_path / "notes.txt"
    a_file.write_text("keep me")
    result = invoke_tvl("demo", a_file / "demo")
    assert_one_line_refusal(result, str(a_file / "demo"), "Not a directory")
    assert a_file.read_text() == "keep me"


def test_an_output_named_like_an_input_or_another_output_is_refused(
    invoke_tvl, tmp_path: Path
) -> None:
    from test_bad_numbers import SQUARE

    log, fam, out = tmp_path / "log.h5", tmp_path / "fam.h5", tmp_path / "out.png"
    data = tmp_path / "out.h5"
    assert (
        invoke_tvl("learn", SQUARE, "--log", log, "--minutes", "0.5", "--fam", fam).returncode == 0
    )
    # A world named as a picture, so that drawing it over itself passes the picture's check.
    world = tmp_path / "square.png"
    world.write_bytes(SQUARE.read_bytes())
    kept = {path: path.read_bytes() for path in (log, fam, world)}
    avoid = ["run", fam, SQUARE, "--behaviour", "avoid"]
    for args, message in (
        (["train", log, "-o", log, "--force"], "given as both -o and LOG 1"),
        (["learn", SQUARE, "--log", data, "--fam", data], "given as both --fam and --log"),
        ([*avoid, "--log", fam, "--force"], "given as both --log and FAM"),
        ([*avoid, "--log", data, "--learn-log", data], "given as both --log and --learn-log"),
        (["replay", log, "--png", out, "--curves", out], "given as both --png and --curves"),
        (["world", "render", world, "-o", world, "--force"], "given as both -o and WORLD"),
    ):
        result = invoke_tvl(*args)
        assert_one_line_refusal(result, "", message)
    assert {path: path.read_bytes() for path in (log, fam, world)} == kept
    assert not out.exists() and not data.exists()


def test_a_special_file_is_never_replaced_even_with_force(invoke_tvl, tmp_path: Path) -> None:
    import os

    pipe = tmp_path / "pipe"
    os.mkfifo(pipe)
    result = invoke_tvl("world", "new", "square", "-o", pipe, "--force")
    assert_one_line_refusal(result, str(pipe), "is a device or other special file")
    assert pipe.is_fifo()
