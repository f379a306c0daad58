"""The method as one value: its presets, its checks, a method file's fields, and how a
command's choice of it lays over what its inputs were made with."""

from __future__ import annotations

import re
from dataclasses import replace

import pytest

from tvl_cli.core.errors import BadInput
from tvl_cli.core.memory import NO_MEMORY, PATCHES, MemoryChoice, MemoryConfig
from tvl_cli.core.method import (
    DEFAULT,
    DEFAULT_REFLEXES,
    LEARNING_FIELDS,
    NOT_GIVEN,
    PAPER,
    Method,
    MethodChoice,
    describe_record,
    method_from_dict,
    method_record,
    preset_name,
)


def test_the_papers_method_learns_at_bumps_alone_and_runs_with_no_reflex_or_memory() -> None:
    assert (PAPER.near_m, PAPER.reflexes, PAPER.memory) == (0.0, (), NO_MEMORY)
    assert PAPER.exploration == DEFAULT.exploration == "least-experience"
    assert DEFAULT.reflexes == DEFAULT_REFLEXES and DEFAULT.memory.kind == PATCHES


def test_reflexes_are_kept_in_stacking_order_whatever_order_they_are_given_in() -> None:
    assert Method(reflexes=("tie", "blocked-ways")).reflexes == ("blocked-ways", "tie")


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("decel_mps2", 0.0, "--decel 0 must be more than 0 and at most 10 m/s²"),
        ("decel_mps2", 1e308, "--decel 1e+308 must be more than 0 and at most 10 m/s²"),
        ("margin_m", -0.1, "--margin -0.1 must be 0 or more and at most 4 m"),
        ("margin_m", 4.5, "--margin 4.5 must be 0 or more and at most 4 m"),
        ("near_m", float("nan"), "--near nan must be 0 or more and at most 4 m"),
        ("label_ceiling_radius_m", 0.0, "--label-ceiling-radius 0 must be more than 0"),
        ("label_ceiling_radius_m", "wide", "--label-ceiling-radius 'wide' must be a number"),
        ("exploration", "greedy", "--explore 'greedy': choose least-experience"),
        ("reflexes", ("bumpy",), "--reflex ('bumpy',): names from blocked-ways"),
        ("wall_rule", "hug", "wall_rule 'hug': choose first-seen"),
        ("sonar", "laser", "--sonar 'laser': choose real, edges, ideal"),
    ],
)
def test_a_method_that_cannot_be_is_refused_naming_the_flag(
    field: str, value: object, message: str
) -> None:
    with pytest.raises(BadInput, match=re.escape(message)):
        replace(DEFAULT, **{field: value})


def test_a_method_file_gives_fields_by_name_and_leaves_the_rest_ours() -> None:
    method = method_from_dict(
        {"decel_mps2": 1, "reflexes": ["tie", "bump"], "memory": {"kind": "none"}}, "m.toml"
    )
    assert method == replace(DEFAULT, decel_mps2=1.0, reflexes=("bump", "tie"), memory=NO_MEMORY)
    assert method_from_dict({"reflexes": "none", "memory": "points"}, "m.toml").reflexes == ()
    assert method_from_dict(method_record(PAPER), "record") == PAPER


