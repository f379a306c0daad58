"""The documentation site builds with every link and anchor checked (`mkdocs build --strict`),
and its references are generated from the code: every `tvl` command in the command-line
reference, every module of the package in the API reference. Skipped without the `docs` extra."""

from __future__ import annotations

import ast
import html
import os
import re
import subprocess
import sys
from importlib.util import find_spec
from pathlib import Path

import pytest
from doc_pages import ROOT

from tvl_cli.cli.main import COMMANDS

MISSING = [
    name for name in ("mkdocs", "mkdocs_click", "mkdocstrings_handlers") if not find_spec(name)
]

pytestmark = [
    pytest.mark.slow,  # a few seconds
    pytest.mark.skipif(
        bool(MISSING), reason=f"the docs extra is not installed ({', '.join(MISSING)})"
    ),
]


def _text(page: Path) -> str:
    """A built page's text, without its markup."""
    return html.unescape(re.sub(r"<[^>]+>", "", page.read_text(encoding="utf-8")))


def test_the_site_builds_strictly_with_generated_references(tmp_path: Path) -> None:
    site = tmp_path / "site"
    done = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(site)],
        cwd=ROOT,
        env={**os.environ, "NO_MKDOCS_2_WARNING": "1"},
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    cli = _text(site / "reference" / "cli" / "index.html")
    for name in COMMANDS:
        assert f"tvl {name} [OPTIONS]" in cli
    # Every public module of every room but the command line's, which the CLI page covers.
    package = ROOT / "tvl_cli"
    for module in package.rglob("*.py"):
        room = module.relative_to(package).parts[0]
        if room in ("cli", "__init__.py") or module.name.startswith("_"):
            continue
        dotted = ".".join(module.relative_to(ROOT).with_suffix("").parts)
        api = (site / "reference" / "api" / room / "index.html").read_text(encoding="utf-8")
        assert f'id="{dotted}"' in api, dotted
    # Every room's page opens with the room's own summary line, then a table of its modules.
    for face in sorted(package.glob("*/__init__.py")):
        room = face.parent.name
        if room == "cli":
            continue
        docstring = ast.get_docstring(ast.parse(face.read_text(encoding="utf-8")))
        assert docstring, f"tvl_cli/{room}/__init__.py has no docstring"
        summary = docstring.splitlines()[0].replace("`", "")  # code spans lose their marks
        page = _text(site / "reference" / "api" / room / "index.html")
        assert summary in page and "Modules:" in page, room
