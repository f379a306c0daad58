"""The figures the documentation quotes for the code's constants are the code's own."""

from __future__ import annotations

import math

from doc_pages import page, section

from tvl_cli.agent.novelty import BLOCKED_BEYOND_STOP_M, NOVELTY_BIN_M, NOVELTY_LOOKAHEAD_M
from tvl_cli.agent.reflexes import (
    BLOCKED_HALF_WIDTH_RAD,
    BLOCKED_S,
    FIRST_ESCAPE_S,
    PROGRESS_M,
    STACK_ORDER,
    STALLED_S,
)
from tvl_cli.commands.learn import LOG_WRITE_EVERY_S
from tvl_cli.core.contacts import NEAR_MISS_WITHIN_RAD
from tvl_cli.core.learn_params import BACKOFF_M
from tvl_cli.core.method import PAPER
from tvl_cli.core.robot_config import EDGE_ECHO_RANGE_M, SonarConfig
from tvl_cli.core.trajectory_choice import LOOKAHEAD_M
from tvl_cli.io.hdf5_header import FAM_FORMAT, FORMAT_VERSIONS, LOG_FORMAT, RUN_FORMAT

METHOD = page("method.md")
REFLEX_TABLE = section(METHOD, "Reflexes: every rule beyond the paper")


def _row(reflex: str) -> str:
    return next(line for line in REFLEX_TABLE.splitlines() if line.startswith(f"| `{reflex}` |"))


def test_every_reflex_has_a_row_in_the_reflex_table_in_stacking_order() -> None:
    rows = [line.split("`")[1] for line in REFLEX_TABLE.splitlines() if line.startswith("| `")]
    assert rows == list(STACK_ORDER)


def test_blocked_ways_are_quoted_with_their_width_and_time() -> None:
    row = _row("blocked-ways")
    assert f"within {math.degrees(BLOCKED_HALF_WIDTH_RAD):g}°" in row
    assert f"until {BLOCKED_S:g} s after" in row
    assert f"first {BACKOFF_M:g} m" in row


def test_the_escape_is_quoted_with_its_times_and_progress() -> None:
    row = _row("escape")
    assert f"no nearer the goal (by {PROGRESS_M:g} m, by odometry) for {STALLED_S:g} s" in row
    assert f"the left wall for {FIRST_ESCAPE_S:g} s" in row
    assert f"{PROGRESS_M:g} m nearer the goal than it has ever been" in row


def test_near_misses_are_quoted_with_their_angle_and_blind_zone() -> None:
    row = _row("near-miss")
    assert f"within {math.degrees(NEAR_MISS_WITHIN_RAD):g}° of straight ahead" in row
    assert f"its {SonarConfig().min_range_m:g} m minimum range" in row
    assert f"reverses {BACKOFF_M:g} m" in row
    assert f"within {math.degrees(NEAR_MISS_WITHIN_RAD):g}° of straight ahead" in section(
        page("guide/behaving.md"), "What a run counts"
    )


def test_the_paper_labels_and_the_lookahead_are_quoted_as_they_are() -> None:
    labels = f"deceleration\n  {PAPER.decel_mps2:g} m/s², margin {PAPER.margin_m:g} m"
    assert labels in page("guide/behaving.md")
    assert f"judged {LOOKAHEAD_M:g} m along itself" in METHOD


def test_the_edge_echo_range_is_quoted_as_it_is() -> None:
    sonars = section(page("guide/robot.md"), "What real sonars hear beyond the specular rule")
    assert f"within {EDGE_ECHO_RANGE_M:.1f} m (a quarter of the maximum range)" in sonars
    assert SonarConfig().max_range_m / 4 == EDGE_ECHO_RANGE_M


def test_the_novelty_rule_is_quoted_as_it_is() -> None:
    learning = page("guide/learning.md")
    novelty = learning.split("**Where to learn next (`--explore`).**")[1].split("**Coverage.**")[0]
    assert f"in {NOVELTY_BIN_M:g} m square bins" in novelty
    assert f"in the next {NOVELTY_LOOKAHEAD_M:g} m" in novelty
    assert f"`--near` and {BLOCKED_BEYOND_STOP_M * 100:g} cm" in " ".join(novelty.split())


def test_what_a_kill_of_learning_may_lose_is_quoted_as_it_is() -> None:
    files = page("guide/files.md")
    assert f"span\n  {LOG_WRITE_EVERY_S:g} simulated seconds" in files
    assert f"ended in the last {LOG_WRITE_EVERY_S:g} simulated seconds" in files
    stopping = (
        page("guide/learning.md").split("Ctrl-C or SIGTERM stops learning")[1].split("\n\n")[0]
    )
    assert f"ended in the last {LOG_WRITE_EVERY_S:g} simulated seconds" in stopping


def test_the_file_format_versions_are_quoted_as_they_are() -> None:
    files = " ".join(page("guide/files.md").split())
    log, fam, run = (FORMAT_VERSIONS[f] for f in (LOG_FORMAT, FAM_FORMAT, RUN_FORMAT))
    assert (
        f"logs of format version {log}, FAM files of version {fam} and run traces of version {run}"
        in files
    )
    assert f"Run trace (`tvl run --log`, format version {run})" in files


def test_the_method_files_ranges_and_limits_are_quoted_as_they_are() -> None:
    from tvl_cli.core.labels import MAX_DECEL_MPS2, MAX_MARGIN_M
    from tvl_cli.core.memory import MAX_PATCH_M, MAX_RANGE_M, MAX_WINDOW_S
    from tvl_cli.core.method import MAX_NEAR_M
    from tvl_cli.core.nesting import MAX_NESTING
    from tvl_cli.io.textfile import MAX_SETTINGS_BYTES

    files = section(METHOD, "Method files")
    rows = {line.split("`")[1]: line for line in files.splitlines() if line.startswith("| `")}
    assert f"more than 0, at most {MAX_DECEL_MPS2:g} m/s²" in rows["decel_mps2"]
    assert f"0 to {MAX_MARGIN_M:g} m" in rows["margin_m"]
    assert f"0 to {MAX_NEAR_M:g} m" in rows["near_m"]
    assert f"at most {MAX_WINDOW_S:g} s" in rows["memory.window_s"]
    assert f"at most {MAX_RANGE_M:g} m" in rows["memory.range_m"]
    assert f"0 to {MAX_PATCH_M:g} m" in rows["memory.patch_m"]
    assert f"at most {MAX_SETTINGS_BYTES >> 20} MiB" in files
    assert f"nest at most {MAX_NESTING} deep" in files
