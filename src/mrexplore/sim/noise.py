"""Imperfect robots: a noisy sensor fused as log-odds, and odometry that drifts.

Both are off by default (``sensor_noise = odometry_noise = 0``); then nothing here
runs and a run is the same, bit for bit, as without this module.

**Sensor model** (``--sensor-noise P``, details with ``--sensor key=value``). Each
reading of a cell in the robot's line-of-sight disk is wrong with a probability:
a free cell is read as occupied with ``false_occupied`` (default ``P``), an
occupied cell is read as free with ``false_free`` (default ``P``). Both grow
linearly with the distance ``r`` to the cell, ``p(r) = p * (1 + range_growth * r /
R)`` for the sensor range ``R`` (``range_growth = 0``, the default, keeps them
constant). Every reading is an independent draw from the robot's own sensor stream.

Each robot fuses its readings into a log-odds occupancy grid, the binary Bayes
filter of Thrun, Burgard & Fox, *Probabilistic Robotics* §9.2 (table 9.1, with the
prior 0.5, so ``l0 = 0``), with the inverse sensor model the error rates imply:

- a reading "occupied" adds ``log((1 - false_free) / false_occupied)``,
- a reading "free" adds ``log(false_free / (1 - false_occupied))``,

clamped to ``[logit(clamp_free), logit(clamp_occupied)]``. Strategies see the usual
free / occupied / unknown belief: occupied above ``logit(occupied_above)``, free
below ``logit(free_below)``, unknown between (and where the robot has no reading):
the more probable state, so a single reading decides a new cell.

The filter of table 9.1 has no clamp, and the worlds here are static, so the default
clamp (1e-6, 1 - 1e-6, log-odds +-13.8) only bounds the numbers: evidence adds up as
the book's filter adds it. OctoMap's clamp (0.12, 0.97; Hornung et al. 2013), meant
for worlds that change, is one ``--sensor clamp_free=0.12 --sensor
clamp_occupied=0.97`` away; with this inverse model it is narrower than one reading
(log(0.9 / 0.1) = 2.2 at 10 % errors), so a cell is only as right as its last reading.

A robot knows that the cell it stands on is free. Its own readings override what
teammates told it about a cell, as perfect sensing does.

**Odometry model** (``--odometry-noise K``, details with ``--odometry key=value``).
Robots move on the grid exactly as planned; what drifts is their estimate of where
they are. Each step of length ``d`` (1 or sqrt 2 cells) adds to the estimate an error
drawn from ``N(0, (K d)^2)`` on each axis, and a heading error from ``N(0, (h d)^2)``
(``h`` = ``heading_deg`` in radians per cell); the estimated step is the true step
turned by the accumulated heading error. After ``n`` unit steps the position error
from the first part alone has a standard deviation of ``K sqrt(n)`` cells per axis.
A robot believes it is on the cell nearest its estimate (clipped to the map): its
strategy sees and plans from that cell, it writes what it senses relative to it
(turned by its heading error), and it executes the planned steps in the world,
where it may bump into a wall its map puts elsewhere (it then marks the wall where
it believes it is). ``reset`` says when the error goes back: ``never`` (the
default, dead reckoning), or ``meeting``: two robots that see each other (in line of
sight within the sensor range) measure their relative pose exactly, and the one
whose odometry has accumulated the larger variance since its last reset takes the
other's estimate (its error becomes the other's error).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numba
import numpy as np
import numpy.typing as npt

from mrexplore.errors import ScenarioError
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN
from mrexplore.params import Param, resolve_params

__all__ = [
    "ODOMETRY_PARAMS",
    "SENSOR_PARAMS",
    "Odometry",
    "OdometryModel",
    "SensorModel",
    "check_noise",
    "odometry_model",
    "resolve_details",
    "sensor_model",
]

SENSOR_PARAMS: dict[str, Param[Any]] = {
    "false_occupied": Param(
        -1.0,
        help="probability that a free cell is read as occupied, at the robot (-1: --sensor-noise)",
        note="-1 (default): the value of --sensor-noise",
        low=-1.0,
        high=0.5,
        high_open=True,
    ),
    "false_free": Param(
        -1.0,
        help="probability that an occupied cell is read as free, at the robot (-1: --sensor-noise)",
        note="-1 (default): the value of --sensor-noise",
        low=-1.0,
        high=0.5,
        high_open=True,
    ),
    "range_growth": Param(
        0.0,
        help="relative growth of both error rates from the robot to the sensor range",
        note="p(r) = p * (1 + range_growth * r / R); 0: the same at every range",
        low=0.0,
    ),
    "clamp_free": Param(
        1e-6,
        help="lowest occupancy probability a cell's log-odds can reach",
        note="a bound for the numbers only (the world is static); OctoMap clamps at 0.12",
        low=0.0,
        high=0.5,
        low_open=True,
        high_open=True,
    ),
    "clamp_occupied": Param(
        1 - 1e-6,
        help="highest occupancy probability a cell's log-odds can reach",
        note="a bound for the numbers only (the world is static); OctoMap clamps at 0.97",
        low=0.5,
        high=1.0,
        low_open=True,
        high_open=True,
    ),
    "occupied_above": Param(
        0.5,
        help="occupancy probability above which a cell is occupied",
        note="the more probable state (OctoMap's default too)",
        low=0.0,
        high=1.0,
        low_open=True,
        high_open=True,
    ),
    "free_below": Param(
        0.5,
        help="occupancy probability below which a cell is free",
        note="the more probable state (OctoMap's default too)",
        low=0.0,
        high=1.0,
        low_open=True,
        high_open=True,
    ),
}
"""The sensor model's parameters (``--sensor key=value``)."""

