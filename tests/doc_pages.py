"""The documentation's text, for the tests that hold it to the code: the README and the pages
of the site under docs/ (mkdocs.yml)."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def page(name: str) -> str:
    """README.md, or a page of the site by its path under docs/ (`guide/behaving.md`)."""
    path = ROOT / name if name == "README.md" else ROOT / "docs" / name
    return path.read_text(encoding="utf-8")


def every_page() -> dict[str, str]:
    """The README and every page of the site, by the name `page` takes."""
    pages = {"README.md": page("README.md")}
    for path in sorted((ROOT / "docs").rglob("*.md")):
        name = path.relative_to(ROOT / "docs").as_posix()
        pages[name] = path.read_text(encoding="utf-8")
    return pages


def _headings(text: str) -> list[tuple[int, int, str]]:
    """(line index, level, title) of each markdown heading outside fenced code."""
    found, fenced = [], False
    for index, line in enumerate(text.splitlines()):
        if line.startswith("```"):
            fenced = not fenced
        elif not fenced and (match := re.match(r"^(#+) (.*)$", line)):
            found.append((index, len(match.group(1)), match.group(2).strip()))
    return found


def section(text: str, title: str) -> str:
    """The text under the heading `title`, at whatever level, up to the next heading of the
    same level or above."""
    lines, headings = text.splitlines(keepends=True), _headings(text)
    (start, level) = next((i, lv) for i, lv, t in headings if t == title)
    end = next((i for i, lv, _ in headings if i > start and lv <= level), len(lines))
    return "".join(lines[start + 1 : end])


def code_blocks(text: str, language: str) -> list[str]:
    """The fenced code blocks of `text` in `language` (```python, ```sh)."""
    return re.findall(rf"^```{re.escape(language)}\n(.*?)^```", text, flags=re.M | re.S)
