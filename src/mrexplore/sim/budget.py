"""How much memory a run needs, estimated before anything large is allocated.

:func:`estimate_run_bytes` adds up what :class:`~mrexplore.sim.engine.Simulation`
keeps for a map of ``H x W`` cells and a team of ``N`` robots, plus the largest
temporary arrays of a tick and of the metrics at the end of the run;
:func:`available_memory_bytes` reads what the machine can still give;
:func:`check_run_memory` refuses a run whose estimate does not fit, with a
:class:`~mrexplore.errors.ScenarioError` (exit status 2) instead of a
``MemoryError`` (or the kernel's OOM killer) minutes into the run.

The byte counts below were read off the allocations of the tick loop
(``sim/engine.py`` and its parts in ``sim/``), ``sim/record.py``, ``trace.py``,
``comm/*``, ``planning/distance.py``, ``strategies/*`` and ``metrics/*``, and checked
against the peak resident memory of real runs (see :func:`estimate_run_bytes`).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

from mrexplore.errors import ScenarioError

__all__ = [
    "MemoryEstimate",
    "available_memory_bytes",
    "check_run_memory",
    "estimate_run_bytes",
    "format_bytes",
]

#: Modules and compiled numba kernels loaded during the first ticks (measured: about
#: 45 MB between importing the engine and the end of a run on a 40x40 map).
FIXED_BYTES = 50 * 10**6
#: Whole-run arrays of one cell: truth (bool), truth_state (int8), explorable (bool),
#: occupant (int32), first_known (int32), sense_count (uint16) and the trace's uint8
#: copy of the truth.
MAP_BYTES_PER_CELL = 1 + 1 + 1 + 4 + 4 + 2 + 1
#: Every robot's belief (int8) and ``sensed`` mask (bool), and the copy of its final
#: belief in the run record (int8, for the map-quality metrics).
ROBOT_BYTES_PER_CELL = 1 + 1 + 1
#: ``robot_first_known`` (int32 per robot and cell), when the run records it.
RECORDED_BELIEF_BYTES_PER_CELL = 4
#: The copy of each belief kept to find changed cells (int8), when ``robot_first_known``
#: is recorded with a sharing mechanism other than ``broadcast`` / ``full`` / ``none``.
BELIEF_SHADOW_BYTES_PER_CELL = 1
#: One distance field (``planning.distance_field``: float64 distances, uint8 states,
#: 3 x int32 buckets) plus the boolean masks (passable, frontier, targets) around it.
PLAN_BYTES_PER_CELL = 8 + 1 + 12 + 5
#: The metrics of ``result.json`` (``metrics.regions``: a dozen int64 / float64 arrays
#: over the explorable cells, sorted, labelled and made unique; measured 139 to 150 B).
METRICS_BYTES_PER_CELL = 150
#: Per-strategy state per robot and cell: ``zlot-market`` keeps the buffers of a
#: distance field (22 B) and its free mask (1 B) per robot; ``kme`` holds one float64
#: distance field per robot of a plan at once.
STRATEGY_ROBOT_BYTES_PER_CELL = {"zlot-market": 23, "kme": 8}
#: Per-sharing state: ``polygon`` keeps each robot's own map (int8) and a shared linked
#: list head (int64) and label buffer (int32) per cell.
SHARING_ROBOT_BYTES_PER_CELL = {"polygon": 1}
#: Per robot and cell in a noisy run (:mod:`mrexplore.sim.noise`): the log-odds
#: (float32), the cells it sensed in the world and the team counter's copy of its
#: belief (its final belief in the trace is the run record's copy, counted above).
NOISY_ROBOT_BYTES_PER_CELL = 4 + 1 + 1
#: Per tick and robot in a noisy run: estimated positions and localisation errors.
NOISY_TICK_BYTES_PER_ROBOT = 8 + 8
SHARING_BYTES_PER_CELL = {"polygon": 8 + 4}
#: The per-tick logs (positions, alive, distance, goals: four small arrays, the known
#: count and list slots, measured 880 B) ...
TICK_BYTES = 880
#: ... their per-robot part, kept twice (lists, then the stacked trace arrays):
#: 2 x (8 + 1 + 8 + 8 + 2) bytes.
TICK_BYTES_PER_ROBOT = 54
#: ``group_diameter``'s temporaries, one robot against the others: ``T x N x 2``
#: float64 differences and squares and ``T x N`` sums (48 B per tick and robot; only
#: with two robots or more).
TICK_BYTES_PER_ROBOT_DIAMETER = 48
#: Packed link flags, one bit per robot pair and tick, in the stacked trace.
TICK_BITS_PER_ROBOT_PAIR = 1
#: ``RangeLinks.links``' numpy temporaries per robot pair (``N x N`` float64
#: differences, squares and sums, and masks: 2 x 42 B), whatever the range.
PAIR_BYTES = 84
#: Each *linked* pair as Python objects: a tuple of two ints in the links frozenset,
#: its copies per sub-network and while the next tick's links are built, and the
#: temporaries of ``pack_links`` (measured 550 to 650 B per pair with all pairs linked,
#: 84 of them the arrays above).
LINKED_PAIR_BYTES = 520
#: Estimated ticks over the bound of :func:`estimate_ticks` (real runs: 2.7 to 14).
TICKS_OVER_BOUND = 2

_GB = 10**9


@dataclass(frozen=True)
class MemoryEstimate:
    """The bytes a run needs, by part (see :func:`estimate_run_bytes`)."""

    map_bytes: int
    robot_bytes: int
    transient_bytes: int
    trace_bytes: int
    ticks: int
    fixed_bytes: int = FIXED_BYTES

    @property
    def total(self) -> int:
        return (
            self.fixed_bytes
            + self.map_bytes
            + self.robot_bytes
            + self.transient_bytes
            + self.trace_bytes
        )


def estimate_ticks(
    free_cells: int,
    n_robots: int,
    *,
    sensor_range_cells: float | None,
    speed: float,
    coverage_threshold: float = 1.0,
    max_ticks: int | None = None,
) -> int:
    """The ticks a run lasts, on the low side (the trace grows with them).

    A robot that moves ``speed`` cells per tick uncovers at most a strip of about
    ``2 r + 1`` cells across per cell travelled (``r`` the sensor radius), so a team
    needs at least ``coverage_threshold x free_cells / (N (2 r + 1) speed)`` ticks.
    Real runs take longer: they turn, revisit and wait. Measured on complete runs
    (blank 300x300 with 1 robot, office 200x200 with 8, maze 150x150 with 4, intel
    with 8, cityblock 300x300 with 16, warehouse with 32), 2.7 to 14 times that
    bound; the estimate is :data:`TICKS_OVER_BOUND` (2) times it, below every one of
    them. The count is capped by ``max_ticks`` and by the default limit (20 x free
    cells / speed, at least 1000). An unknown sensor radius counts as no trace.
    """
    default_limit = max(1000, math.ceil(20 * free_cells / speed))
    limit = default_limit if max_ticks is None else min(max_ticks, default_limit)
    if sensor_range_cells is None or not math.isfinite(sensor_range_cells):
        return 1
    sweep = n_robots * (2 * max(sensor_range_cells, 1.0) + 1) * speed
    needed = math.ceil(TICKS_OVER_BOUND * coverage_threshold * free_cells / sweep)
    return max(1, min(limit, needed)) + 1  # tick 0 is recorded too


def estimate_run_bytes(
    shape: tuple[int, int],
    n_robots: int,
    *,
    strategy: str = "nearest-frontier",
    sharing: str = "full",
    record_beliefs: bool = False,
    ticks: int = 1,
    linked_share: float = 1.0,
    noisy: bool = False,
) -> MemoryEstimate:
    """Bytes a run of ``n_robots`` on an ``H x W`` grid needs at its peak.

    With ``C = H x W`` cells, ``N`` robots and ``T`` ticks (:func:`estimate_ticks`)::

        total = 50 MB                                     modules, numba kernels
              + C x 14                                    truth, occupancy, stamps
              + C x N x (3 + 4 [recorded beliefs] + 1 [shadow]
                         + 23 [zlot-market] or 8 [kme] + 1 [polygon] + 6 [noisy])
              + C x 12 [polygon sharing]
              + C x max(26, 150)                          a distance field; metrics
              + P x (84 + 520 x linked_share)             links, P = N (N - 1) / 2
              + T x (880 + 54 N + 48 N [N >= 2] + N^2 / 16 + 16 N [noisy])
                                                                per-tick trace

    ``linked_share`` is the share of robot pairs within communication range (1 for
    an unlimited range).

    What each constant counts is in this module's constants (``*_BYTES*``). The
    temporaries of a tick (a distance field) and of the metrics at the end (which
    run while the simulation is still alive) do not overlap, so only the larger
    counts. Not counted: the map file's own pixels while it is read (at most
    :data:`mrexplore.grid.io.MAX_CELLS` cells, freed before the run), messages in
    flight, and the animations of ``--gif`` / ``--mp4``.

    Measured against the peak resident memory (``ru_maxrss``) minus the resident
    memory before the simulation was built (estimate / measured, MB): ``blank``
    3000x3000, 1 robot, 50 ticks: 1544 / 1325; ``blank`` 1000x1000, 4 robots, sensor
    20, complete in 20144 ticks (estimated 12026): 259 / 251; ``intel``, 8 robots,
    sensor 40, complete: 161 / 125; ``warehouse``, 32 robots, complete in 13366
    ticks (estimated 5178): 661 / 835; ``blank`` 100x100, 1000 robots, 2 ticks:
    494 / 467. The trace of a long run is where it falls short (the tick count is
    estimated on the low side); the metrics' temporaries, where it is generous.
    """
    height, width = shape
    cells = int(height) * int(width)
    n = int(n_robots)
    per_robot = ROBOT_BYTES_PER_CELL
    if record_beliefs:
        per_robot += RECORDED_BELIEF_BYTES_PER_CELL
        if sharing not in ("broadcast", "full", "none"):
            per_robot += BELIEF_SHADOW_BYTES_PER_CELL
    per_robot += STRATEGY_ROBOT_BYTES_PER_CELL.get(strategy, 0)
    per_robot += SHARING_ROBOT_BYTES_PER_CELL.get(sharing, 0)
    if noisy:
        per_robot += NOISY_ROBOT_BYTES_PER_CELL
    per_tick = (
        TICK_BYTES
        + (TICK_BYTES_PER_ROBOT + (NOISY_TICK_BYTES_PER_ROBOT if noisy else 0)) * n
        + (TICK_BYTES_PER_ROBOT_DIAMETER * n if n >= 2 else 0)
        + TICK_BITS_PER_ROBOT_PAIR * n * (n - 1) // 16
    )
    pairs = n * (n - 1) // 2
    share = min(max(float(linked_share), 0.0), 1.0)
    return MemoryEstimate(
        map_bytes=cells * (MAP_BYTES_PER_CELL + SHARING_BYTES_PER_CELL.get(sharing, 0)),
        robot_bytes=cells * n * per_robot
        + math.ceil(pairs * (PAIR_BYTES + LINKED_PAIR_BYTES * share)),
        transient_bytes=cells * max(PLAN_BYTES_PER_CELL, METRICS_BYTES_PER_CELL),
        trace_bytes=int(ticks) * per_tick,
        ticks=int(ticks),
    )


def _meminfo_available(path: str = "/proc/meminfo") -> int | None:
    try:
        with open(path, encoding="ascii", errors="replace") as handle:
            for line in handle:
                if line.startswith("MemAvailable:"):
                    words = line.split()
                    scale = 1024 if len(words) > 2 and words[2].lower() == "kb" else 1
                    return int(words[1]) * scale
    except (OSError, ValueError, IndexError):
        return None
    return None


def _read_int(path: str) -> int | None:
    try:
        with open(path, encoding="ascii") as handle:
            text = handle.read().strip()
    except (OSError, UnicodeDecodeError):
        return None
    return int(text) if text.isdigit() else None  # "max" (no limit) is not a number


def _cgroup_headroom(root: str = "/sys/fs/cgroup") -> int | None:
    """Limit minus usage of the cgroup this process is charged to, if it has a limit."""
    for limit_file, usage_file in (
        ("memory.max", "memory.current"),  # cgroup v2
        ("memory/memory.limit_in_bytes", "memory/memory.usage_in_bytes"),  # cgroup v1
    ):
        limit = _read_int(os.path.join(root, limit_file))
        usage = _read_int(os.path.join(root, usage_file))
        if limit is not None and usage is not None and limit < 2**60:  # 2**63-ish: none
            return max(limit - usage, 0)
    return None


def _sysconf_available() -> int | None:
    try:
        pages = os.sysconf("SC_AVPHYS_PAGES")
        page_size = os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):
        return None
    if pages <= 0 or page_size <= 0:
        return None
    return int(pages) * int(page_size)


def available_memory_bytes() -> int | None:
    """Memory this process can still use, in bytes, or ``None`` if unknown.

    On Linux ``MemAvailable`` of ``/proc/meminfo`` (free memory plus the page cache
    and other memory the kernel can reclaim), lowered to the headroom of a cgroup
    memory limit when one is set; elsewhere ``os.sysconf`` free physical pages.
    """
    available = _meminfo_available()
    if available is None:
        available = _sysconf_available()
    headroom = _cgroup_headroom()
    if headroom is not None:
        available = headroom if available is None else min(available, headroom)
    return available


def format_bytes(count: int, other: int | None = None) -> str:
    """``count`` bytes as ``41 GB`` (decimal units); with ``other``, precise enough
    that the two numbers do not print the same."""

    def show(value: int, digits: int) -> str:
        if value >= _GB:
            return f"{value / _GB:.{digits}f} GB"
        return f"{value / 10**6:.{digits}f} MB"

    for digits in (0, 1, 2):
        if other is None or show(count, digits) != show(other, digits):
            return show(count, digits)
    return show(count, 3)


def check_run_memory(
    what: str,
    estimate: MemoryEstimate,
    n_robots: int,
    advice: str,
    available: int | None = None,
) -> None:
    """Refuse a run whose estimate exceeds the available memory.

    ``what`` names the map the way the user asked for it (``--size 10000x10000``);
    ``advice`` says what to change. Nothing is refused when the available memory
    cannot be read.

    Raises:
        ScenarioError: ``estimate.total`` is more than the available memory.
    """
    if available is None:
        available = available_memory_bytes()
    if available is None or estimate.total <= available:
        return
    robots = f"{n_robots} robot" + ("" if n_robots == 1 else "s")
    raise ScenarioError(
        f"{what} with {robots} needs about {format_bytes(estimate.total, available)}, "
        f"more than the {format_bytes(available, estimate.total)} available; {advice}"
    )