RESETS = ("never", "meeting")

ODOMETRY_PARAMS: dict[str, Param[Any]] = {
    "heading_deg": Param(
        0.0,
        "degrees per cell",
        help="standard deviation of the heading error each cell travelled adds",
        low=0.0,
    ),
    "reset": Param(
        "never",
        help="when the error resets: never, or meeting (robots that see each other)",
        choices=RESETS,
    ),
}
"""The odometry model's parameters (``--odometry key=value``)."""


#: Each details option: its parameters and what takes them, as messages name it.
DETAILS = {
    "--sensor": (SENSOR_PARAMS, "the sensor model"),
    "--odometry": (ODOMETRY_PARAMS, "the odometry model"),
}


def resolve_details(option: str, given: Mapping[str, Any]) -> dict[str, Any]:
    """Every parameter of ``option`` (``--sensor`` or ``--odometry``): the defaults
    overridden by ``given``, converted and checked."""
    declared, owner = DETAILS[option]
    return resolve_params(declared, given, owner=owner, option=option)


def _logit(p: float) -> float:
    return math.log(p / (1.0 - p))


@dataclass(frozen=True)
class SensorModel:
    """The error rates, their growth with range, and the log-odds fusion."""

    false_occupied: float
    false_free: float
    range_growth: float
    clamp_low: float
    """Lowest log-odds."""
    clamp_high: float
    """Highest log-odds."""
    occupied_above: float
    """Log-odds above which a cell is occupied."""
    free_below: float
    """Log-odds below which a cell is free."""

    @property
    def active(self) -> bool:
        """Whether any reading can be wrong."""
        return self.false_occupied > 0 or self.false_free > 0


@dataclass(frozen=True)
class OdometryModel:
    """The per-cell error of the position and the heading, and the reset rule."""

    position: float
    """Standard deviation per cell of step, each axis (cells per cell)."""
    heading: float
    """Standard deviation per cell of step of the heading error (radians per cell)."""
    reset: str

    @property
    def active(self) -> bool:
        return self.position > 0 or self.heading > 0


def sensor_model(sensor_noise: float, params: Mapping[str, Any]) -> SensorModel:
    """The sensor model of ``--sensor-noise`` and ``--sensor`` (checked).

    Raises:
        ScenarioError: an unknown or out-of-range parameter, or error rates that
            reach 0.5 within the sensor range (a reading would tell nothing).
    """
    p = resolve_details("--sensor", params)
    false_occupied = sensor_noise if p["false_occupied"] < 0 else p["false_occupied"]
    false_free = sensor_noise if p["false_free"] < 0 else p["false_free"]
    for name, rate in (("false_occupied", false_occupied), ("false_free", false_free)):
        far = rate * (1.0 + p["range_growth"])
        if far >= 0.5:
            raise ScenarioError(
                f"--sensor range_growth={p['range_growth']:g}: {name} would reach "
                f"{far:g} at the sensor range; a reading at 0.5 or above tells nothing"
            )
    if p["free_below"] > p["occupied_above"]:
        raise ScenarioError(
            f"--sensor free_below={p['free_below']:g}: above occupied_above="
            f"{p['occupied_above']:g}; a cell cannot be free and occupied"
        )
    return SensorModel(
        false_occupied=false_occupied,
        false_free=false_free,
        range_growth=p["range_growth"],
        clamp_low=_logit(p["clamp_free"]),
        clamp_high=_logit(p["clamp_occupied"]),
        occupied_above=_logit(p["occupied_above"]),
        free_below=_logit(p["free_below"]),
    )


