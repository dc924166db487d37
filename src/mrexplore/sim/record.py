"""The record of one run and the files it leaves behind (DESIGN §8).

``result.json`` holds the full scenario (under the CLI's option names) and the
metrics; ``trace.npz`` holds the arrays anyone can re-check the run from:

================  ==================  ==============================================
array             shape, dtype        meaning
================  ==================  ==============================================
truth             H x W uint8         1 = occupied
explorable        H x W bool          free cells reachable from the start cells
positions         T+1 x N x 2 int32   row, col of each robot at each tick
first_known       H x W int32         first tick any robot knew the cell, -1 never
alive             T+1 x N bool        robot alive at the end of the tick
distance          T+1 x N float64     cumulative path length travelled (cells)
goals             T+1 x N x 2 int32   each robot's goal after the tick, -1 none
sense_count       H x W uint16        how many robots sensed the cell
sensed_by_robot   N int64             cells each robot sensed itself
known_explorable  T+1 int64           explorable cells known to the team
robot_complete    N int32             first tick robot i's own belief held every
                                      explorable cell, -1 never
coverage          T+1 float64         known_explorable / explorable cells
bytes_per_tick    T+1 int64           bytes sent at each tick
bytes_by_robot    N int64             bytes sent by each robot
subnetworks       T+1 int64           number of sub-networks at each tick
group_diameter    T+1 float64         largest distance between two robots (cells)
sensor_range      () float64          sensor radius in cells
speed             () float64          cells of path per tick
component         T+1 x N int16       sub-network of each robot during the tick, -1
                                      failed (optional)
link_bits         T+1 x B uint8       direct links during the tick, packed (optional)
robot_first_known N x H x W int32     first tick robot i knew the cell, -1 never
                                      (optional)
================  ==================  ==============================================

The last three arrays feed the animations and the HTML replay (:mod:`mrexplore.viz`);
traces written before they existed lack them (and ``robot_complete``), and every
reader treats them as optional (:func:`load_trace` loads any ``trace.npz``).

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
  --belief-panels``) or, by default, when ``N H W <= BELIEF_CELLS_AUTO``.
"""

from __future__ import annotations

import itertools
import json
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numba
import numpy as np
import numpy.typing as npt

from mrexplore import __version__
from mrexplore.metrics import group_diameter, json_safe, summarize
from mrexplore.sim.scenario import Scenario
from mrexplore.sim.world import World

#: Default limit on ``N x H x W`` (robots x cells) up to which every robot's own
#: ``robot_first_known`` is recorded (32 MiB of int32); above it only on request.
BELIEF_CELLS_AUTO = 2**23

#: Arrays that traces written by older versions lack.
OPTIONAL_TRACE_ARRAYS = ("component", "link_bits", "robot_first_known", "robot_complete")


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


@numba.njit(cache=True, nogil=True)
def mark_known(
    belief: npt.NDArray[np.int8], first_known: npt.NDArray[np.int32], tick: int, unknown: int
) -> None:  # pragma: no cover - compiled
    """Set ``first_known`` to ``tick`` where it is -1 and ``belief`` is not ``unknown``."""
    height, width = belief.shape
    for row in range(height):
        for col in range(width):
            if first_known[row, col] < 0 and belief[row, col] != unknown:
                first_known[row, col] = tick


@numba.njit(cache=True, nogil=True)
def mark_known_changed(
    belief: npt.NDArray[np.int8],
    shadow: npt.NDArray[np.int8],
    belief_words: npt.NDArray[np.uint64],
    shadow_words: npt.NDArray[np.uint64],
    first_known: npt.NDArray[np.int32],
    tick: int,
    unknown: int,
) -> None:  # pragma: no cover - compiled
    """:func:`mark_known` on flat arrays, looking only at cells that changed.

    ``shadow`` is a copy of ``belief`` as it was at the previous call (all
    ``unknown`` before the first); ``belief_words`` and ``shadow_words`` are the
    two arrays' first ``8 * (n // 8)`` bytes viewed as uint64. Eight cells are
    compared at once, so the unchanged bulk of the map costs a fraction of a
    cell-by-cell pass; ``shadow`` is brought up to date. The result equals
    ``mark_known(belief, first_known, tick, unknown)`` on the same arrays.
    """
    n_words = belief_words.shape[0]
    for w in range(n_words):
        if belief_words[w] == shadow_words[w]:
            continue
        shadow_words[w] = belief_words[w]
        for i in range(8 * w, 8 * w + 8):
            if first_known[i] < 0 and belief[i] != unknown:
                first_known[i] = tick
    for i in range(8 * n_words, belief.shape[0]):
        if belief[i] != shadow[i]:
            shadow[i] = belief[i]
            if first_known[i] < 0 and belief[i] != unknown:
                first_known[i] = tick


