"""The parameter tables in the docs and docstrings are rendered from the code."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import ClassVar

import pytest

from mrexplore.strategies import Param
from mrexplore.strategies.base import FrontierStrategy
from mrexplore.strategies.doc import (
    builtin_strategies,
    docstring_table,
    markdown_table,
    refresh,
    refreshed_page,
)

ROOT = Path(__file__).resolve().parents[1]


def test_every_page_and_docstring_table_is_current() -> None:
    stale = refresh(ROOT, write=False)
    assert stale == [], (
        f"stale parameter tables in {[str(p) for p in stale]}: "
        "run `python -m mrexplore.strategies.doc`"
    )


def test_every_builtin_strategy_has_a_page_with_a_block() -> None:
    for cls in builtin_strategies():
        page = ROOT / "docs" / "strategies" / f"{cls.id}.md"
        assert "<!-- params:begin -->" in page.read_text(encoding="utf-8"), cls.id


class _Toy(FrontierStrategy):
    id = "toy"
    params: ClassVar[Mapping[str, Param]] = {
        "alpha": Param(0.5, "cells", "short help", "α", low=0, note="the long | meaning"),
        "mode": Param("a", "", "a or b", choices=("a", "b")),
    }


def test_tables_show_every_declared_field() -> None:
    table = markdown_table(_Toy)
    assert "| α | `alpha` | 0.5 | cells | a finite number >= 0 | the long \\| meaning |" in table
    assert "| - | `mode` | `a` | - | one of a, b | a or b |" in table
    lines = docstring_table(_Toy, width=50).splitlines()
    assert max(len(line) for line in lines) <= 50
    assert lines[1].split() == ["name", "symbol", "default", "unit", "meaning"]


def test_a_page_without_its_block_is_refused() -> None:
    with pytest.raises(ValueError, match="params:begin"):
        refreshed_page("# toy\n", _Toy)
    page = "# toy\n\n<!-- params:begin -->\nold\n<!-- params:end -->\n\nkept\n"
    fresh = refreshed_page(page, _Toy)
    assert "old" not in fresh and fresh.endswith("<!-- params:end -->\n\nkept\n")
