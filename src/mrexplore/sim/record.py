"""The record of one run and the data files it leaves behind (DESIGN §8).

:meth:`RunRecord.save` writes ``result.json`` (the full scenario under the CLI's
option names, and the metrics) and ``trace.npz``, whose arrays are described in
:mod:`mrexplore.trace`, the trace schema. It writes data only: the pictures
(``final.png``, ``run.gif``, ...) are drawn by :mod:`mrexplore.viz`, and
:func:`mrexplore.save_run` writes both, as ``mrexplore run --out`` does.

The schema's names (:func:`load_trace`, :func:`pack_links`, :func:`n_link_pairs`,
...) are importable from here as well, as they were before the schema had its
own module.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numba
import numpy as np
import numpy.typing as npt

from mrexplore import __version__
from mrexplore.metrics import group_diameter, json_safe, map_quality_metrics, summarize
from mrexplore.sim.scenario import Scenario
from mrexplore.sim.world import World
from mrexplore.trace import (
    OPTIONAL_TRACE_ARRAYS,
    REQUIRED_TRACE_ARRAYS,
    component_labels,
    load_trace,
    n_link_pairs,
    pack_links,
    save_trace,
    unpack_links,
)

__all__ = [
    "BELIEF_CELLS_AUTO",
    "OPTIONAL_TRACE_ARRAYS",
    "REQUIRED_TRACE_ARRAYS",
    "RunRecord",
    "component_labels",
    "load_trace",
    "mark_known",
    "mark_known_changed",
    "n_link_pairs",
    "pack_links",
    "save_trace",
    "unpack_links",
]

#: Default limit on ``N x H x W`` (robots x cells) up to which every robot's own
#: ``robot_first_known`` is recorded (32 MiB of int32); above it only on request.
BELIEF_CELLS_AUTO = 2**23


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
    final_beliefs: npt.NDArray[np.int8] | None = None
    """``N x H x W``: each robot's belief at the end of the run (the map-quality keys
    of ``result.json``; the trace's ``robot_belief`` in a noisy run)."""
    map_known: npt.NDArray[np.int64] | None = None
    """``T+1``: cells the team map knows at each tick (noisy runs)."""
    map_wrong: npt.NDArray[np.int64] | None = None
    """``T+1``: cells of the team map that disagree with the truth (noisy runs)."""
    correct_known: npt.NDArray[np.int64] | None = None
    """``T+1``: explorable cells the team map holds free (noisy runs)."""
    estimated_positions: npt.NDArray[np.int32] | None = None
    """``T+1 x N x 2``: the cell each robot believes it is on (noisy runs)."""
    localisation_error: npt.NDArray[np.float64] | None = None
    """``T+1 x N``: cells from each robot's estimated position to its cell (noisy
    runs; zeros without odometry drift)."""
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
        optional = self._optional_trace_arrays()
        for name in OPTIONAL_TRACE_ARRAYS:
            value = optional[name]
            if value is not None:
                arrays[name] = value
        return arrays

    def _optional_trace_arrays(self) -> dict[str, np.ndarray | None]:
        """Each of :data:`OPTIONAL_TRACE_ARRAYS`, ``None`` where this run has none.

        The map-quality arrays are written only for a noisy run (``scenario.noisy``),
        so that a run without noise leaves the trace it left before noise existed.
        """
        noisy = self.scenario.noisy
        correct_coverage = (
            None
            if self.correct_known is None
            else self.correct_known / max(self.world.n_explorable, 1)
        )
        return {
            "component": self.component,
            "link_bits": self.link_bits,
            "robot_first_known": self.robot_first_known,
            "robot_complete": self.robot_complete,
            "map_known": self.map_known,
            "map_wrong": self.map_wrong,
            "correct_known": self.correct_known,
            "correct_coverage": correct_coverage,
            "estimated_positions": self.estimated_positions,
            "localisation_error": self.localisation_error,
            "robot_belief": self.final_beliefs if noisy else None,
        }

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
        metrics = summarize(self.trace_arrays())
        if "map_error_fraction" not in metrics and self.final_beliefs is not None:
            # a run without noise: the final maps are not in the trace, but are in hand
            metrics.update(
                map_quality_metrics(self.final_beliefs, grid.occupied, self.world.explorable)
            )
        out.update(metrics)
        out.update(
            {
                "bytes_total": int(sum(self.bytes_by_type.values())),
                "bytes_by_type": self.bytes_by_type,
                "messages_by_type": self.messages_by_type,
                "hops_by_type": self.hops_by_type,
                "messages_lost": self.messages_lost,
                "lost_by_type": self.lost_by_type,
                "queue_delay_mean": self.queue_delay_mean,
                "comm_description": self.comm_description,
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
                "distance_fields": self.fields,
                "decide_ms_per_plan": 1000 * self.decide_seconds / max(self.plans, 1),
            }
        )
        return json_safe(out)

    def save(self, out_dir: str | Path, *, replace: bool = False) -> dict[str, Path]:
        """Write ``result.json`` and ``trace.npz`` into ``out_dir``: data only.

        The pictures of the run (``final.png``, ``run.gif``, ``run.mp4``) are
        drawn by :mod:`mrexplore.viz`; :func:`mrexplore.save_run` writes both.

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
                staged = self.save(stage)
            return {name: Path(out_dir) / path.name for name, path in staged.items()}
        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        written = {"result": out / "result.json", "trace": out / "trace.npz"}
        save_trace(written["trace"], self.trace_arrays())
        written["result"].write_text(json.dumps(self.result(), indent=2) + "\n")
        return written