def odometry_model(odometry_noise: float, params: Mapping[str, Any]) -> OdometryModel:
    """The odometry model of ``--odometry-noise`` and ``--odometry`` (checked)."""
    p = resolve_details("--odometry", params)
    return OdometryModel(
        position=float(odometry_noise), heading=math.radians(p["heading_deg"]), reset=p["reset"]
    )


def check_noise(scenario: Any) -> None:
    """Check the scenario's noise fields (called by :meth:`Scenario.check_fields`)."""
    from mrexplore.sim.scenario import _is_real

    noise = scenario.sensor_noise
    if not (_is_real(noise) and 0.0 <= noise < 0.5):
        raise ScenarioError(
            f"--sensor-noise {noise}: must be a probability in [0, 0.5) (at 0.5 a reading "
            "tells nothing)"
        )
    odometry = scenario.odometry_noise
    if not (_is_real(odometry) and math.isfinite(odometry) and odometry >= 0):
        raise ScenarioError(
            f"--odometry-noise {odometry}: must be a finite number >= 0 (standard deviation "
            "per cell travelled, as a fraction of the step)"
        )
    tables = (("--sensor", scenario.sensor_params), ("--odometry", scenario.odometry_params))
    for option, table in tables:
        if not isinstance(table, Mapping):
            raise ScenarioError(f"{option} {table!r}: expected a mapping of KEY=VALUE")
    sensor_model(noise, scenario.sensor_params)
    odometry_model(odometry, scenario.odometry_params)


# --------------------------------------------------------------------------- sensing


@numba.njit(cache=True, nogil=True)
def noisy_sense_kernel(
    visible: npt.NDArray[np.int64],
    width: int,
    height: int,
    true_row: int,
    true_col: int,
    est_row: float,
    est_col: float,
    cos_h: float,
    sin_h: float,
    believed: int,
    truth_state: npt.NDArray[np.int8],
    draws: npt.NDArray[np.float64],
    sensor_range: float,
    false_occupied: float,
    false_free: float,
    range_growth: float,
    clamp_low: float,
    clamp_high: float,
    occupied_above: float,
    free_below: float,
    log_odds: npt.NDArray[np.float32],
    belief: npt.NDArray[np.int8],
    sensed: npt.NDArray[np.bool_],
    world_sensed: npt.NDArray[np.bool_],
    sense_count: npt.NDArray[np.uint16],
    first_known: npt.NDArray[np.int32],
    explorable: npt.NDArray[np.bool_],
    tick: int,
    listed: npt.NDArray[np.int64],
    call: int,
    rows: npt.NDArray[np.int64],
    cols: npt.NDArray[np.int64],
    values: npt.NDArray[np.int8],
    was_unknown: npt.NDArray[np.bool_],
    robot_known: npt.NDArray[np.int32],
) -> tuple[int, int, int]:  # pragma: no cover - compiled
    """One robot's noisy sensing of the flat world cells ``visible`` (each once).

    Each cell's reading is the truth, flipped when ``draws[k]`` falls below the
    error rate at its distance; it is written at the belief cell the robot believes
    it sees (its offset from the true cell, turned by the heading error, from the
    estimated position), fused as log-odds and thresholded. The robot's believed
    cell is set free first. ``listed`` and ``call`` keep a belief cell from being
    listed twice in one call.

    Returns ``(changed cells, listed cells, newly known explorable cells)``; the
    listed cells (their value changed, or the robot read them for the first time,
    and they are known now) are in ``rows``, ``cols``, ``values``, ``was_unknown``.
    """
    changed = 0
    n_listed = 0
    explorable_new = 0
    stamp = robot_known.shape[0] > 0
    # the robot's own cell: it knows it stands on free ground
    for k in range(-1, visible.shape[0]):
        if k < 0:
            j = believed
            level = clamp_low
        else:
            i = visible[k]
            d_row = i // width - true_row
            d_col = i % width - true_col
            truth = truth_state[i]
            if not world_sensed[i]:
                world_sensed[i] = True
                sense_count[i] += 1
            r = math.sqrt(d_row * d_row + d_col * d_col)
            growth = 1.0 + range_growth * r / sensor_range
            if truth == OCCUPIED:
                read_occupied = not draws[k] < false_free * growth
            else:
                read_occupied = draws[k] < false_occupied * growth
            b_row = math.floor(est_row + cos_h * d_row - sin_h * d_col + 0.5)
            b_col = math.floor(est_col + sin_h * d_row + cos_h * d_col + 0.5)
            if b_row < 0 or b_col < 0 or b_row >= height or b_col >= width:
                continue
            j = b_row * width + b_col
            if j == believed:
                continue  # its own cell stays free
            # the inverse sensor model of the error rates at this range (an error-free
            # direction is certain: the clamp bounds it)
            p_fo = false_occupied * growth
            p_ff = false_free * growth
            if read_occupied:
                step = math.log((1.0 - p_ff) / p_fo) if p_fo > 0 else 1e9
            else:
                step = math.log(p_ff / (1.0 - p_fo)) if p_ff > 0 else -1e9
            level = log_odds[j] + step
        if level < clamp_low:
            level = clamp_low
        elif level > clamp_high:
            level = clamp_high
        log_odds[j] = level
        if level > occupied_above:
            value = OCCUPIED
        elif level < free_below:
            value = FREE
        else:
            value = UNKNOWN
        before = belief[j]
        first = not sensed[j]
        sensed[j] = True
        if before != value:
            changed += 1
            belief[j] = value
        if value == UNKNOWN or listed[j] == call or not (first or before != value):
            continue
        listed[j] = call
        rows[n_listed] = j // width
        cols[n_listed] = j % width
        values[n_listed] = value
        was_unknown[n_listed] = before == UNKNOWN
        n_listed += 1
        if stamp and robot_known[j] < 0:
            robot_known[j] = tick
        if first_known[j] < 0:
            first_known[j] = tick
            if explorable[j]:
                explorable_new += 1
    return changed, n_listed, explorable_new