def load_trace(path: str | Path) -> dict[str, np.ndarray]:
    """Every array of a ``trace.npz`` (any version) as a dict of numpy arrays.

    Traces written before :data:`OPTIONAL_TRACE_ARRAYS` existed simply lack those
    keys; nothing is invented for them.
    """
    # Our own file handle: np.load leaves its own open when the file is not a zip.
    with open(Path(path), "rb") as handle, np.load(handle, allow_pickle=False) as data:
        return {name: data[name] for name in data.files}


@dataclass
class RunRecord:
    """Everything a finished run produced."""

    scenario: Scenario
    world: World
    status: str
    ticks: int
    positions: npt.NDArray[np.int32]
    alive: npt.NDArray[np.bool_]
    distance: npt.NDArray[np.float64]
    goals: npt.NDArray[np.int32]
    known_explorable: npt.NDArray[np.int64]
    first_known: npt.NDArray[np.int32]
    sense_count: npt.NDArray[np.uint16]
    sensed_by_robot: npt.NDArray[np.int64]
    bytes_per_tick: npt.NDArray[np.int64]
    bytes_by_type: dict[str, int]
    messages_by_type: dict[str, int]
    bytes_by_robot: npt.NDArray[np.int64]
    wall_time_s: float
    decide_seconds: float
    decisions: int
    plans: int
    strategy_params: dict[str, Any]
    max_ticks: int
    comm_range_cells: float
    comm_description: str
    subnetworks: npt.NDArray[np.int64]
    partition_events: int
    merge_events: int
    messages_lost: int
    lost_by_type: dict[str, int]
    hops_by_type: dict[str, int]
    queue_delay_mean: float
    sharing_metrics: dict[str, Any]
    sharing: str
    component: npt.NDArray[np.int16] | None = None
    link_bits: npt.NDArray[np.uint8] | None = None
    robot_first_known: npt.NDArray[np.int32] | None = None
    robot_complete: npt.NDArray[np.int32] | None = None
    field_decisions: int = 0
    """Decide calls that computed at least one distance field (benchmarks only)."""
    fields: int = 0
    """Distance fields computed inside decide calls (benchmarks only)."""
    _trace: dict[str, np.ndarray] | None = field(default=None, init=False, repr=False)

    def trace_arrays(self) -> dict[str, np.ndarray]:
        """The arrays of ``trace.npz`` (computed once; ``result()`` and ``save()`` reuse
        them)."""
        if self._trace is None:
            self._trace = self._build_trace()
        return dict(self._trace)

    def _build_trace(self) -> dict[str, np.ndarray]:
        arrays: dict[str, np.ndarray] = {
            "truth": self.world.grid.truth_uint8(),
            "explorable": self.world.explorable,
            "positions": self.positions,
            "first_known": self.first_known,
            "alive": self.alive,
            "distance": self.distance,
            "goals": self.goals,
            "sense_count": self.sense_count,
            "sensed_by_robot": self.sensed_by_robot,
            "known_explorable": self.known_explorable,
            "coverage": self.known_explorable / max(self.world.n_explorable, 1),
            "bytes_per_tick": self.bytes_per_tick,
            "bytes_by_robot": self.bytes_by_robot,
            "subnetworks": self.subnetworks,
            "group_diameter": group_diameter(self.positions),
            "sensor_range": np.array(self.world.sensor_range_cells, dtype=np.float64),
            "speed": np.array(self.scenario.speed, dtype=np.float64),
        }
        for name in OPTIONAL_TRACE_ARRAYS:
            value = getattr(self, name)
            if value is not None:
                arrays[name] = value
        return arrays

    def result(self) -> dict[str, Any]:
        """The content of ``result.json``: scenario, map, metrics, provenance."""
        grid = self.world.grid
        out: dict[str, Any] = {"mrexplore_version": __version__}
        out.update(self.scenario.to_dict())
        out["params"] = dict(self.strategy_params)  # defaults included, converted types
        out["max_ticks"] = self.max_ticks  # the limit in force, also when it was automatic
        out["sharing"] = self.sharing  # the mechanism in force, also when it was the default
        out.update(
            {
                "status": self.status,
                "ticks": self.ticks,
                "n_robots": self.scenario.robots,
                "sensor_range_cells": self.world.sensor_range_cells,
                "map_name": grid.name,
                "map_shape": list(grid.shape),
                "map_resolution_m": grid.resolution_m,
                "map_source": grid.source,
                "map_credit": grid.credit,
                "starts": [list(s) for s in self.world.starts],
            }
        )
        if self.scenario.start_delay > 0:  # each robot's first live tick (None: never)
            awake = np.asarray(self.alive, dtype=bool)
            out["start_ticks"] = [int(np.argmax(c)) if c.any() else None for c in awake.T]
        out.update(summarize(self.trace_arrays()))
        out.update(
            {
                "bytes_total": int(sum(self.bytes_by_type.values())),
                "bytes_by_type": self.bytes_by_type,
                "messages_by_type": self.messages_by_type,
                "hops_by_type": self.hops_by_type,
                "messages_lost": self.messages_lost,
                "lost_by_type": self.lost_by_type,
                "queue_delay_mean": self.queue_delay_mean,
                "comm_model": self.comm_description,
                "comm_range_cells": self.comm_range_cells,
                "subnetworks_max": int(self.subnetworks.max(initial=1)),
                "subnetworks_mean": float(self.subnetworks.mean())
                if self.subnetworks.size
                else 1.0,
                "partition_events": self.partition_events,
                "merge_events": self.merge_events,
                **self.sharing_metrics,
                "bytes_by_robot": [int(b) for b in self.bytes_by_robot],
                "wall_time_s": self.wall_time_s,
                "decisions": self.decisions,
                "plans": self.plans,
                "decide_ms_per_plan": 1000 * self.decide_seconds / max(self.plans, 1),
            }
        )
        return json_safe(out)

    def save(
        self,
        out_dir: str | Path,
        *,
        gif: bool = False,
        png: bool = True,
        mp4: bool = False,
        belief_panels: bool = False,
        max_frames: int | None = None,
        replace: bool = False,
    ) -> dict[str, Path]:
        """Write ``result.json``, ``trace.npz``, ``final.png`` (and ``run.gif``, ``run.mp4``).

        The animations are those of :func:`mrexplore.viz.save_animation` (links,
        targets, header; one panel per robot's own belief with ``belief_panels``,
        which needs ``robot_first_known``); ``max_frames`` defaults to 300. An MP4
        needs ``ffmpeg`` on ``PATH``.

        By default the files are written into ``out_dir`` (created if needed),
        overwriting files of the same names and leaving any others. With
        ``replace`` the run is written into a staging folder first and then
        replaces ``out_dir`` whole (:func:`mrexplore.rundir.staged_dir`): no file
        of an earlier run stays beside the new ones, and an error or a crash
        while writing leaves ``out_dir`` as it was.
        """
        if replace:
            from mrexplore.rundir import staged_dir

            with staged_dir(out_dir) as stage:
                staged = self.save(
                    stage,
                    gif=gif,
                    png=png,
                    mp4=mp4,
                    belief_panels=belief_panels,
                    max_frames=max_frames,
                )
            return {name: Path(out_dir) / path.name for name, path in staged.items()}
        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        written = {"result": out / "result.json", "trace": out / "trace.npz"}
        arrays = self.trace_arrays()
        np.savez_compressed(written["trace"], **arrays)  # type: ignore[arg-type]  # stub types allow_pickle as **kwds
        written["result"].write_text(json.dumps(self.result(), indent=2) + "\n")
        if png or gif or mp4:
            from mrexplore import viz

            title = (
                f"{self.scenario.strategy}, {self.scenario.robots} robots on {self.world.grid.name}"
            )
            if png:
                written["final"] = viz.save_final_png(
                    out / "final.png",
                    arrays["truth"],
                    self.first_known,
                    self.positions,
                    title=f"{title}: {self.status} at tick {self.ticks}",
                    credit=self.world.grid.credit,
                    alive=self.alive,
                    explorable=self.world.explorable,
                )
            frames = {"max_frames": max_frames} if max_frames is not None else {}
            for wanted, name in ((gif, "gif"), (mp4, "mp4")):
                if wanted:
                    written[name] = viz.save_animation(
                        out / f"run.{name}",
                        arrays,
                        belief_panels=belief_panels,
                        title=title,
                        **frames,
                    )
        return written
