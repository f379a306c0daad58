"""Imports point one way: cli -> sweep -> commands -> (render, analysis, io) -> baselines ->
agent -> sim -> core, and the Gymnasium environment (gym, an optional extra) sits beside commands,
imported by nothing. Checked over every import statement in the package, function-level ones
too."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from package_imports import PACKAGE, imports, room_imported, room_modules

# The rooms each room may import from, besides itself. Top-level modules (tvl_cli/__init__)
# hold only the version and may be imported by anyone.
ALLOWED: dict[str, set[str]] = {
    "core": set(),
    "sim": {"core"},
    "agent": {"core", "sim"},
    "baselines": {"core", "sim", "agent"},
    "io": {"core"},
    # Coverage measures the floor a robot can reach in a world's own geometry.
    "analysis": {"core", "sim"},
    "render": {"core", "sim", "analysis", "io"},
    "commands": {"core", "sim", "agent", "baselines", "io", "analysis", "render"},
    # The sweep runs the verbs' work (learn, train, run, baseline) over a grid of cells.
    "sweep": {"core", "sim", "agent", "baselines", "io", "analysis", "render", "commands"},
    # The bench runs suites of cells on the sweep's engine, and scores Gymnasium controllers.
    "bench": {"core", "sim", "agent", "baselines", "io", "analysis", "render", "commands"}
    | {"sweep", "gym"},
    "cli": {"core", "sim", "agent", "baselines", "io", "analysis", "render", "commands"}
    | {"sweep", "bench"},
    "gym": {"core", "sim", "agent", "baselines", "io", "render"},
}
# Libraries a room must not load: the paper's core is numpy and the standard library, and the
# run loop never pulls in files, the terminal or drawing.
BANNED: dict[str, set[str]] = {
    "core": {"h5py", "pymunk", "click", "rich", "matplotlib"},
    "sim": {"h5py", "click", "rich", "matplotlib"},
    "agent": {"h5py", "click", "rich", "matplotlib"},
    "baselines": {"h5py", "click", "rich", "matplotlib"},
    "io": {"pymunk", "click", "rich", "matplotlib"},
    "analysis": {"h5py", "pymunk", "click", "rich", "matplotlib"},
    "gym": {"click", "rich"},
    "bench": {"click", "rich", "matplotlib"},
}
# Libraries only one room may load: Gymnasium, the optional extra's, since tvl works without
# it installed; and the libraries of other tools' file formats (map_server's YAML and images,
# MCAP and Foxglove's protobuf schemas), which belong with the files.
ONLY_IN: dict[str, str] = {
    "gymnasium": "gym",
    "stable_baselines3": "gym",
    "yaml": "io",
    "PIL": "io",
    "mcap": "io",
    "mcap_protobuf": "io",
    "foxglove_schemas_protobuf": "io",
    "google": "io",
}
# Libraries of the tests alone: the schemas are JSON files the package prints, and checking a
# document against one is a test's work, not the command line's.
TESTS_ONLY = frozenset({"jsonschema", "referencing"})
# Libraries only modules whose file name ends so may load: numba compiles the hot loops, each a
# `*_kernel.py` beside its concept, and no other module should depend on it (nor load it, and
# its compiler, before a kernel runs).
CONFINED: dict[str, str] = {"numba": "_kernel.py"}


def _confined_to(name: str) -> str | None:
    """How the file names of the modules that alone may import the library `name` end, if
    that is set."""
    return CONFINED.get(name.split(".")[0])


def test_every_module_lives_in_a_known_room() -> None:
    assert {room for room, _ in room_modules()} == set(ALLOWED)


@pytest.mark.parametrize(("room", "path"), room_modules(), ids=lambda v: str(v))
def test_imports_point_one_way(room: str, path: Path) -> None:
    wrong = []
    for name in imports(path):
        parts = name.split(".")
        target = room_imported(name)
        if target in ALLOWED:
            if target != room and target not in ALLOWED[room]:
                wrong.append(name)
        elif (
            parts[0] in BANNED.get(room, set())
            or ONLY_IN.get(parts[0], room) != room
            or parts[0] in TESTS_ONLY
        ):
            wrong.append(name)
    assert not wrong, f"{path.relative_to(PACKAGE)} ({room}) imports {wrong}"


# The verb that runs other verbs in turn, by design; what any other verbs share lives in the
# room it belongs to.
COMPOSES_VERBS = {"demo"}


@pytest.mark.parametrize("path", sorted((PACKAGE / "commands").glob("*.py")), ids=lambda p: p.stem)
def test_a_verb_imports_no_other_verb(path: Path) -> None:
    if path.stem in COMPOSES_VERBS:
        return
    verbs = [n for n in imports(path) if n.startswith("tvl_cli.commands")]
    assert not verbs, f"commands/{path.name} imports {verbs}: move what they share out"


def test_the_verb_composing_others_imports_them() -> None:
    # Else the exemption above would hold of nothing.
    for name in COMPOSES_VERBS:
        assert any(
            n.startswith("tvl_cli.commands.") for n in imports(PACKAGE / "commands" / f"{name}.py")
        )


@pytest.mark.parametrize(("room", "path"), room_modules(), ids=lambda v: str(v))
def test_confined_libraries_are_imported_only_by_their_modules(room: str, path: Path) -> None:
    wrong = [
        n for n in imports(path) if (ending := _confined_to(n)) and not path.name.endswith(ending)
    ]
    assert not wrong, f"{path.relative_to(PACKAGE)} imports {wrong}"


def test_the_kernel_modules_import_numba() -> None:
    # Else the confinement above would hold of nothing.
    assert any("numba" in imports(path) for path in PACKAGE.rglob("*_kernel.py"))


def test_importing_the_run_loop_loads_no_file_or_terminal_library() -> None:
    code = (
        "import sys, tvl_cli.agent.drive_tvl, tvl_cli.agent.explore, tvl_cli.baselines.dwa; "
        "print(sorted(m for m in ('h5py', 'click', 'rich', 'matplotlib') if m in sys.modules))"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=60
    )
    assert result.stdout.strip() == "[]"
