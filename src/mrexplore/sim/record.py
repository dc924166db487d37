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
coverage          T+1 float64         known_explorable / explorable cells
bytes_per_tick    T+1 int64           bytes sent at each tick
bytes_by_robot    N int64             bytes sent by each robot
subnetworks       T+1 int64           number of sub-networks at each tick
group_diameter    T+1 float64         largest distance between two robots (cells)
sensor_range      () float64          sensor radius in cells
speed             () float64          cells of path per tick
================  ==================  ==============================================
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from mrexplore import __version__
from mrexplore.metrics import group_diameter, json_safe, summarize
from mrexplore.sim.scenario import Scenario
from mrexplore.sim.world import World


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

    def trace_arrays(self) -> dict[str, np.ndarray]:
        """The arrays of ``trace.npz``."""
        return {
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

    def save(self, out_dir: str | Path, *, gif: bool = False, png: bool = True) -> dict[str, Path]:
        """Write ``result.json``, ``trace.npz``, ``final.png`` (and ``run.gif``)."""
        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        written = {"result": out / "result.json", "trace": out / "trace.npz"}
        arrays = self.trace_arrays()
        np.savez_compressed(written["trace"], **arrays)  # type: ignore[arg-type]  # stub types allow_pickle as **kwds
        written["result"].write_text(json.dumps(self.result(), indent=2) + "\n")
        if png or gif:
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
            if gif:
                written["gif"] = viz.save_gif(
                    out / "run.gif",
                    arrays["truth"],
                    self.first_known,
                    self.positions,
                    alive=self.alive,
                )
        return written
