"""The paper's method is said in one place, core/method.py: no other module, benchmark or
experiment script defines a piece of it (a constant for its deceleration, a flag set standing
for `--paper`). Docstrings and comments may speak of the paper; code names only the preset."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
HOME = ROOT / "tvl_cli" / "core" / "method.py"
# Names with "paper" in them that are no part of the paper's method, each for a reason.
NOT_THE_METHOD = {
    "PAPER": "the preset itself, imported from core.method",
    "PAPER_NAME": "the preset's name, imported from core.method",
    "paper": "the --paper flag's value, and text quoting the paper's figures",
    "PAPER_FIG21": "the paper's reported results, which figures are drawn against",
    "PAPER_FIG27": "the paper's reported results, which figures are drawn against",
    "PAPER_COLOUR": "how figures draw the paper's results",
    "check_paper_runs": "a grid's check that reflexes and memory do not contradict the preset",
}
# Package modules where the word itself stands as a value: the ablation figure labels the runs
# of the paper's method with it (experiments/grids/ablation.toml). (Benchmarks label their
# columns and settings with it freely.)
PAPER_AS_A_LABEL = {"tvl_cli/analysis/ablation_table.py"}


def _sources() -> list[Path]:
    found = sorted((ROOT / "tvl_cli").rglob("*.py")) + sorted((ROOT / "benchmarks").glob("*.py"))
    return [path for path in found if path != HOME]


def _names(tree: ast.AST) -> list[tuple[int, str]]:
    """(line, name) of every identifier the module binds, reads, imports or passes."""
    found: list[tuple[int, str]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Name):
            found.append((node.lineno, node.id))
        elif isinstance(node, ast.Attribute):
            found.append((node.lineno, node.attr))
        elif isinstance(node, ast.FunctionDef | ast.ClassDef):
            found.append((node.lineno, node.name))
        elif isinstance(node, ast.arg):
            found.append((node.lineno, node.arg))
        elif isinstance(node, ast.alias):
            found.append((0, node.asname or node.name))
        elif isinstance(node, ast.keyword) and node.arg:
            found.append((node.value.lineno, node.arg))
    return found


@pytest.mark.parametrize("path", _sources(), ids=lambda p: str(p.relative_to(ROOT)))
def test_no_module_but_core_method_names_a_piece_of_the_papers_method(path: Path) -> None:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    named = {
        f"{path.relative_to(ROOT)}:{line}: {name}"
        for line, name in _names(tree)
        if "paper" in name.lower() and name not in NOT_THE_METHOD
    }
    assert not named, "say it in core/method.py (PAPER), or name PAPER's field"
    literal = [
        node.lineno
        for node in ast.walk(tree)
        if isinstance(node, ast.Constant) and node.value == "paper"
    ]
    where = str(path.relative_to(ROOT))
    if where.startswith("tvl_cli/") and where not in PAPER_AS_A_LABEL:
        assert not literal, f"{path}: lines {literal}: name the preset by PAPER_NAME"


# Options that set a choice of the method; a script beside `paper` picks the method instead.
METHOD_OPTIONS = re.compile(r"--(decel|margin|near|explore|memory|reflex)\b")


@pytest.mark.parametrize(
    "path",
    sorted((ROOT / "experiments").rglob("*.sh")) + sorted((ROOT / "docs").glob("*.sh")),
    ids=lambda p: str(p.relative_to(ROOT)),
)
def test_scripts_take_the_papers_method_by_name(path: Path) -> None:
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1):
        code = line.split("#", 1)[0]
        if "paper" in code:
            assert not METHOD_OPTIONS.search(code), f"{path}:{number}: {line.strip()}"


def test_the_scan_finds_a_second_definition() -> None:
    planted = ast.parse("from x import y\nPAPER_NEAR_M = 0.0\nLearnParams(paper_near=1)\n")
    assert {name for _, name in _names(planted) if "paper" in name.lower()} == {
        "PAPER_NEAR_M",
        "paper_near",
    }
