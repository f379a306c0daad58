"""Fuzzing the map YAML reader (`tvl world import`): any YAML file, mutated from map_saver's,
written as an attacker would (aliases nested to a billion laughs, lists nested thousands
deep, tags, numbers past a float) or made of random values, is read or refused in one short
line naming the file, never another exception or a hang. 150 mutated files and 40 of random
values in the fast tier (where generating the random ones costs most), 10,000 of each in the
slow one; TVL_FUZZ_EXAMPLES=N sets the fast tier's count of each."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from map_samples import pgm_bytes, room_pixels, yaml_text

from tvl_cli.core.errors import BadInput
from tvl_cli.io.occupancy_map import MAX_IMAGE_NAME, read_occupancy_map

MAX_PIXELS = 1 << 20
FAST_MUTATED = int(os.environ.get("TVL_FUZZ_EXAMPLES", "150"))
FAST_RANDOM = int(os.environ.get("TVL_FUZZ_EXAMPLES", "40"))
# Ten thousand in the slow tier (TVL_FUZZ_LONG_EXAMPLES sets another count).
SLOW = int(os.environ.get("TVL_FUZZ_LONG_EXAMPLES", "10000"))
# A message quotes what it refuses cut short: one line a person reads, beside the name of the
# file (an image's name may be long: up to 1,024 characters).
MAX_MESSAGE_CHARS = 400 + MAX_IMAGE_NAME


def fuzzing(examples: int) -> settings:
    return settings(
        max_examples=examples,
        # Milliseconds on the wall clock: a map that takes longer to read counts as a hang. The
        # slowest readable (lists nested deep, which PyYAML scans ahead 1,024 characters
        # deep) takes a quarter of a second of CPU; a loaded machine stretches that.
        deadline=10_000,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
    )


def laughs(levels: int, width: int) -> str:
    """A "billion laughs": each level an anchored list of `width` aliases of the one below."""
    lines = ["l0: &l0 [lol]"]
    for level in range(1, levels + 1):
        aliases = ", ".join(f"*l{level - 1}" for _ in range(width))
        lines.append(f"l{level}: &l{level} [{aliases}]")
    return "\n".join(lines) + "\n"


FRAGMENT = st.one_of(
    st.text(alphabet="[]{}:,-&*!|>'\"#%@ \n\t0123456789.eE+ablolmxyz", max_size=30),
    st.integers(1, 6000).map(lambda depth: "[" * depth + "0" + "]" * depth),
    st.integers(1, 6000).map(lambda depth: "{a: " * depth + "0" + "}" * depth),
    st.builds(laughs, st.integers(1, 12), st.integers(2, 10)),
    st.sampled_from(
        [
            "*l9",
            "&a [*a]",
            "!!python/object:os.system ls",
            "!!binary aGk=",
            "1e400",
            "-.inf",
            ".nan",
            "0x" + "f" * 200,
            "9" * 500,
            "~",
            "true",
            "[1, 2, 3]",
            "{x: 1}",
            "\u2028",
            "\x00",
            "\ufeff",
            "? [a]\n: b",
            "<<: *l1",
        ]
    ),
)
KEYS = st.sampled_from(
    ["image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh", "mode"]
)
VALUE = st.recursive(
    st.none() | st.booleans() | st.floats() | st.integers() | st.text(max_size=12),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=6), inner),
    max_leaves=20,
)


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A folder holding the room's image, which every YAML file names."""
    where = tmp_path_factory.mktemp("fuzz")
    (where / "room.pgm").write_bytes(pgm_bytes(room_pixels()))
    return where


def mutated(data: st.DataObject) -> str:
    """map_saver's YAML with a fragment in place of a stretch of it, or as a key's value."""
    text = yaml_text("room.pgm")
    if data.draw(st.booleans()):
        key = data.draw(KEYS)
        return "\n".join(
            f"{key}: {data.draw(FRAGMENT)}" if line.startswith(f"{key}:") else line
            for line in text.splitlines()
        )
    start = data.draw(st.integers(0, len(text)))
    end = data.draw(st.integers(start, min(len(text), start + 20)))
    return text[:start] + data.draw(FRAGMENT) + text[end:]


def random_document(data: st.DataObject) -> str:
    """A document of map keys holding any values, as PyYAML writes them."""
    keys = data.draw(st.dictionaries(KEYS, VALUE, max_size=7))
    return yaml.safe_dump({"image": "room.pgm", **keys})


def read_or_refuse(folder: Path, text: str) -> None:
    path = folder / "room.yaml"
    path.write_bytes(text.encode("utf-8", "surrogatepass"))
    try:
        found = read_occupancy_map(path, MAX_PIXELS)
    except BadInput as refusal:
        message = str(refusal)
        assert message.startswith((str(path), str(folder / "")))  # names the file it read
        assert "\n" not in message and len(message) <= MAX_MESSAGE_CHARS, message
        return
    assert found.free.shape == room_pixels().shape


@pytest.mark.slow  # over a second
@fuzzing(FAST_MUTATED)
@given(st.data())
def test_a_mutated_map_yaml_is_read_or_refused_in_one_line(folder: Path, data) -> None:
    read_or_refuse(folder, mutated(data))


@pytest.mark.slow  # over a second
@fuzzing(FAST_RANDOM)
@given(st.data())
def test_any_values_under_the_map_keys_are_read_or_refused_in_one_line(folder, data) -> None:
    read_or_refuse(folder, random_document(data))


@pytest.mark.slow
@fuzzing(SLOW)
@given(st.data())
def test_ten_thousand_mutated_map_yamls(folder: Path, data) -> None:
    read_or_refuse(folder, mutated(data))


@pytest.mark.slow
@fuzzing(SLOW)
@given(st.data())
def test_ten_thousand_random_map_yamls(folder: Path, data) -> None:
    read_or_refuse(folder, random_document(data))


def test_a_billion_laughs_is_refused_at_its_first_alias(folder: Path) -> None:
    text = yaml_text("room.pgm", origin="*l9") + laughs(9, 10)
    path = folder / "laughs.yaml"
    path.write_text(text)
    with pytest.raises(BadInput, match=r"laughs\.yaml:4:9: not valid YAML \(an alias"):
        read_occupancy_map(path, MAX_PIXELS)


def test_a_list_nested_five_thousand_deep_is_refused(folder: Path) -> None:
    path = folder / "deep.yaml"
    path.write_text(yaml_text("room.pgm", origin="[" * 5000 + "]" * 5000))
    with pytest.raises(BadInput, match=r"deep\.yaml:4:28: not valid YAML \(nested deeper"):
        read_occupancy_map(path, MAX_PIXELS)
