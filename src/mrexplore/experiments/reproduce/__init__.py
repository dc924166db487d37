"""One-command reproductions of the papers' experiments (DESIGN §9):
``mrexplore reproduce ID --out DIR [--quick]``, ids in :data:`MODULES`.
"""

from __future__ import annotations

import importlib

from mrexplore.errors import UnknownIdError
from mrexplore.experiments.reproduce.base import Reproduction, reproduce
from mrexplore.experiments.reproduce.claims import Verdict

MODULES = {
    paper: f"mrexplore.experiments.reproduce.{paper}"
    for paper in ("sheng2006", "vazquez2005", "wu2011", "market2018", "meier2006")
}


def get_reproduction(paper_id: str) -> Reproduction:
    """The reproduction of a paper by id (its module defines ``REPRODUCTION``)."""
    if paper_id not in MODULES:
        raise UnknownIdError("reproduction", paper_id, list(MODULES))
    reproduction: Reproduction = importlib.import_module(MODULES[paper_id]).REPRODUCTION
    return reproduction


__all__ = ["MODULES", "Reproduction", "Verdict", "get_reproduction", "reproduce"]