@pytest.mark.parametrize(
    ("data", "message"),
    [
        ({"decel": 0.2}, "m.toml: unknown key 'decel' (did you mean 'decel_mps2'?)"),
        ({"colour": "red"}, "m.toml: unknown key 'colour' (known: decel_mps2, margin_m,"),
        ({"margin_m": "wide"}, "m.toml: margin_m 'wide' must be a number"),
        ({"near_m": True}, "m.toml: near_m True must be a number"),
        ({"reflexes": ["bumpy"]}, "m.toml: reflexes ['bumpy']: a list of names from"),
        ({"memory": {"kind": "lines"}}, "m.toml: memory: --memory lines: choose none"),
        ({"wall_rule": ["first-seen"]}, "m.toml: wall_rule ['first-seen']: choose first-seen"),
        ({"decel_mps2": 1e20}, "m.toml: decel_mps2 1e+20 must be more than 0 and at most 10"),
        ({"memory": {"kind": "patches", "window_s": True}}, "m.toml: memory: window_s True must"),
        ({"memory": {"kind": "patches", "window_s": "20"}}, "m.toml: memory: window_s '20' must"),
        ({"memory": {"kind": "points", "range_m": 1e308}}, "m.toml: memory: range_m 1e+308 must"),
        ({"memory": {"kind": 1}}, "m.toml: memory: kind 1 is not text"),
    ],
)
def test_a_bad_method_file_is_refused_naming_the_file_and_key(data: dict, message: str) -> None:
    with pytest.raises(BadInput) as refused:
        method_from_dict(data, "m.toml")
    assert str(refused.value).startswith(message)


def test_a_record_names_the_preset_it_equals_on_the_fields_it_keeps() -> None:
    assert method_record(PAPER)["preset"] == "paper"
    assert method_record(DEFAULT, LEARNING_FIELDS) == {
        "preset": "default",
        **{n: v for n, v in DEFAULT.to_dict().items() if n in LEARNING_FIELDS},
    }
    # The paper's learning, behaving with our reflexes: the paper's on learning alone.
    mixed = replace(PAPER, reflexes=DEFAULT_REFLEXES)
    assert preset_name(mixed) is None and preset_name(mixed, LEARNING_FIELDS) == "paper"
    labels = (
        f"decel_mps2 {PAPER.decel_mps2:g}, margin_m {PAPER.margin_m:g}, labels bump, "
        "label_ceiling 1, label_ceiling_radius_m inf"
    )
    assert (
        describe_record(method_record(mixed)) == f"default, except {labels}, near_m 0, memory none"
    )
    assert describe_record(None) == "unrecorded"


def test_a_choice_not_given_leaves_a_command_its_inputs_method() -> None:
    inherited = replace(DEFAULT, memory=NO_MEMORY, near_m=0.2)
    assert NOT_GIVEN.over(inherited, ("reflexes", "memory")) == inherited


def test_a_chosen_method_gives_only_the_commands_own_fields() -> None:
    inherited = replace(DEFAULT, near_m=0.2)
    run = MethodChoice(PAPER, "paper").over(inherited, ("reflexes", "wall_rule", "memory"))
    assert run == replace(inherited, reflexes=(), memory=NO_MEMORY)


def test_finer_settings_lay_over_the_chosen_method() -> None:
    choice = MethodChoice(
        PAPER, "my.toml", (("decel_mps2", 0.2), ("sonar", "edges")), MemoryChoice(window_s=5.0)
    )
    made = choice.over(DEFAULT, ("decel_mps2", "memory"))
    assert (made.decel_mps2, made.sonar, made.memory) == (0.2, "edges", NO_MEMORY)
    remembering = MethodChoice(settings=(), memory=MemoryChoice(PATCHES, 5.0)).over(
        PAPER, ("memory",)
    )
    assert remembering.memory == MemoryConfig(PATCHES, window_s=5.0)


def test_a_setting_contradicts_the_papers_method_only_by_name_and_only_if_it_differs() -> None:
    def contradictions(name: str, *settings: tuple[str, object], **memory: object) -> list[str]:
        return MethodChoice(PAPER, name, settings, MemoryChoice(**memory)).contradictions()

    assert contradictions("paper", ("decel_mps2", 0.1), ("near_m", 0.0)) == ["decel_mps2"]
    assert contradictions("paper", ("reflexes", ()), ("decel_mps2", PAPER.decel_mps2)) == []
    assert contradictions("paper", kind="patches", window_s=10.0) == [
        "memory.kind",
        "memory.window_s",
    ]
    # The sonar model is no addition: another is a setting, not a contradiction.
    assert contradictions("paper", ("sonar", "edges")) == []
    # A file that happens to equal the paper's method is a method of one's own.
    assert contradictions("paper.toml", ("decel_mps2", 0.1)) == []
