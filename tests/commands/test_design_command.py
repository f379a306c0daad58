"""`tvl design` as a command: logs in, a configuration file out that `--config` takes."""

from __future__ import annotations

from pathlib import Path

import pytest

from tvl_cli.commands.design import DesignSummary, design_from_logs
from tvl_cli.commands.train import train_from_logs
from tvl_cli.core.errors import BadInput
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io.fam_config_file import resolve_fam_config
from tvl_cli.io.logreader import file_sha256, read_log

EXAMPLE_LOG = Path(__file__).resolve().parents[2] / "logs" / "square-s1.h5"


@pytest.fixture(scope="module")
def designed(tmp_path_factory: pytest.TempPathFactory) -> DesignSummary:
    output = tmp_path_factory.mktemp("design") / "square-inputs.json"
    return design_from_logs([EXAMPLE_LOG], output, seed=1)


def test_the_file_written_is_the_configuration_chosen(designed: DesignSummary) -> None:
    config = resolve_fam_config(str(designed.output), RobotConfig())
    assert config == designed.design.config
    assert config.name == "square-inputs"
    assert config.design is not None
    assert config.design.logs_sha256 == (file_sha256(EXAMPLE_LOG),)
    assert config.design.seed == 1


@pytest.mark.slow  # over a second
def test_the_configuration_trains_on_every_exemplar_of_the_log(designed: DesignSummary) -> None:
    config = resolve_fam_config(str(designed.output), RobotConfig())
    summary = train_from_logs([EXAMPLE_LOG], config)
    assert summary.exemplars == read_log(EXAMPLE_LOG).exemplar_count
    assert summary.rules_total == config.rule_count
    assert 0 < summary.rules_touched <= summary.rules_total


def test_every_episode_is_either_trained_on_or_held_out(designed: DesignSummary) -> None:
    episodes = sum(len(s.episode_table) for s in read_log(EXAMPLE_LOG).sessions)
    design = designed.design
    assert design.train_episodes + design.heldout_episodes == episodes
    assert design.heldout_episodes == pytest.approx(episodes / 4, abs=4)


@pytest.mark.slow
def test_a_small_budget_is_kept(tmp_path: Path) -> None:
    summary = design_from_logs([EXAMPLE_LOG], tmp_path / "small.json", budget_rules=40)
    assert summary.design.config.rule_count <= 40


def test_an_unreadable_log_is_refused_by_name(tmp_path: Path) -> None:
    log = tmp_path / "notes.h5"
    log.write_text("not a log")
    with pytest.raises(BadInput, match=r"notes\.h5"):
        design_from_logs([log], tmp_path / "out.json")
    assert not (tmp_path / "out.json").exists()


def test_no_log_is_refused() -> None:
    with pytest.raises(BadInput, match="no learning log given"):
        design_from_logs([], Path("out.json"))
