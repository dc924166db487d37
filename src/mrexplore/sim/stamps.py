"""``robot_first_known``: the first tick at which each robot's own belief held each cell.

How the stamps are kept up to date depends on what can change a belief, and is
chosen once per run by :func:`make_belief_stamps`:

- :class:`BeliefStamps` (the base): the run does not record them; every hook does
  nothing.
- :class:`DirectStamps`: with the built-in ``broadcast`` / ``full`` / ``none``
  sharing a belief changes only where the robot senses, bumps into a wall or merges
  the cells of a :class:`~mrexplore.comm.sharing.CellUpdates` payload, so those
  cells are stamped as they change (the tick is the same as at the record).
- :class:`ShadowStamps`: any other mechanism may write anywhere, so each record
  compares every belief with a copy of it from the previous record, eight cells
  at a time.
"""

from __future__ import annotations

from collections.abc import Sequence

import numba
import numpy as np
import numpy.typing as npt

from mrexplore.comm import MapSharing, Message
from mrexplore.comm.sharing import BroadcastSharing, CellUpdates, FullSharing, NoSharing
from mrexplore.grid.occupancy import UNKNOWN
from mrexplore.sim.record import mark_known_changed
from mrexplore.sim.roster import Robot
from mrexplore.sim.scenario import Cell

_NO_STAMPS = np.zeros(0, dtype=np.int32)

#: Sharing mechanisms that change a belief only at the cells of their CellUpdates.
CELL_UPDATE_SHARING = (BroadcastSharing, FullSharing, NoSharing)


@numba.njit(cache=True, nogil=True)
def _stamp_cells(
    rows: npt.NDArray[np.int64],
    cols: npt.NDArray[np.int64],
    width: int,
    belief: npt.NDArray[np.int8],
    robot_known: npt.NDArray[np.int32],
    tick: int,
) -> None:  # pragma: no cover - compiled
    """Stamp ``tick`` on the listed cells that are known in ``belief`` and not stamped."""
    for k in range(rows.shape[0]):
        i = rows[k] * width + cols[k]
        if robot_known[i] < 0 and belief[i] != -1:
            robot_known[i] = tick


class BeliefStamps:
    """No ``robot_first_known``: the run does not record it (every hook is a no-op)."""

    robot_first_known: npt.NDArray[np.int32] | None = None
    """``(N, H, W)`` int32, -1 where the robot never knew the cell; ``None`` here."""

    def sensed_cells(self, robot_id: int) -> npt.NDArray[np.int32]:
        """The flat array the sensing kernel stamps the robot's fresh cells into
        (empty: it stamps nothing)."""
        return _NO_STAMPS

    def bumped(self, robot_id: int, cells: Sequence[Cell], tick: int) -> None:
        """``cells`` became known to the robot by bumping into a wall."""

    def received(self, robot: Robot, messages: list[Message], tick: int) -> None:
        """The robot merged the map ``messages`` into its belief."""

    def record(self, robots: Sequence[Robot], tick: int) -> None:
        """End of tick ``tick``: stamp what the hooks above did not see."""


class DirectStamps(BeliefStamps):
    """Stamps each cell where the belief changes (sensing, bumps, merged CellUpdates)."""

    def __init__(self, n_robots: int, shape: tuple[int, int]) -> None:
        self.robot_first_known = np.full((n_robots, *shape), -1, dtype=np.int32)
        self._flat = [known.reshape(-1) for known in self.robot_first_known]
        self._width = shape[1]

    def sensed_cells(self, robot_id: int) -> npt.NDArray[np.int32]:
        return self._flat[robot_id]

    def bumped(self, robot_id: int, cells: Sequence[Cell], tick: int) -> None:
        known = self._flat[robot_id]
        for row, col in cells:
            i = row * self._width + col
            if known[i] < 0:
                known[i] = tick

    def received(self, robot: Robot, messages: list[Message], tick: int) -> None:
        belief = robot.belief.reshape(-1)
        known = self._flat[robot.id]
        for message in messages:
            payload = message.payload
            assert isinstance(payload, CellUpdates)
            _stamp_cells(payload.rows, payload.cols, self._width, belief, known, tick)


class ShadowStamps(BeliefStamps):
    """Compares each belief with its copy from the previous record, eight cells at a time."""

    def __init__(self, n_robots: int, shape: tuple[int, int]) -> None:
        self.robot_first_known = np.full((n_robots, *shape), -1, dtype=np.int32)
        self._n_cells = shape[0] * shape[1]
        # rows padded to whole 8-byte words so that every row is word-aligned
        self._shadow = np.full((n_robots, -(-self._n_cells // 8) * 8), UNKNOWN, dtype=np.int8)

    def record(self, robots: Sequence[Robot], tick: int) -> None:
        assert self.robot_first_known is not None
        n_cells = self._n_cells
        n_words = n_cells // 8
        for robot in robots:
            belief = robot.belief.reshape(-1)
            shadow = self._shadow[robot.id, :n_cells]
            mark_known_changed(
                belief,
                shadow,
                belief[: 8 * n_words].view(np.uint64),
                shadow[: 8 * n_words].view(np.uint64),
                self.robot_first_known[robot.id].reshape(-1),
                tick,
                UNKNOWN,
            )


def make_belief_stamps(
    record_beliefs: bool, sharing: MapSharing, n_robots: int, shape: tuple[int, int]
) -> BeliefStamps:
    """The way this run keeps ``robot_first_known`` (see the module docstring)."""
    if not record_beliefs:
        return BeliefStamps()
    if type(sharing) in CELL_UPDATE_SHARING:  # exact types: a subclass may write anywhere
        return DirectStamps(n_robots, shape)
    return ShadowStamps(n_robots, shape)
