"""Each package of tvl_cli shows one face: a docstring whose first line says what it is, and
an `__all__` naming its modules (and what it defines itself), without importing them: a
package imported on the way to one of its modules loads none of the others, which keeps
`tvl --help` free of numpy and the rest (tests/cli/test_help.py)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest
from package_imports import PACKAGE, imports

from tvl_cli.cli.main import COMMANDS, command_named

# Every package's face but the top one's, which holds the version.
FACES = sorted(PACKAGE.glob("*/**/__init__.py"))

# The faces that import, and the modules they may import from: the console script's entry
# point is the command line's `main`, after os sets BLAS's threads before numpy can load;
# importing the Gymnasium room registers its environment.
IMPORTING = {
    "cli": {"os", "tvl_cli.cli.main"},
    "gym": {"gymnasium", "tvl_cli.core.competence", "tvl_cli.gym.env"}
    | {"tvl_cli.gym.policies", "tvl_cli.gym.vector"},
}


def _name(face: Path) -> str:
    return face.parent.relative_to(PACKAGE).as_posix()


def _tree(face: Path) -> ast.Module:
    return ast.parse(face.read_text(encoding="utf-8"))


def _all(tree: ast.Module) -> list[str]:
    for node in tree.body:
        if isinstance(node, ast.Assign) and [ast.unparse(t) for t in node.targets] == ["__all__"]:
            return ast.literal_eval(node.value)
    return []


def _bound(tree: ast.Module) -> set[str]:
    """The names the face binds itself: by assignment or import."""
    names: set[str] = set()
    for node in tree.body:
        if isinstance(node, ast.Assign):
            names |= {t.id for t in node.targets if isinstance(t, ast.Name)}
        elif isinstance(node, ast.Import | ast.ImportFrom):
            names |= {(alias.asname or alias.name).split(".")[0] for alias in node.names}
    return names


def _modules(package: Path) -> set[str]:
    """The package's public modules and subpackages."""
    files = {path.stem for path in package.glob("*.py") if not path.stem.startswith("_")}
    return files | {path.parent.name for path in package.glob("*/__init__.py")}


@pytest.mark.parametrize("face", FACES, ids=_name)
def test_a_face_says_in_one_line_what_its_package_is(face: Path) -> None:
    docstring = ast.get_docstring(_tree(face))
    assert docstring, f"tvl_cli/{_name(face)} has no docstring"
    first, *rest = docstring.splitlines()
    assert first.endswith(".") and (not rest or rest[0] == ""), first


@pytest.mark.parametrize("face", FACES, ids=_name)
def test_a_face_lists_its_modules_and_its_own_names(face: Path) -> None:
    tree = _tree(face)
    listed = _all(tree)
    assert len(listed) == len(set(listed)), "a name listed twice"
    modules = _modules(face.parent)
    assert modules <= set(listed), f"not in __all__: {sorted(modules - set(listed))}"
    strangers = set(listed) - modules - _bound(tree)
    assert not strangers, f"__all__ names what is neither module nor bound: {sorted(strangers)}"


@pytest.mark.parametrize("face", FACES, ids=_name)
def test_a_face_imports_nothing_but_what_it_must(face: Path) -> None:
    allowed = IMPORTING.get(_name(face), set())
    wrong = [
        name
        for name in imports(face)
        if not any(name == module or name.startswith(f"{module}.") for module in allowed)
    ]
    assert not wrong, f"tvl_cli/{_name(face)}/__init__.py imports {wrong}"


def test_a_module_name_says_its_room_but_for_a_verbs_pair() -> None:
    # A name met in two rooms would make the reader ask which: only a verb has two modules,
    # its command line in cli/ and its work in commands/.
    rooms_of: dict[str, list[str]] = {}
    for path in PACKAGE.glob("**/*.py"):
        if path.stem != "__init__":
            rooms_of.setdefault(path.stem, []).append(path.parent.relative_to(PACKAGE).as_posix())
    shared = {name: sorted(rooms) for name, rooms in rooms_of.items() if len(rooms) > 1}
    verbs_pairs = {name for name, rooms in shared.items() if rooms == ["cli", "commands"]}
    assert verbs_pairs <= set(COMMANDS), f"pairs that are not verbs: {verbs_pairs - set(COMMANDS)}"
    assert shared.keys() == verbs_pairs, f"names in two rooms: {shared}"


@pytest.mark.parametrize("verb", sorted(COMMANDS))
def test_each_verbs_command_line_is_the_module_of_its_name(verb: str) -> None:
    assert (PACKAGE / "cli" / f"{verb}.py").is_file()
    assert command_named(verb).name == verb


# Test folders that are not a room's: the files tests read, and the numpy references the
# kernels are checked against.
TEST_FOLDERS_NOT_ROOMS = {"data", "kernel_references"}


def test_the_test_tree_has_a_folder_for_each_room_and_no_other() -> None:
    tests = Path(__file__).resolve().parent
    rooms = {path.parent.name for path in PACKAGE.glob("*/__init__.py")}
    folders = {path.name for path in tests.iterdir() if path.is_dir() and path.name[0] != "_"}
    assert folders - TEST_FOLDERS_NOT_ROOMS == rooms
