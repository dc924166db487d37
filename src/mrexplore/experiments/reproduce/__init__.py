"""One-command reproductions of the papers' experiments (DESIGN §9):
``mrexplore reproduce ID --out DIR [--quick]``, ids in :data:`REPRODUCTIONS`.

Each built-in reproduction's module defines ``REPRODUCTION`` and is imported on
first use; third-party packages add theirs through the entry-point group
``mrexplore.reproductions`` (each entry point naming a :class:`Reproduction`).
"""

from __future__ import annotations

from mrexplore.experiments.reproduce.base import Reproduction, reproduce
from mrexplore.experiments.reproduce.claims import Verdict
from mrexplore.registry import Registry

MODULES = {
    paper: f"mrexplore.experiments.reproduce.{paper}"
    for paper in ("sheng2006", "vazquez2005", "wu2011", "market2018", "meier2006")
}
"""The built-in reproductions' modules by paper id."""

REPRODUCTIONS: Registry[Reproduction] = Registry(
    "reproduction",
    "mrexplore.reproductions",
    summary_of=lambda reproduction: reproduction.title,
)
"""Reproductions by paper id (``mrexplore reproduce ID``)."""
for _paper, _module in MODULES.items():
    REPRODUCTIONS.register_lazy(_paper, f"{_module}:REPRODUCTION")


def get_reproduction(paper_id: str) -> Reproduction:
    """The reproduction of a paper by id (:class:`~mrexplore.errors.UnknownIdError` if
    there is none)."""
    return REPRODUCTIONS.get(paper_id)


__all__ = ["MODULES", "REPRODUCTIONS", "Reproduction", "Verdict", "get_reproduction", "reproduce"]
