"""Link models: which robots can hear each other directly.

A link model is the physical layer of a communication model. It sees where the
robots are (and, for line-of-sight blocking, the walls: the simulator hands it
the ground truth, which no strategy ever sees) and returns the set of direct
links. Sub-networks are the connected components of that link graph.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Mapping
from typing import ClassVar

import numpy as np
import numpy.typing as npt

from mrexplore.sensing import is_visible

Cell = tuple[int, int]
Link = tuple[int, int]

_SMALL_TEAM = 32
"""Up to this many robots, range links are computed in plain Python (faster than numpy)."""


class LinkModel(ABC):
    """Decides the direct links between live robots.

    A link model whose links lose receptions depending on the link itself (distance,
    walls, a packet's length) sets :attr:`lossy` and implements
    :meth:`delivery_probability`; :class:`~mrexplore.comm.models.Network` then loses
    each reception over a link with one minus that probability.
    """

    lossy: ClassVar[bool] = False
    """Whether :meth:`delivery_probability` can be below 1."""

    @abstractmethod
    def links(self, positions: Mapping[int, Cell]) -> frozenset[Link]:
        """Direct links ``(a, b)`` with ``a < b`` between the given (live) robots."""

    @abstractmethod
    def describe(self) -> str:
        """A short description for reports."""

    def delivery_probability(self, transmitter: int, receiver: int, n_bytes: int) -> float:
        """Probability that one transmission of ``n_bytes`` by robot ``transmitter`` is
        received by robot ``receiver`` over one of the links of the last :meth:`links`
        call (1 unless :attr:`lossy`)."""
        return 1.0

    def signal_strength(self, a: Cell, b: Cell) -> float:
        """Received signal strength between two cells, relative to 1 at one cell.

        Vazquez & Malcolm §3.1.2: proportional to 1/d^2 (d in cells; inf at d = 0).
        """
        d2 = float((a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2)
        return math.inf if d2 == 0 else 1.0 / d2


class AllLinks(LinkModel):
    """Unlimited range: every pair of live robots is linked."""

    def __init__(self) -> None:
        self._last: tuple[tuple[int, ...], frozenset[Link]] = ((), frozenset())

    def links(self, positions: Mapping[int, Cell]) -> frozenset[Link]:
        ids = tuple(sorted(positions))
        if ids != self._last[0]:  # the same live robots: the same pairs as last time
            pairs = frozenset((a, b) for i, a in enumerate(ids) for b in ids[i + 1 :])
            self._last = (ids, pairs)
        return self._last[1]

    def describe(self) -> str:
        return "unlimited range"


class RangeLinks(LinkModel):
    """Robots within ``comm_range`` cells (Euclidean) are linked.

    With ``line_of_sight`` a link also needs a clear straight line between the two
    cells (the sensor's line-of-sight rule, both ways: walls block radio).
    """

    def __init__(
        self,
        comm_range: float,
        *,
        line_of_sight: bool = False,
        occupied: npt.NDArray[np.bool_] | None = None,
    ) -> None:
        if line_of_sight and occupied is None:
            raise ValueError("line-of-sight links need the occupancy grid")
        self.comm_range = float(comm_range)
        self.line_of_sight = line_of_sight
        self.occupied = occupied

    def links(self, positions: Mapping[int, Cell]) -> frozenset[Link]:
        ids = sorted(positions)
        if len(ids) < 2:
            return frozenset()
        # A product, not ``**``: float ``**`` raises OverflowError past 1.8e308 (a range
        # of 1e308 cells) where a product gives inf, and every pair is then in range.
        limit = self.comm_range * self.comm_range
        pairs: list[tuple[int, int]]
        if len(ids) <= _SMALL_TEAM:
            # Plain Python beats numpy's set-up costs for a few robots; integer cells
            # give the same squared distances exactly.
            cells = [(float(positions[i][0]), float(positions[i][1])) for i in ids]
            pairs = [
                (ids[i], ids[j])
                for i in range(len(ids))
                for j in range(i + 1, len(ids))
                if (cells[i][0] - cells[j][0]) ** 2 + (cells[i][1] - cells[j][1]) ** 2 <= limit
            ]
        else:
            array = np.array([positions[i] for i in ids], dtype=np.float64)
            d2 = ((array[:, None, :] - array[None, :, :]) ** 2).sum(axis=-1)
            close = np.argwhere(np.triu(d2 <= limit, k=1))
            pairs = [(ids[i], ids[j]) for i, j in close.tolist()]
        out = []
        for a, b in pairs:
            if self.line_of_sight:
                assert self.occupied is not None
                if not (
                    is_visible(self.occupied, positions[a], positions[b])
                    and is_visible(self.occupied, positions[b], positions[a])
                ):
                    continue
            out.append((a, b))
        return frozenset(out)

    def describe(self) -> str:
        walls = ", walls block" if self.line_of_sight else ""
        return f"range {self.comm_range:g} cells{walls}"


def components(nodes: frozenset[int], links: frozenset[Link]) -> list[frozenset[int]]:
    """Connected components of the link graph, each sorted by its lowest id.

    >>> components(frozenset({0, 1, 2, 3}), frozenset({(0, 2)}))
    [frozenset({0, 2}), frozenset({1}), frozenset({3})]
    """
    parent = {n: n for n in nodes}

    def find(n: int) -> int:
        while parent[n] != n:
            parent[n] = parent[parent[n]]
            n = parent[n]
        return n

    for a, b in links:
        ra, rb = find(a), find(b)
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)
    groups: dict[int, set[int]] = {}
    for n in sorted(nodes):
        groups.setdefault(find(n), set()).add(n)
    return [frozenset(g) for _, g in sorted(groups.items())]
