"""What a noisy run's trace adds to the pictures: believed positions and beliefs.

With odometry drift and sensor noise (issue 19) a trace may hold three optional
arrays (:mod:`mrexplore.trace`):

=====================  ==================  =========================================
array                  shape, dtype        meaning
=====================  ==================  =========================================
estimated_positions    T+1 x N x 2 int32   cell each robot believes it is on at the
                                           end of each tick (the true one is
                                           ``positions``)
localisation_error     T+1 x N float64     distance in cells between the true and
                                           the estimated position
robot_belief           N x H x W int8      each robot's final belief map (-1 unknown,
                                           0 free, 100 occupied)
=====================  ==================  =========================================

This module reads and checks them for the animation
(:mod:`mrexplore.viz.animate`), the final picture (:mod:`mrexplore.viz.render`)
and the HTML replay (:mod:`mrexplore.viz.replay`), so the three draw the same
thing. Every function returns ``None`` for a trace without the array: traces of
noiseless runs, and of versions before issue 19, simply lack them.

A belief panel colours each cell with a *belief code*, the colour class it takes
once the robot knows it:

====  ==============================================================================
code  the robot's final belief of the cell
====  ==============================================================================
0, 1  unknown (the robot knew it once but no longer holds it): shown as an unknown
      cell, free (0) or occupied (1) in truth, like cells it never knew
2     free, and free in truth
3     occupied, and occupied in truth
4     free, but occupied in truth (a wall the robot missed or put elsewhere)
5     occupied, but free in truth (a wall where there is none)
====  ==============================================================================

A belief value below 0 is unknown, 50 or more occupied, anything else free (the
``nav_msgs/OccupancyGrid`` reading; mrexplore's maps hold -1, 0 and 100).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import numpy.typing as npt

from mrexplore.errors import MrexploreInputError

ESTIMATED_POSITIONS = "estimated_positions"
LOCALISATION_ERROR = "localisation_error"
ROBOT_BELIEF = "robot_belief"

#: Belief codes (see the module docstring). The order makes a block of cells,
#: reduced by its highest code, show a wrong cell over a right one and a wall over
#: free space.
BELIEF_UNKNOWN_FREE = 0
BELIEF_UNKNOWN_OCCUPIED = 1
BELIEF_FREE = 2
BELIEF_OCCUPIED = 3
BELIEF_WRONG_FREE = 4
BELIEF_WRONG_OCCUPIED = 5

#: A belief value at or above this is occupied.
_OCCUPIED_FROM = 50


def estimated_positions(
    trace: Mapping[str, Any], positions: npt.NDArray[np.intp], shape: tuple[int, int]
) -> npt.NDArray[np.intp] | None:
    """The trace's ``estimated_positions``, checked against ``positions`` and the map
    ``shape``, or ``None`` when the trace has none.

    >>> true = np.array([[[1, 1]], [[1, 2]]])
    >>> estimated_positions({"estimated_positions": true + [0, 1]}, true, (4, 4))[1].tolist()
    [[1, 3]]
    """
    if ESTIMATED_POSITIONS not in trace:
        return None
    estimated = np.asarray(trace[ESTIMATED_POSITIONS])
    if estimated.shape != positions.shape:
        raise MrexploreInputError(
            f"estimated_positions has shape {estimated.shape}, expected {positions.shape} "
            "(that of positions)"
        )
    if not np.issubdtype(estimated.dtype, np.integer):
        raise MrexploreInputError(f"estimated_positions must be integers, got {estimated.dtype}")
    height, width = shape
    if estimated.size:
        rows, cols = estimated[..., 0], estimated[..., 1]
        if rows.min() < 0 or rows.max() >= height or cols.min() < 0 or cols.max() >= width:
            raise MrexploreInputError(
                f"estimated_positions leave the {height} x {width} map "
                f"(rows {rows.min()}..{rows.max()}, cols {cols.min()}..{cols.max()})"
            )
    result: npt.NDArray[np.intp] = estimated.astype(np.intp)
    return result


def localisation_errors(
    trace: Mapping[str, Any],
    positions: npt.NDArray[np.intp],
    estimated: npt.NDArray[np.intp] | None,
) -> npt.NDArray[np.float64] | None:
    """Each robot's localisation error per tick (``T+1 x N``, cells).

    The trace's ``localisation_error`` when it has one of the right shape (measured
    from the robot's continuous estimate), else the distance between the true and
    the believed cell, else ``None`` (no estimated positions).

    >>> true = np.zeros((1, 1, 2), dtype=np.intp)
    >>> localisation_errors({}, true, true + [3, 4]).tolist()
    [[5.0]]
    """
    if LOCALISATION_ERROR in trace:
        errors = np.asarray(trace[LOCALISATION_ERROR], dtype=np.float64)
        if errors.shape != positions.shape[:2]:
            raise MrexploreInputError(
                f"localisation_error has shape {errors.shape}, expected (T+1) x N = "
                f"{positions.shape[:2]}"
            )
        return errors
    if estimated is None:
        return None
    offset = (estimated - positions).astype(np.float64)
    distance: npt.NDArray[np.float64] = np.hypot(offset[..., 0], offset[..., 1])
    return distance


def belief_codes(
    trace: Mapping[str, Any], occupied: npt.NDArray[Any]
) -> npt.NDArray[np.uint8] | None:
    """Each robot's final belief as belief codes (``N x H x W`` uint8), or ``None``.

    ``occupied`` is the ground truth (``H x W``, nonzero = occupied).

    >>> truth = np.array([[0, 1, 0, 1]])
    >>> belief = np.array([[[0, 100, 100, 0]]], dtype=np.int8)
    >>> belief_codes({"robot_belief": belief}, truth).tolist()
    [[[2, 3, 5, 4]]]
    """
    if ROBOT_BELIEF not in trace:
        return None
    belief = np.asarray(trace[ROBOT_BELIEF])
    truth = np.asarray(occupied) != 0
    if belief.ndim != 3 or belief.shape[1:] != truth.shape:
        raise MrexploreInputError(
            f"robot_belief has shape {belief.shape}, expected N x {truth.shape[0]} x "
            f"{truth.shape[1]} (robots x the map)"
        )
    held_occupied = belief >= _OCCUPIED_FROM
    codes = np.where(
        held_occupied,
        np.where(truth, BELIEF_OCCUPIED, BELIEF_WRONG_OCCUPIED),
        np.where(truth, BELIEF_WRONG_FREE, BELIEF_FREE),
    ).astype(np.uint8)
    unknown = np.broadcast_to(truth.astype(np.uint8), belief.shape)  # 0 or 1, as in truth
    result: npt.NDArray[np.uint8] = np.where(belief < 0, unknown, codes).astype(np.uint8)
    return result


def belief_first_known(trace: Mapping[str, Any]) -> npt.NDArray[Any] | None:
    """The first tick each robot knew each cell, for the belief panels (``N x H x W``).

    ``robot_first_known`` when the trace has it. A trace with ``robot_belief`` but
    without ``robot_first_known`` says only what each robot held at the end, so every
    cell it holds (free or occupied) counts as known from tick 0: its panel shows the
    final belief in every frame. ``None`` when the trace has neither.

    >>> belief_first_known({"robot_belief": np.array([[[-1, 0, 100]]])}).tolist()
    [[[-1, 0, 0]]]
    """
    if "robot_first_known" in trace:
        return np.asarray(trace["robot_first_known"])  # as stored: N H W int32 is large
    if ROBOT_BELIEF in trace:
        belief = np.asarray(trace[ROBOT_BELIEF])
        known: npt.NDArray[np.int64] = np.where(belief >= 0, 0, -1).astype(np.int64)
        return known
    return None


def block_belief_codes(codes: npt.NDArray[np.uint8], stride: int) -> npt.NDArray[np.uint8]:
    """Reduce ``N x H x W`` belief codes by ``stride``: each block's highest code.

    A block then shows a wrong cell if it holds one, else a wall if it holds one
    (as the team's map shows walls in :func:`mrexplore.viz.render_frame`).

    >>> block_belief_codes(np.array([[[2, 5, 2], [3, 2, 0]]], dtype=np.uint8), 2).tolist()
    [[[5, 2]]]
    """
    if stride == 1:
        return codes
    n_robots, height, width = codes.shape
    out_h, out_w = -(-height // stride), -(-width // stride)
    padded = np.zeros((n_robots, out_h * stride, out_w * stride), dtype=np.uint8)
    padded[:, :height, :width] = codes
    blocks = padded.reshape(n_robots, out_h, stride, out_w, stride)
    result: npt.NDArray[np.uint8] = blocks.max(axis=(2, 4))
    return result
