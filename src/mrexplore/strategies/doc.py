"""Parameter tables of the strategies, rendered from their declarations.

Every parameter is declared once, as a :class:`~mrexplore.strategies.base.Param` in
its strategy's ``params``. The tables in the strategy modules' docstrings and in
``docs/strategies/<id>.md`` are rendered from those declarations into a marked block
(``.. params:begin <id>`` / ``.. params:end`` in a docstring, ``<!-- params:begin -->`` /
``<!-- params:end -->`` in a page); nothing else of the page or docstring is touched.

    python -m mrexplore.strategies.doc            # rewrite the stale blocks
    python -m mrexplore.strategies.doc --check    # list them; exit status 1 if any

run from the root of a source checkout (``--root`` names another). The test suite
runs the check, so a table cannot drift from the code.
"""

from __future__ import annotations

import argparse
import inspect
import math
import re
import sys
import textwrap
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from mrexplore.strategies.base import Param, ReplanRules, Strategy, declared_params

PAGE_BEGIN = "<!-- params:begin -->"
PAGE_END = "<!-- params:end -->"
DOCSTRING_BEGIN = ".. params:begin"
DOCSTRING_END = ".. params:end"
LINE_LENGTH = 100
"""The source's line length (ruff): a docstring table wraps its last column to fit."""


def value_text(value: Any) -> str:
    """A default as a user types it after ``--set``.

    >>> value_text(True), value_text(0.5), value_text(math.inf), value_text("team")
    ('true', '0.5', 'inf', 'team')
    """
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float) and math.isinf(value):
        return "inf" if value > 0 else "-inf"
    return str(value)


def meaning(spec: Param) -> str:
    """The table's meaning of a parameter: its note, else its help."""
    return spec.note or spec.help


def markdown_table(cls: type[Strategy]) -> str:
    """The parameter table of ``cls`` for its doc page (Markdown)."""
    lines = [
        "| symbol | name | default | unit | values | meaning |",
        "|---|---|---|---|---|---|",
    ]
    for name, spec in cls.params.items():
        default = value_text(spec.default)
        if isinstance(spec.default, str):
            default = f"`{default}`"
        cells = (
            spec.symbol or "-",
            f"`{name}`",
            default,
            spec.unit or "-",
            spec.describe(),
            meaning(spec).replace("|", "\\|"),
        )
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def shared_groups() -> dict[str, Mapping[str, Param[Any]]]:
    """Parameter groups that several strategies inherit, by the dotted name of the
    class that declares them.

    A docstring table gives each group one row that points to it (the doc pages list
    every parameter)."""
    from mrexplore.strategies.fallback import FallbackRules
    from mrexplore.strategies.utility import UtilityDiscounting

    return {
        f"{group.__module__}.{group.__name__}": declared_params(group)
        for group in (ReplanRules, FallbackRules, UtilityDiscounting)
    }


def _docstring_rows(cls: type[Strategy]) -> list[tuple[str, str, str, str, str]]:
    """One row per own parameter, and per shared parameter whose default ``cls``
    changes; one row per shared group for the rest of its members."""
    rows: list[tuple[str, str, str, str, str]] = []
    done: set[str] = set()
    groups = shared_groups()
    for name, spec in cls.params.items():
        group = next((g for g, members in groups.items() if name in members), None)
        if group is None or spec.default != groups[group][name].default:
            default = value_text(spec.default)
            rows.append(
                (f"``{name}``", spec.symbol or "-", default, spec.unit or "-", meaning(spec))
            )
        elif group not in done:
            done.add(group)
            module, label = group.rsplit(".", 1)
            rows.append((label, "-", "", "", f"shared: ``{module.removeprefix('mrexplore.')}``"))
    return rows


def docstring_table(cls: type[Strategy], width: int = LINE_LENGTH) -> str:
    """The parameter table of ``cls`` for its module docstring (a reST simple table
    whose last column wraps to keep every line within ``width``); a group of shared
    parameters (:func:`shared_groups`) takes one row."""
    header = ("name", "symbol", "default", "unit", "meaning")
    rows = _docstring_rows(cls)
    widths = [max(len(header[i]), *(len(row[i]) for row in rows)) for i in range(4)]
    last = width - sum(widths) - 2 * len(widths)
    last = max(len(header[4]), min(last, max(len(row[4]) for row in rows)))
    rule = "  ".join("=" * w for w in [*widths, last])

    def line(cells: Sequence[str]) -> str:
        return "  ".join(c.ljust(w) for c, w in zip(cells, [*widths, last], strict=True)).rstrip()

    out = [rule, line(header), rule]
    for row in rows:
        wrapped = textwrap.wrap(row[4], last, break_long_words=False) or [""]
        out.append(line([*row[:4], wrapped[0]]))
        out += [line(["", "", "", "", more]) for more in wrapped[1:]]
    out.append(rule)
    return "\n".join(out)


def _replace_block(text: str, begin: str, end: str, body: str, where: str) -> str:
    pattern = re.compile(re.escape(begin) + r"\n.*?" + re.escape(end), re.DOTALL)
    if len(pattern.findall(text)) != 1:
        raise ValueError(f"{where}: expected one block '{begin}' ... '{end}'")
    return pattern.sub(lambda _: f"{begin}\n\n{body}\n\n{end}", text)


def refreshed_page(text: str, cls: type[Strategy]) -> str:
    """``text`` (a doc page) with its parameter block rendered anew."""
    body = (
        f"Generated from `{cls.__name__}.params` by `python -m mrexplore.strategies.doc`: "
        "change the declaration, not this table.\n\n" + markdown_table(cls)
    )
    return _replace_block(text, PAGE_BEGIN, PAGE_END, body, f"page of {cls.id}")


def refreshed_source(text: str, cls: type[Strategy]) -> str:
    """``text`` (a module's source) with the docstring block of ``cls`` rendered anew."""
    begin = f"{DOCSTRING_BEGIN} {cls.id}"
    return _replace_block(text, begin, DOCSTRING_END, docstring_table(cls), f"{cls.__name__}")


def builtin_strategies() -> list[type[Strategy]]:
    """The strategies that ship with mrexplore (plugins have their own docs)."""
    from mrexplore.strategies import available_strategies

    return [
        cls
        for cls in available_strategies().values()
        if cls.__module__.startswith("mrexplore.strategies.")
    ]


def refresh(root: Path, *, write: bool) -> list[Path]:
    """The pages under ``root/docs/strategies`` and the strategy modules whose parameter
    blocks are stale; with ``write``, rewrite them."""
    updated: dict[Path, str] = {}
    stale: list[Path] = []
    for cls in builtin_strategies():
        source = Path(inspect.getfile(cls))
        page = root / "docs" / "strategies" / f"{cls.id}.md"
        for path, render in ((page, refreshed_page), (source, refreshed_source)):
            text = updated.get(path, path.read_text(encoding="utf-8"))
            updated[path] = render(text, cls)
    for path, text in updated.items():
        if path.read_text(encoding="utf-8") != text:
            stale.append(path)
            if write:
                path.write_text(text, encoding="utf-8")
    return stale


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m mrexplore.strategies.doc")
    parser.add_argument("--check", action="store_true", help="only list the stale files")
    parser.add_argument("--root", type=Path, default=Path.cwd(), help="source checkout")
    args = parser.parse_args(argv)
    stale = refresh(args.root, write=not args.check)
    for path in stale:
        sys.stdout.write(f"{'stale' if args.check else 'rewrote'}: {path}\n")
    return 1 if stale and args.check else 0


if __name__ == "__main__":
    sys.exit(main())