# -------------------------------------------------------------------------- odometry


class Odometry:
    """Each robot's estimate of where it is, and how it drifts and resets."""

    def __init__(
        self,
        model: OdometryModel,
        starts: Sequence[tuple[int, int]],
        shape: tuple[int, int],
        rngs: Sequence[np.random.Generator],
    ) -> None:
        self.model = model
        self.shape = shape
        self.rngs = rngs
        n = len(starts)
        self.estimate = np.array(starts, dtype=np.float64).reshape(n, 2)
        """Each robot's estimated position (row, col), continuous."""
        self.heading = np.zeros(n, dtype=np.float64)
        """Each robot's heading error (radians)."""
        self.variance = np.zeros(n, dtype=np.float64)
        """The position variance each robot's odometry accumulated since its last reset."""
        self.resets = 0
        """Resets so far (``meeting``)."""

    def believed_cell(self, robot_id: int) -> tuple[int, int]:
        """The cell nearest the estimate, clipped to the map."""
        row, col = self.estimate[robot_id]
        height, width = self.shape
        return (
            min(max(math.floor(row + 0.5), 0), height - 1),
            min(max(math.floor(col + 0.5), 0), width - 1),
        )

    def moved(self, robot_id: int, d_row: int, d_col: int) -> None:
        """The robot made the step ``(d_row, d_col)`` in the world: its estimate moves by
        the step turned by the heading error, plus the position error."""
        model = self.model
        length = math.hypot(d_row, d_col)
        rng = self.rngs[robot_id]
        # Always three draws per step, in this order: the stream stays aligned whatever
        # the parameters.
        noise_row, noise_col, noise_heading = rng.standard_normal(3)
        self.heading[robot_id] += model.heading * length * noise_heading
        cos_h, sin_h = math.cos(self.heading[robot_id]), math.sin(self.heading[robot_id])
        sigma = model.position * length
        self.estimate[robot_id, 0] += cos_h * d_row - sin_h * d_col + sigma * noise_row
        self.estimate[robot_id, 1] += sin_h * d_row + cos_h * d_col + sigma * noise_col
        self.variance[robot_id] += sigma * sigma

    def error(self, robot_id: int, position: tuple[int, int]) -> float:
        """Distance in cells from the true ``position`` to the estimate."""
        row, col = self.estimate[robot_id]
        return math.hypot(row - position[0], col - position[1])

    def meet(self, pairs: Sequence[tuple[int, int]], positions: Sequence[tuple[int, int]]) -> None:
        """``reset = meeting``: for each pair of robots that see each other (in order),
        the one with the larger variance takes the other's error."""
        for a, b in pairs:
            if self.variance[a] == self.variance[b]:
                continue
            keep, take = (a, b) if self.variance[a] < self.variance[b] else (b, a)
            offset = self.estimate[keep] - np.asarray(positions[keep], dtype=np.float64)
            self.estimate[take] = np.asarray(positions[take], dtype=np.float64) + offset
            self.heading[take] = self.heading[keep]
            self.variance[take] = self.variance[keep]
            self.resets += 1
