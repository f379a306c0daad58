"""Method files (`--method FILE.toml`) as a careless or hostile user writes them, through
`tvl learn` and `tvl train`: numbers of the wrong type, beyond their range or not finite, and
lists, tables and dotted keys nested far too deep, each refused in one line naming the file
(and the key), exit 2, with nothing written and what was there unchanged."""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SQUARE = ROOT / "worlds" / "square.txt"
GOLDEN_LOG = ROOT / "tests" / "data" / "golden-log-v1.h5"

# name: (the file's text, what the one line says after the file's name)
BAD_METHODS = {
    "a window that is true": (
        'memory = { kind = "patches", window_s = true }',
        ": memory: window_s True must be a number",
    ),
    "a window that is text": (
        "memory = { kind = \"patches\", window_s = '20' }",
        ": memory: window_s '20' must be a number",
    ),
    "a deceleration of 1e20": ("decel_mps2 = 1e20", ": decel_mps2 1e+20 must be more than 0"),
    "a deceleration of 1e308": ("decel_mps2 = 1e308", ": decel_mps2 1e+308 must be more than 0"),
    "an infinite deceleration": ("decel_mps2 = inf", ": decel_mps2 inf must be more than 0"),
    "a margin beyond the ring": ("margin_m = 5.0", ": margin_m 5 must be 0 or more and at most 4"),
    "a memory range of 1e308": (
        'memory = { kind = "points", range_m = 1e308 }',
        ": memory: range_m 1e+308 must be more than 0 and at most 100 m",
    ),
    "lists nested 100,000 deep": (
        "decel_mps2 = " + "[" * 100_000 + "]" * 100_000,
        ":1: nested too deeply (more than 32",
    ),
    "inline tables nested 3,000 deep": (
        "memory = " + "{ a = " * 3000 + "1" + " }" * 3000,
        ":1: nested too deeply (more than 32",
    ),
    "a dotted key 100,000 parts deep": (
        "memory" + ".a" * 100_000 + " = 1",
        ":1: nested too deeply (more than 32",
    ),
    "a table header 100,000 parts deep": (
        "decel_mps2 = 0.2\n[" + "a." * 100_000 + "a]",
        ":2: nested too deeply (more than 32",
    ),
    "lists nested 40 deep": ("decel_mps2 = " + "[" * 40 + "]" * 40, ":1: nested too deeply"),
}


def method_file(folder: Path, name: str) -> tuple[Path, str]:
    """One of BAD_METHODS as a file; and what its refusal says after the file's name."""
    text, says = BAD_METHODS[name]
    path = folder / "m.toml"
    path.write_text(text)
    return path, says


def refused(result, *phrases: str) -> None:
    assert result.returncode == 2, result.stderr
    assert len(result.stderr.splitlines()) == 1, result.stderr
    for phrase in phrases:
        assert phrase in result.stderr, result.stderr


@pytest.mark.parametrize("name", sorted(BAD_METHODS))
def test_learn_refuses_the_method_file_naming_it_and_writes_no_log(
    invoke_tvl, tmp_path: Path, name: str
) -> None:
    method, says = method_file(tmp_path, name)
    log = tmp_path / "log.h5"
    refused(invoke_tvl("learn", SQUARE, "--log", log, "--minutes", "0.1", "--method", method),
            f"{method}{says}")  # fmt: skip
    assert not log.exists()


@pytest.mark.parametrize("name", ["a deceleration of 1e308", "a window that is text"])
def test_train_refuses_the_method_file_and_leaves_the_fam_there_unchanged(
    invoke_tvl, tmp_path: Path, name: str
) -> None:
    method, says = method_file(tmp_path, name)
    fam = tmp_path / "fam.h5"
    assert invoke_tvl("train", GOLDEN_LOG, "-o", fam).returncode == 0
    before = fam.read_bytes()
    refused(invoke_tvl("train", GOLDEN_LOG, "-o", fam, "--force", "--method", method),
            f"{method}{says}")  # fmt: skip
    assert fam.read_bytes() == before


def test_a_deceleration_beyond_reason_as_a_flag_is_one_line_not_a_numpy_warning(
    invoke_tvl, tmp_path: Path
) -> None:
    fam = tmp_path / "fam.h5"
    refused(invoke_tvl("train", GOLDEN_LOG, "-o", fam, "--decel", "1e308"),
            "--decel 1e+308 must be more than 0 and at most 10 m/s²")  # fmt: skip
    assert not fam.exists()


def test_appending_by_a_bad_method_leaves_the_log_as_it_was(invoke_tvl, tmp_path: Path) -> None:
    log = tmp_path / "log.h5"
    assert invoke_tvl("learn", SQUARE, "--log", log, "--minutes", "0.1").returncode == 0
    before = log.read_bytes()
    method, _ = method_file(tmp_path, "a deceleration of 1e308")
    refused(invoke_tvl("learn", SQUARE, "--log", log, "--minutes", "0.1", "--method", method),
            str(method))  # fmt: skip
    assert log.read_bytes() == before


def test_a_method_file_of_more_than_a_megabyte_is_refused_unread(
    invoke_tvl, tmp_path: Path
) -> None:
    method = tmp_path / "m.toml"
    method.write_text("# " + "x" * (1 << 20) + "\ndecel_mps2 = 0.2\n")
    log = tmp_path / "log.h5"
    refused(invoke_tvl("learn", SQUARE, "--log", log, "--method", method),
            f"{method}: over 1 MiB")  # fmt: skip
    assert not log.exists()
