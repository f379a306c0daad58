"""Output paths the system refuses, through the real `tvl` process: one line, no traceback."""

from __future__ import annotations

from pathlib import Path

from test_bad_numbers import assert_one_line_refusal


def test_demo_under_a_file_is_one_line_naming_the_path(run_tvl, tmp_path: Path) -> None:
    a_file = tmp_path / "notes.txt"
    a_file.write_text("keep me")
    result = run_tvl("demo", a_file / "demo")
    assert_one_line_refusal(result, str(a_file / "demo"), "Not a directory")
    assert a_file.read_text() == "keep me"
