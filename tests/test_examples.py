"""The examples in docs/*.md run as tests (scikit-fem's practice): every ```python block of a page
runs, in order, in one namespace per page, from the repository root. The pages check their own
numbers with asserts against the equations they quote; a page that stops running fails here."""
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = sorted((ROOT / "docs").glob("*.md"))
BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)


def test_every_page_has_an_example():
    assert PAGES, "docs/ has no pages"
    for page in PAGES:
        assert BLOCK.search(page.read_text()), f"{page.name} has no ```python block"


@pytest.mark.parametrize("page", PAGES, ids=[p.name for p in PAGES])
def test_page_runs(page, monkeypatch):
    monkeypatch.chdir(ROOT)
    namespace = {"__name__": f"docs_{page.stem}"}
    for k, block in enumerate(BLOCK.findall(page.read_text())):
        exec(compile(block, f"{page.name}[block {k}]", "exec"), namespace)
