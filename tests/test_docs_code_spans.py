"""The documentation's tables show their code as written: rendered as the site renders its
tables (Python-Markdown's), no page shows a literal `\\|` (a pipe escaped for GitHub, which
the site prints as it is). Skipped without the `docs` extra."""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = sorted((ROOT / "docs").rglob("*.md"))


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_no_page_shows_an_escaped_pipe(page: Path) -> None:
    markdown = pytest.importorskip("markdown")
    html = markdown.markdown(page.read_text(encoding="utf-8"), extensions=["tables"])
    assert "\\|" not in html, [line for line in html.splitlines() if "\\|" in line][:3]
