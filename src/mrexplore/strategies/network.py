"""What a robot knows of its sub-network's topology: hop counts and the waits they set.

Every robot knows the links of its own sub-network (:attr:`RobotView.links
<mrexplore.strategies.base.RobotView>`); strategies that wait for answers size
their waits by the hops a message needs (``comm_latency`` ticks per hop).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable

from mrexplore.strategies.base import RobotView


def hop_distances(source: int, links: Iterable[tuple[int, int]]) -> dict[int, int]:
    """Hops from ``source`` to every robot it reaches over ``links`` (itself: 0).

    >>> hop_distances(0, [(0, 1), (1, 2), (3, 4)])
    {0: 0, 1: 1, 2: 2}
    """
    neighbours: dict[int, list[int]] = {}
    for a, b in links:
        neighbours.setdefault(a, []).append(b)
        neighbours.setdefault(b, []).append(a)
    hops = {source: 0}
    queue = deque([source])
    while queue:
        node = queue.popleft()
        for nxt in neighbours.get(node, ()):
            if nxt not in hops:
                hops[nxt] = hops[node] + 1
                queue.append(nxt)
    return hops


def hop_diameter(members: Iterable[int], links: Iterable[tuple[int, int]]) -> int:
    """Largest number of hops between two robots of a connected sub-network.

    >>> hop_diameter([0, 1, 2, 3], [(0, 1), (1, 2), (2, 3)])
    3
    """
    link_list = list(links)
    return max((max(hop_distances(m, link_list).values()) for m in members), default=0)


def hops_from(source: int, members: Iterable[int], links: Iterable[tuple[int, int]]) -> int:
    """Largest hop count from ``source`` to a member of its sub-network (0 when alone).

    Only links between members count; a member no link reaches counts one hop more
    per such member (unknown topology: assume a chain).

    >>> hops_from(0, {0, 1, 2}, {(0, 1), (1, 2)}), hops_from(0, {0, 1, 2}, {(0, 1)})
    (2, 2)
    """
    team = set(members)
    depth = hop_distances(source, [(a, b) for a, b in links if a in team and b in team])
    unreached = len(team) - len(depth)
    return max(depth.values()) + unreached


def round_timeout(given: int, view: RobotView, source: int) -> int:
    """Ticks a round opened by ``source`` waits for answers: ``given``, or when 0 a
    message there and back to the farthest member, ``2 x latency x hops + 1``."""
    if given > 0:
        return given
    return 2 * view.comm_latency * hops_from(source, view.subnetwork, view.links) + 1


def request_timeout(given: int, round_ticks: int) -> int:
    """Ticks before a robot asks again: ``given``, or when 0 two rounds and two ticks.

    >>> request_timeout(0, 3), request_timeout(7, 3)
    (8, 7)
    """
    return given if given > 0 else 2 * round_ticks + 2
