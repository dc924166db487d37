"""Map quality: how much of what the robots believe is true (DESIGN §7).

After Z. Yan, L. Fabresse, J. Laval, N. Bouraqadi, "Metrics for performance
benchmarking of multi-robot exploration", IEEE/RSJ IROS 2015, whose benchmark
judges an exploration by the quality of the map it leaves as well as by its time
and cost. The definitions below are this module's.

A *map* is an ``H x W`` int8 belief (:mod:`mrexplore.grid.occupancy`: ``UNKNOWN =
-1``, ``FREE = 0``, ``OCCUPIED = 100``); a cell is *known* in it unless it is
``UNKNOWN``, and a known cell other than ``FREE`` counts as occupied. The truth is a
boolean ``H x W`` grid (``True`` = occupied) and the explorable cells a boolean mask
(free cells reachable from the start cells, the cells coverage counts).

==================  ==============================================  ================
name                definition                                      code
==================  ==============================================  ================
team map            a cell is known if any robot's map knows it;    :func:`team_map`
                    its value is the one most of the robots that
                    know it hold, ``OCCUPIED`` on a tie
known               cells the map knows                             :class:`MapQuality`
wrong               known cells whose value disagrees with the      :class:`MapQuality`
                    truth (free held occupied, or occupied free)
correct             explorable cells the map holds ``FREE``         :class:`MapQuality`
error fraction      wrong / known (0 when nothing is known)         :class:`MapQuality`
correct fraction    correct / explorable cells                      :class:`MapQuality`
==================  ==============================================  ================

The team map breaks a tie towards ``OCCUPIED``: a robot told that a cell may be a
wall keeps away from it, which is the safe mistake. With perfect sensing and
localisation, every robot holds the truth wherever it knows anything (with every
sharing mechanism but ``polygon``), so the error fraction is 0 and the correct
fraction is the explored fraction; the maps ``polygon`` sharing rebuilds from
polygons, and imperfect robots (:mod:`mrexplore.sim.noise`), make them differ.

:func:`team_counts` counts the team map's known, wrong and correct cells without
building it (the simulator calls it every tick of a noisy run, through
:class:`TeamCounter`); it equals :func:`map_quality` of :func:`team_map`.

>>> import numpy as np
>>> from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN
>>> truth = np.array([[True, False, False]])
>>> explorable = np.array([[False, True, True]])
>>> a = np.array([[OCCUPIED, FREE, UNKNOWN]], dtype=np.int8)
>>> b = np.array([[FREE, OCCUPIED, UNKNOWN]], dtype=np.int8)
>>> team_map([a, b]).tolist()  # a tie on both known cells: occupied
[[100, 100, -1]]
>>> quality = map_quality(a, truth, explorable)
>>> quality.known, quality.wrong, quality.correct, quality.correct_fraction
(2, 0, 1, 0.5)
>>> team_counts([a, b], truth, explorable)  # the wall is right, the free cell wrong
(2, 1, 0)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numba
import numpy as np
import numpy.typing as npt

from mrexplore.errors import MrexploreInputError
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN

__all__ = [
    "MapQuality",
    "TeamCounter",
    "map_quality",
    "map_quality_metrics",
    "team_counts",
    "team_map",
]

Belief = npt.NDArray[np.int8]
"""One map, ``H x W``."""
Beliefs = npt.NDArray[np.int8]
"""The maps of a team, ``N x H x W``."""


@dataclass(frozen=True)
class MapQuality:
    """The counts of one map (a robot's, or the team's) against the truth."""

    known: int
    """Cells the map knows (not ``UNKNOWN``)."""
    wrong: int
    """Known cells whose value disagrees with the truth."""
    correct: int
    """Explorable cells the map holds ``FREE``."""
    explorable: int
    """Explorable cells of the world."""

    @property
    def error_fraction(self) -> float:
        """``wrong / known``; 0.0 when the map knows nothing."""
        return self.wrong / self.known if self.known else 0.0

    @property
    def correct_fraction(self) -> float:
        """``correct / explorable``; 0.0 when nothing is explorable."""
        return self.correct / self.explorable if self.explorable else 0.0


# ------------------------------------------------------------------------ kernels


@numba.njit(cache=True, nogil=True)
def _map_counts(
    belief: Belief, truth: npt.NDArray[np.bool_], explorable: npt.NDArray[np.bool_]
) -> tuple[int, int, int]:  # pragma: no cover - compiled
    """``(known, wrong, correct)`` of one map."""
    known = 0
    wrong = 0
    correct = 0
    height, width = belief.shape
    for row in range(height):
        for col in range(width):
            value = belief[row, col]
            if value == UNKNOWN:
                continue
            known += 1
            occupied = value != FREE
            if occupied != truth[row, col]:
                wrong += 1
            if not occupied and explorable[row, col]:
                correct += 1
    return known, wrong, correct


@numba.njit(cache=True, nogil=True)
def _tally_row(
    beliefs: Beliefs,
    row: int,
    free_votes: npt.NDArray[np.int32],
    occupied_votes: npt.NDArray[np.int32],
) -> None:  # pragma: no cover - compiled
    """How many maps of ``beliefs`` (``N x H x W``) hold each cell of ``row`` free, and
    how many occupied: row by row, so that each map is read in order and no ``H x W``
    array is built."""
    free_votes[:] = 0
    occupied_votes[:] = 0
    width = free_votes.shape[0]
    for k in range(beliefs.shape[0]):
        for col in range(width):  # branch-free: noisy maps mix the values unpredictably
            value = beliefs[k, row, col]
            free_votes[col] += value == FREE
            occupied_votes[col] += (value != FREE) & (value != UNKNOWN)


@numba.njit(cache=True, nogil=True)
def _team_map(beliefs: Beliefs, out: Belief) -> None:  # pragma: no cover - compiled
    """Fill ``out`` with the team map of ``beliefs`` (``N x H x W``)."""
    height, width = out.shape
    free_votes = np.zeros(width, dtype=np.int32)
    occupied_votes = np.zeros(width, dtype=np.int32)
    for row in range(height):
        _tally_row(beliefs, row, free_votes, occupied_votes)
        for col in range(width):
            free, occupied = free_votes[col], occupied_votes[col]
            if free + occupied == 0:
                out[row, col] = UNKNOWN
            elif occupied >= free:
                out[row, col] = OCCUPIED
            else:
                out[row, col] = FREE


@numba.njit(cache=True, nogil=True)
def _team_counts(
    beliefs: Beliefs, truth: npt.NDArray[np.bool_], explorable: npt.NDArray[np.bool_]
) -> tuple[int, int, int]:  # pragma: no cover - compiled
    """``(known, wrong, correct)`` of the team map of ``beliefs``, not built."""
    height, width = truth.shape
    free_votes = np.zeros(width, dtype=np.int32)
    occupied_votes = np.zeros(width, dtype=np.int32)
    known = 0
    wrong = 0
    correct = 0
    for row in range(height):
        _tally_row(beliefs, row, free_votes, occupied_votes)
        for col in range(width):
            free, occupied_count = free_votes[col], occupied_votes[col]
            if free + occupied_count == 0:
                continue
            known += 1
            occupied = occupied_count >= free
            if occupied != truth[row, col]:
                wrong += 1
            if not occupied and explorable[row, col]:
                correct += 1
    return known, wrong, correct


# ------------------------------------------------------------------ public functions


def _grid(name: str, array: npt.ArrayLike, shape: tuple[int, ...] | None) -> npt.NDArray[Any]:
    grid = np.asarray(array)
    if grid.ndim != 2 or (shape is not None and grid.shape != shape):
        expected = "a 2-D grid" if shape is None else f"shape {shape}"
        raise MrexploreInputError(
            f"map quality: {name} has shape {grid.shape}, expected {expected}"
        )
    return grid


def _beliefs(beliefs: Sequence[Belief] | Beliefs) -> list[Belief]:
    """The maps, checked: 2-D int8 grids of one shape."""
    if len(beliefs) == 0:
        raise MrexploreInputError("map quality: no belief maps given (a team has a robot)")
    grids = [_grid(f"belief {i}", belief, None) for i, belief in enumerate(beliefs)]
    for i, grid in enumerate(grids):
        if grid.dtype != np.int8:
            raise MrexploreInputError(
                f"map quality: belief {i} is {grid.dtype}, expected int8 (UNKNOWN / FREE / "
                "OCCUPIED of mrexplore.grid.occupancy)"
            )
        if grid.shape != grids[0].shape:
            raise MrexploreInputError(
                f"map quality: belief {i} has shape {grid.shape}, belief 0 {grids[0].shape}"
            )
    return grids


def _stacked(beliefs: Sequence[Belief] | Beliefs) -> Beliefs:
    """The maps as one C-contiguous ``N x H x W`` array (checked; not copied if it is
    one already)."""
    grids = _beliefs(beliefs)
    if isinstance(beliefs, np.ndarray) and beliefs.flags.c_contiguous:
        return beliefs
    return np.stack(grids)


def _truth_and_explorable(
    truth: npt.ArrayLike, explorable: npt.ArrayLike, shape: tuple[int, ...]
) -> tuple[npt.NDArray[np.bool_], npt.NDArray[np.bool_]]:
    truth_grid = np.ascontiguousarray(_grid("truth", truth, shape), dtype=bool)
    explorable_grid = np.ascontiguousarray(_grid("explorable", explorable, shape), dtype=bool)
    return truth_grid, explorable_grid


def team_map(beliefs: Sequence[Belief] | Beliefs) -> Belief:
    """The team's merged map of the robots' maps ``beliefs`` (each ``H x W`` int8).

    A cell is known to the team if any robot's map knows it; its value is the one
    most of the robots that know it hold (``FREE`` or ``OCCUPIED``; any other known
    value counts as ``OCCUPIED``), and ``OCCUPIED`` on a tie.

    >>> from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN
    >>> maps = np.array([[[FREE, UNKNOWN]], [[FREE, OCCUPIED]], [[OCCUPIED, UNKNOWN]]],
    ...                 dtype=np.int8)
    >>> team_map(maps).tolist()  # two robots against one; one robot alone
    [[0, 100]]

    Raises:
        MrexploreInputError: no maps, a map that is not a 2-D int8 grid, or maps of
            different shapes.
    """
    stack = _stacked(beliefs)
    out = np.empty(stack.shape[1:], dtype=np.int8)
    _team_map(stack, out)
    return out


def map_quality(belief: Belief, truth: npt.ArrayLike, explorable: npt.ArrayLike) -> MapQuality:
    """The known, wrong and correct cells of one map (see the module's table).

    ``truth`` is ``H x W``, truthy = occupied (the trace's uint8 ``truth`` will do);
    ``explorable`` is the ``H x W`` mask of explorable cells.

    Raises:
        MrexploreInputError: ``belief`` is not a 2-D int8 grid, or a grid's shape
            differs from the belief's.
    """
    grid = np.ascontiguousarray(_beliefs([belief])[0])
    truth_grid, explorable_grid = _truth_and_explorable(truth, explorable, grid.shape)
    known, wrong, correct = _map_counts(grid, truth_grid, explorable_grid)
    return MapQuality(int(known), int(wrong), int(correct), int(np.count_nonzero(explorable_grid)))


class TeamCounter:
    """:func:`team_counts` of the same maps, read again at every call.

    The maps, the truth and the explorable cells are checked once; each
    :meth:`count` reads the maps as they are then (the simulator updates the robots'
    beliefs in place). It copies them into one ``N x H x W`` array it keeps (a
    kernel reads one array faster, and a numba list of arrays costs a fraction of a
    second to set up in every process), so a call costs about two passes over the
    robots' cells.
    """

    def __init__(
        self,
        beliefs: Sequence[Belief] | Beliefs,
        truth: npt.ArrayLike,
        explorable: npt.ArrayLike,
    ) -> None:
        grids = _beliefs(beliefs)
        self.beliefs: tuple[Belief, ...] = tuple(beliefs)
        """The maps counted, as given."""
        self._stack = np.empty((len(grids), *grids[0].shape), dtype=np.int8)
        self._truth, self._explorable = _truth_and_explorable(truth, explorable, grids[0].shape)

    def count(self) -> tuple[int, int, int]:
        """``(known, wrong, correct)`` of the team map of the maps as they are now."""
        np.stack(self.beliefs, out=self._stack)
        known, wrong, correct = _team_counts(self._stack, self._truth, self._explorable)
        return int(known), int(wrong), int(correct)


def team_counts(
    beliefs: Sequence[Belief] | Beliefs,
    truth: npt.ArrayLike,
    explorable: npt.ArrayLike,
) -> tuple[int, int, int]:
    """``(known, wrong, correct)`` of :func:`team_map` of ``beliefs``, without building it.

    Equal to ``map_quality(team_map(beliefs), truth, explorable)``'s counts, in one
    pass over the robots' cells (``beliefs`` as one C-contiguous ``N x H x W`` array
    is not copied).

    Raises:
        MrexploreInputError: as :func:`team_map`, or a grid whose shape differs from
            the maps'.
    """
    stack = _stacked(beliefs)
    truth_grid, explorable_grid = _truth_and_explorable(truth, explorable, stack.shape[1:])
    known, wrong, correct = _team_counts(stack, truth_grid, explorable_grid)
    return int(known), int(wrong), int(correct)


def map_quality_metrics(
    beliefs: Sequence[Belief] | Beliefs,
    truth: npt.ArrayLike,
    explorable: npt.ArrayLike,
) -> dict[str, Any]:
    """The map-quality keys of ``result.json`` from the robots' final maps.

    ``map_error_fraction`` and ``map_correct_fraction`` are the team map's error and
    correct fractions; ``map_error_by_robot`` and ``map_correct_by_robot`` each
    robot's own, in id order.
    """
    stack = _stacked(beliefs)
    truth_grid, explorable_grid = _truth_and_explorable(truth, explorable, stack.shape[1:])
    team = map_quality(team_map(stack), truth_grid, explorable_grid)
    robots = [map_quality(grid, truth_grid, explorable_grid) for grid in stack]
    return {
        "map_error_fraction": team.error_fraction,
        "map_correct_fraction": team.correct_fraction,
        "map_error_by_robot": [quality.error_fraction for quality in robots],
        "map_correct_by_robot": [quality.correct_fraction for quality in robots],
    }
