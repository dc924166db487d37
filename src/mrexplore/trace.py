"""The trace schema: the arrays of ``trace.npz``, and writing and reading them (DESIGN §8).

The simulator writes traces (:meth:`mrexplore.sim.RunRecord.save`); the pictures
(:mod:`mrexplore.viz`), the checkers (:mod:`mrexplore.checks`) and anyone else read
them. This module is the format both sides share and needs nothing but numpy.

``trace.npz`` (a compressed numpy archive) holds the arrays anyone can re-check a run
from; ``result.json`` beside it holds the scenario and the metrics
(:meth:`mrexplore.sim.RunRecord.result`):

===================  ==================  ==============================================
array                shape, dtype        meaning
===================  ==================  ==============================================
truth                H x W uint8         1 = occupied
explorable           H x W bool          free cells reachable from the start cells
positions            T+1 x N x 2 int32   row, col of each robot at each tick
first_known          H x W int32         first tick any robot knew the cell, -1 never
alive                T+1 x N bool        robot alive at the end of the tick
distance             T+1 x N float64     cumulative path length travelled (cells)
goals                T+1 x N x 2 int32   each robot's goal after the tick, -1 none
sense_count          H x W uint16        how many robots sensed the cell
sensed_by_robot      N int64             cells each robot sensed itself
known_explorable     T+1 int64           explorable cells known to the team
robot_complete       N int32             first tick robot i's own belief held every
                                         explorable cell, -1 never
coverage             T+1 float64         known_explorable / explorable cells
bytes_per_tick       T+1 int64           bytes sent at each tick
bytes_by_robot       N int64             bytes sent by each robot
subnetworks          T+1 int64           number of sub-networks at each tick
group_diameter       T+1 float64         largest distance between two robots (cells)
sensor_range         () float64          sensor radius in cells
speed                () float64          cells of path per tick
component            T+1 x N int16       sub-network of each robot during the tick, -1
                                         failed (optional)
link_bits            T+1 x B uint8       direct links during the tick, packed (optional)
robot_first_known    N x H x W int32     first tick robot i knew the cell, -1 never
                                         (optional)
map_known            T+1 int64           cells the team map knows (noisy runs)
map_wrong            T+1 int64           cells of the team map that disagree with the
                                         truth (noisy runs)
correct_known        T+1 int64           explorable cells the team map holds free
                                         (noisy runs)
correct_coverage     T+1 float64         correct_known / explorable cells (noisy runs)
estimated_positions  T+1 x N x 2 int32   row, col of the cell each robot believes it is
                                         on at the end of the tick (noisy runs)
localisation_error   T+1 x N float64     cells from each robot's estimated position to
                                         its cell, 0 without odometry drift (noisy runs)
robot_belief         N x H x W int8      each robot's belief at the end of the run
                                         (noisy runs)
===================  ==================  ==============================================

``component``, ``link_bits`` and ``robot_first_known`` feed the animations and the
HTML replay (:mod:`mrexplore.viz`); traces written before they existed lack them (and
``robot_complete`` and the arrays of noisy runs), and every reader treats them as
optional (:func:`load_trace` loads any ``trace.npz``).

* ``component[t, i]`` is the index of robot ``i``'s sub-network in the list of
  connected components of the link graph in force during tick ``t`` (components
  ordered by their lowest robot id, so the group holding robot 0 is 0), ``-1`` for
  a robot that has failed by then. ``subnetworks[t]`` is the number of labels.
* ``link_bits[t]`` is ``numpy.packbits`` of the ``N (N - 1) / 2`` flags "robots
  ``a < b`` are linked" in the order (0, 1), (0, 2), ..., (0, N-1), (1, 2), ...;
  :func:`unpack_links` turns it back into pairs or an ``N x N`` matrix.
  The links of tick ``t`` are those the communication model computed at its start,
  from the positions at the end of tick ``t - 1`` (tick 0: the start cells).
* ``robot_first_known[i]`` is the first tick at whose end robot ``i``'s own belief
  held the cell as free or occupied, whether it sensed the cell or was told about
  it. It costs ``4 N H W`` bytes in memory, so the simulator records it only when
  asked (``Simulation(..., record_beliefs=True)``, ``mrexplore run
  --belief-panels``) or, by default, when ``N H W <=``
  :data:`mrexplore.sim.record.BELIEF_CELLS_AUTO`.

The arrays marked "noisy runs" are written only when the scenario has sensor noise or
odometry drift (``Scenario.noisy``), so that a run without noise leaves the same
trace as before noise existed. The *team map* is the robots' beliefs merged: a cell
is known if any robot knows it, with the value most of the robots that know it hold,
occupied on a tie (:func:`mrexplore.metrics.map_quality.team_map`); every robot
counts, a failed one with the belief it had when it stopped.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Mapping
from pathlib import Path

import numpy as np
import numpy.typing as npt

#: Arrays every trace has, whatever version wrote it (the run contract).
REQUIRED_TRACE_ARRAYS = ("truth", "first_known", "positions")

#: Arrays that traces written by older versions lack.
OPTIONAL_TRACE_ARRAYS = (
    "component",
    "link_bits",
    "robot_first_known",
    "robot_complete",
    "map_known",
    "map_wrong",
    "correct_known",
    "correct_coverage",
    "estimated_positions",
    "localisation_error",
    "robot_belief",
)


def n_link_pairs(n_robots: int) -> int:
    """How many unordered robot pairs ``a < b`` a team of ``n_robots`` has."""
    return n_robots * (n_robots - 1) // 2


def pack_links(links: Iterable[tuple[int, int]], n_robots: int) -> npt.NDArray[np.uint8]:
    """One row of ``link_bits``: the links ``(a, b)`` as packed pair flags.

    >>> pack_links([(0, 1), (1, 2)], 3).tolist()
    [160]
    """
    flags = np.zeros(n_link_pairs(n_robots), dtype=bool)
    flat = itertools.chain.from_iterable(links)
    pairs = np.fromiter(flat, dtype=np.int64).reshape(-1, 2)
    low, high = pairs.min(axis=1), pairs.max(axis=1)
    flags[low * n_robots - low * (low + 1) // 2 + (high - low - 1)] = True
    packed: npt.NDArray[np.uint8] = np.packbits(flags)
    return packed


def unpack_links(link_bits: npt.ArrayLike, n_robots: int) -> npt.NDArray[np.bool_]:
    """``link_bits`` (one row, or ``T+1`` rows) as symmetric ``N x N`` link matrices.

    >>> matrix = unpack_links(pack_links([(0, 2)], 3), 3)
    >>> matrix.astype(int).tolist()
    [[0, 0, 1], [0, 0, 0], [1, 0, 0]]
    """
    bits = np.asarray(link_bits, dtype=np.uint8)
    rows = bits.reshape(-1, bits.shape[-1]) if bits.ndim else bits.reshape(1, 1)
    flags = np.unpackbits(rows, axis=1, count=n_link_pairs(n_robots)).astype(bool)
    low, high = np.triu_indices(n_robots, k=1)
    matrix = np.zeros((rows.shape[0], n_robots, n_robots), dtype=bool)
    matrix[:, low, high] = flags
    matrix[:, high, low] = flags
    result: npt.NDArray[np.bool_] = matrix if bits.ndim > 1 else matrix[0]
    return result


def component_labels(groups: Iterable[Iterable[int]], n_robots: int) -> npt.NDArray[np.int16]:
    """One row of ``component``: the index of each robot's group, -1 if in none.

    >>> component_labels([{0, 2}, {1}], 4).tolist()
    [0, 1, 0, -1]
    """
    labels = np.full(n_robots, -1, dtype=np.int16)
    for label, group in enumerate(groups):
        labels[list(group)] = label
    return labels


def load_trace(path: str | Path) -> dict[str, np.ndarray]:
    """Every array of a ``trace.npz`` (any version) as a dict of numpy arrays.

    Traces written before :data:`OPTIONAL_TRACE_ARRAYS` existed simply lack those
    keys; nothing is invented for them.
    """
    # Our own file handle: np.load leaves its own open when the file is not a zip.
    with open(Path(path), "rb") as handle, np.load(handle, allow_pickle=False) as data:
        return {name: data[name] for name in data.files}


def save_trace(path: str | Path, arrays: Mapping[str, np.ndarray]) -> Path:
    """Write ``arrays`` (the schema above) to ``path`` as a compressed ``trace.npz``."""
    target = Path(path)
    np.savez_compressed(target, **arrays)  # type: ignore[arg-type]  # stub types allow_pickle as **kwds
    return target
