"""A scenario: every setting of one run, under the names of ``run``'s long options.

``Scenario`` holds what the user asked for; :func:`mrexplore.sim.world.build_world`
resolves it against a map (loading or generating it, converting metres to cells,
placing the robots). Field names are the CLI's long options with dashes turned
into underscores, and they are the keys of ``result.json``.
"""

from __future__ import annotations

import math
import numbers
import re
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from mrexplore.errors import MapFileError, ScenarioError

Cell = tuple[int, int]

START_MODES = ("together", "separate")
MAX_ROBOTS = 10_000
"""Largest team :meth:`Scenario.check` accepts (every robot holds a belief of the whole
map; the map's free cells bound the team again when the world is built)."""
SENSING_MODES = ("moving", "arrival")
#: What completes a run: the team's union of beliefs reaching ``coverage_threshold``,
#: or one robot's own belief holding every explorable cell.
COMPLETE_WHEN = ("team", "robot")

_LENGTH = re.compile(r"^\s*(-?[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*(m|cells?)?\s*$")


@dataclass
class Scenario:
    """Everything that defines a run. Two runs of equal scenarios are identical.

    Attributes:
        map: a generator id (``office``, ``maze``, ...) or a map file path.
        size: ``(width, height)`` in cells for generators; ``None`` = generator default.
            Refused with a map file (its size is the file's).
        map_seed: seed of the map generator (an integer >= 0); ``None`` = ``seed``.
        cell_size: resample a file map to this many metres per cell (coarser only).
            Refused with a generator (use ``size``).
        robots: team size, 1 to :data:`MAX_ROBOTS`.
        strategy: strategy registry id.
        params: strategy parameters (``--set key=value``).
        sensor_range: sensor radius in cells, or a string such as ``"2.5m"`` in
            metres (needs a map with a resolution).
        speed: cells of path per tick.
        seed: master seed (an integer >= 0, as :class:`numpy.random.SeedSequence` takes);
            the map, start cells, communication and every robot get independent streams
            split from it.
        max_ticks: hard limit on the run's length; ``None`` = 20 x explorable cells /
            speed (at least 1000), enough for every baseline on every bundled map.
        start: ``"together"`` (default: adjacent cells in the largest free region),
            ``"separate"`` (random cells of that region) or a list of ``(row, col)``.
        start_delay: robots start at different ticks: each robot's first tick is drawn
            uniformly from ``0..start_delay`` (the seed's ``start_times`` stream), the
            earliest moved to tick 0; until then a robot does nothing (no sensing,
            decisions or radio) but stands on its cell. 0 (default): all at tick 0.
        sensing: ``"moving"`` (sense every tick) or ``"arrival"`` (only when not
            travelling, Sheng et al. §2.1).
        comm_range: communication range in cells (or ``"20m"``); ``inf`` = unlimited. A
            finite range longer than the map links every pair too, but strategies that
            plan with the range see the number given.
        comm_los: walls on the straight line between two robots block their link.
        bandwidth: bytes each robot may transmit per tick (``inf`` = unlimited).
        latency: ticks a message takes over one hop (at least 1).
        loss: probability that one reception of one hop is lost.
        comm_model: communication model id (``--comm-model``, see ``mrexplore
            comm-models``); the default ``network`` honours the five settings above.
        comm_params: the communication model's own parameters (``--comm key=value``
            with a key other than range, los, bandwidth, latency and loss).
        fail: robots that fail, as ``(robot, tick)`` pairs, at most one per robot.
        fail_at_coverage: robots that fail mid-run, as ``(robot, share)`` pairs
            (``--fail ROBOT@P%``): the robot fails at the first tick after the team's
            knowledge covers ``share`` of the explorable cells; robot ``-1`` (``any``)
            is one robot drawn uniformly from the seed (the same robot for every
            strategy run with that seed).
        failure_rate: probability per tick that each live robot fails.
        sharing: map-sharing mechanism id; ``None`` = the strategy's default (``full``
            for most, ``polygon`` for ``meier-polygon``).
        sharing_params: parameters of the sharing mechanism (``--share key=value``).
        coverage_threshold: share of explorable cells that completes the run.
        complete_when: ``"team"`` (default: the team's union of beliefs reaches
            ``coverage_threshold``) or ``"robot"`` (some live robot's own belief holds
            every explorable cell, whatever the threshold).
        stall_ticks: ticks without any new team knowledge that end the run as
            ``stalled``; ``None`` = 1.5 x explorable cells / speed + 100.
        idle_ticks: ticks with every robot idle and nothing in flight that end the run
            as ``stalled``.
        patience: ticks a robot waits behind another before it detours or gives up.
        sensor_noise: probability that one reading of one cell is wrong (a free cell
            read as occupied, or the reverse); readings are fused into each robot's
            belief as log-odds (:mod:`mrexplore.sim.noise`). 0 (default): perfect
            sensing.
        sensor_params: the sensor model's details (``--sensor key=value``): separate
            error rates per direction, their growth with range, the log-odds clamp
            and thresholds.
        odometry_noise: standard deviation of the position error each step adds to a
            robot's estimate of where it is, as a fraction of the step's length
            (0.05: 5 % of the distance). 0 (default): perfect localisation.
        odometry_params: the odometry model's details (``--odometry key=value``):
            heading drift and the rule that resets the error.
    """

    map: str = "office"
    size: tuple[int, int] | None = None
    map_seed: int | None = None
    cell_size: float | None = None
    robots: int = 4
    strategy: str = "nearest-frontier"
    params: dict[str, Any] = field(default_factory=dict)
    sensor_range: float | str = 8.0
    speed: float = 1.0
    seed: int = 0
    max_ticks: int | None = None
    start: str | list[Cell] = "together"
    start_delay: int = 0
    sensing: str = "moving"
    comm_range: float | str = math.inf
    comm_los: bool = False
    bandwidth: float = math.inf
    latency: int = 1
    loss: float = 0.0
    comm_model: str = "network"
    comm_params: dict[str, Any] = field(default_factory=dict)
    fail: list[tuple[int, int]] = field(default_factory=list)
    fail_at_coverage: list[tuple[int, float]] = field(default_factory=list)
    failure_rate: float = 0.0
    sharing: str | None = None
    sharing_params: dict[str, Any] = field(default_factory=dict)
    coverage_threshold: float = 0.99
    complete_when: str = "team"
    stall_ticks: int | None = None
    idle_ticks: int = 10
    patience: int = 3
    sensor_noise: float = 0.0
    sensor_params: dict[str, Any] = field(default_factory=dict)
    odometry_noise: float = 0.0
    odometry_params: dict[str, Any] = field(default_factory=dict)

    @property
    def noisy(self) -> bool:
        """Whether sensing or localisation is imperfect (a sensor error rate or the
        odometry error above 0); the scenario must be valid."""
        from mrexplore.sim.noise import odometry_model, sensor_model

        return (
            sensor_model(self.sensor_noise, self.sensor_params).active
            or odometry_model(self.odometry_noise, self.odometry_params).active
        )

    def check(self) -> None:
        """Check everything that can be checked before a run: every field (type and
        range), that the map exists, the strategy and its parameters, the sharing
        mechanism and its parameters.

        The simulator, the CLI and sweeps call this, so one place defines what a
        valid scenario is. What needs the map (its file's contents, the start cells,
        ranges in metres, the memory the run needs) is checked when the world is
        built (:func:`mrexplore.sim.world.build_world`).

        Raises:
            ScenarioError: a field is out of range or of the wrong type; the message
                is one line naming the option (``--robots 0: ...``).
            MapFileError: ``map`` names a map file that is missing or not a file.
            UnknownIdError: ``map``, ``strategy`` or ``sharing`` is not a known id.

        >>> Scenario(robots=0).check()
        Traceback (most recent call last):
        ...
        mrexplore.errors.ScenarioError: --robots 0: must be an integer in [1, 10000] (team size)
        """
        self.check_fields()
        self._check_ids()

    def validate(self) -> None:
        """The same as :meth:`check` (its earlier name)."""
        self.check()

    def check_fields(self) -> None:
        """The part of :meth:`check` that looks at the fields alone (no registry, no
        file system): what building a world needs."""
        from mrexplore.grid.generators import GENERATORS

        for option, text in (("--map", self.map), ("--strategy", self.strategy)):
            if not isinstance(text, str) or not text:
                raise ScenarioError(f"{option} {text!r}: expected a name")
        if self.sharing is not None and not isinstance(self.sharing, str):
            raise ScenarioError(f"--sharing {self.sharing!r}: expected a name")
        for option, table in (("--set", self.params), ("--share", self.sharing_params)):
            if not isinstance(table, Mapping):
                raise ScenarioError(f"{option} {table!r}: expected a mapping of KEY=VALUE")
        if not _is_int(self.robots) or not 1 <= self.robots <= MAX_ROBOTS:
            raise ScenarioError(
                f"--robots {self.robots}: must be an integer in [1, {MAX_ROBOTS}] (team size)"
            )
        for option, seed in (("--seed", self.seed), ("--map-seed", self.map_seed)):
            if seed is not None and not (_is_int(seed) and seed >= 0):
                raise ScenarioError(
                    f"{option} {seed}: must be an integer >= 0 (numpy's SeedSequence takes "
                    "no negative seeds)"
                )
        generator = self.map in GENERATORS
        if self.size is not None:
            if not (
                isinstance(self.size, Sequence)
                and len(self.size) == 2
                and all(_is_int(side) for side in self.size)
            ):
                raise ScenarioError(f"--size {self.size!r}: expected WIDTHxHEIGHT, e.g. 200x150")
            if not generator:
                raise ScenarioError(
                    f"--size {self.size[0]}x{self.size[1]}: applies to map generators only; "
                    f"{self.map!r} is a map file, whose size is the file's (--cell-size "
                    "resamples it)"
                )
            width, height = self.size
            if width <= 0 or height <= 0:
                raise ScenarioError(f"--size {width}x{height}: both sides must be positive")
        if self.cell_size is not None:
            if generator:
                raise ScenarioError(
                    f"--cell-size {self.cell_size}: applies to map files only; {self.map!r} "
                    "is a generator, sized in cells with --size"
                )
            if not (_is_real(self.cell_size) and math.isfinite(self.cell_size)) or not (
                self.cell_size > 0
            ):
                raise ScenarioError(
                    f"--cell-size {self.cell_size}: must be a finite number > 0 (metres per cell)"
                )
        if not (_is_real(self.speed) and math.isfinite(self.speed)) or not self.speed > 0:
            raise ScenarioError(f"--speed {self.speed}: must be a positive number of cells/tick")
        if self.max_ticks is not None and not (_is_int(self.max_ticks) and self.max_ticks > 0):
            raise ScenarioError(f"--max-ticks {self.max_ticks}: must be positive (whole ticks)")
        if not _is_real(self.coverage_threshold) or not 0 < self.coverage_threshold <= 1:
            raise ScenarioError(
                f"--coverage-threshold {self.coverage_threshold}: must be in (0, 1]"
            )
        if self.complete_when not in COMPLETE_WHEN:
            raise ScenarioError(
                f"--complete-when {self.complete_when}: choose team (the team's union of "
                "beliefs reaches the coverage threshold) or robot (one robot holds the whole map)"
            )
        if not (_is_int(self.start_delay) and self.start_delay >= 0):
            raise ScenarioError(
                f"--start-delay {self.start_delay}: must be a whole number of ticks >= 0"
            )
        if self.sensing not in SENSING_MODES:
            raise ScenarioError(f"--sensing {self.sensing}: choose one of {SENSING_MODES}")
        self._check_start()
        for name in ("patience", "idle_ticks", "stall_ticks"):
            value = getattr(self, name)
            if value is None and name == "stall_ticks":
                continue  # chosen from the map
            if not (_is_int(value) and value > 0):
                raise ScenarioError(
                    f"--{name.replace('_', '-')} {value}: must be positive (whole ticks)"
                )
        parse_length(self.sensor_range, "--sensor-range")
        if not is_unlimited(self.comm_range):
            parse_length(self.comm_range, "--comm-range")
        if not isinstance(self.comm_los, bool | np.bool_):
            raise ScenarioError(f"--comm-los {self.comm_los!r}: expected true or false")
        if not _is_real(self.bandwidth) or not self.bandwidth > 0:
            raise ScenarioError(f"--bandwidth {self.bandwidth}: must be positive (bytes per tick)")
        if not _is_int(self.latency) or self.latency < 1:
            raise ScenarioError(f"--latency {self.latency}: must be a whole number of ticks >= 1")
        if not _is_real(self.loss) or not 0.0 <= self.loss <= 1.0:
            raise ScenarioError(f"--loss {self.loss}: must be a probability in [0, 1]")
        if not _is_real(self.failure_rate) or not 0.0 <= self.failure_rate <= 1.0:
            raise ScenarioError(f"--failure-rate {self.failure_rate}: must be in [0, 1]")
        self._check_failures()
        from mrexplore.sim.noise import check_noise

        check_noise(self)

    def _check_start(self) -> None:
        start = self.start
        if isinstance(start, str):
            if start not in START_MODES:
                raise ScenarioError(
                    f"--start {start}: choose together, separate, or cells 'R,C;R,C'"
                )
            return
        if not isinstance(start, Sequence) or not all(_is_pair_of_ints(cell) for cell in start):
            raise ScenarioError(
                f"--start {start!r}: expected together, separate or a list of (row, col)"
            )
        # The cells themselves (one per robot, distinct, free, inside the map) are
        # checked with the map (world.choose_starts): in a sweep a bad one makes that
        # run failed rather than the sweep refused.

    def _check_failures(self) -> None:
        if not isinstance(self.fail, Sequence) or not all(
            _is_pair_of_ints(item) for item in self.fail
        ):
            raise ScenarioError(f"--fail {self.fail!r}: expected a list of (robot, tick)")
        failing: dict[int, int] = {}
        for robot, tick in self.fail:
            if not 0 <= robot < self.robots:
                raise ScenarioError(
                    f"--fail {robot}@{tick}: no robot {robot} in a team of {self.robots}"
                )
            if tick < 1:
                raise ScenarioError(f"--fail {robot}@{tick}: the tick must be >= 1")
            if robot in failing:
                raise ScenarioError(
                    f"--fail {robot}@{tick}: robot {robot} already fails at tick "
                    f"{failing[robot]}; a robot fails once (one --fail per robot)"
                )
            failing[robot] = tick
        if not isinstance(self.fail_at_coverage, Sequence) or not all(
            isinstance(item, Sequence)
            and not isinstance(item, str)
            and len(item) == 2
            and _is_int(item[0])
            and _is_real(item[1])
            for item in self.fail_at_coverage
        ):
            raise ScenarioError(
                f"--fail {self.fail_at_coverage!r}: expected a list of (robot, share of cells)"
            )
        for robot, share in self.fail_at_coverage:
            text = format_coverage_failure(robot, share)
            if not -1 <= robot < self.robots:
                raise ScenarioError(f"--fail {text}: no robot {robot} in a team of {self.robots}")
            if not 0.0 < share < 1.0:
                raise ScenarioError(f"--fail {text}: the share must be between 0% and 100%")
            if robot in failing:
                raise ScenarioError(
                    f"--fail {text}: robot {robot} already fails; a robot fails once "
                    "(one --fail per robot)"
                )
            failing[robot] = 0

    def _check_ids(self) -> None:
        """The map exists; the strategy, the comm model, the sharing mechanism and their
        parameters are known (by building one strategy and one sharing mechanism, the
        latter only when it has parameters or an unknown id: building one costs more
        than the other checks)."""
        from mrexplore.comm.models import COMM_MODELS
        from mrexplore.comm.sharing import SHARING, make_sharing
        from mrexplore.sim.world import resolve_map
        from mrexplore.strategies.registry import get_strategy, make_strategy

        map_path = resolve_map(self.map)
        if map_path is not None and not map_path.is_file():
            raise MapFileError(map_path, "not a map file")
        make_strategy(self.strategy, 0, self.robots, dict(self.params))
        if not isinstance(self.comm_model, str) or not self.comm_model:
            raise ScenarioError(f"--comm-model {self.comm_model!r}: expected a name")
        if not isinstance(self.comm_params, Mapping):
            raise ScenarioError(f"--comm {self.comm_params!r}: expected a mapping of KEY=VALUE")
        COMM_MODELS.resolve_params(self.comm_model, self.comm_params, option="--comm")
        sharing = self.sharing or get_strategy(self.strategy).default_sharing
        if self.sharing_params or sharing not in SHARING:
            make_sharing(sharing, **self.sharing_params)

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready dict under the CLI's option names."""
        data = asdict(self)
        if self.size is not None:
            data["size"] = f"{self.size[0]}x{self.size[1]}"
        if not isinstance(self.start, str):
            data["start"] = [list(cell) for cell in self.start]
        data["fail"] = [f"{robot}@{tick}" for robot, tick in self.fail]
        data["fail_at_coverage"] = [
            format_coverage_failure(robot, share) for robot, share in self.fail_at_coverage
        ]
        return data


def _is_int(value: object) -> bool:
    """Whether ``value`` is an integer, numpy's included (``True`` and ``False`` are not)."""
    return isinstance(value, numbers.Integral) and not isinstance(value, bool | np.bool_)


def _is_real(value: object) -> bool:
    """Whether ``value`` is a real number, numpy's included (not ``True`` / ``False``)."""
    return isinstance(value, numbers.Real) and not isinstance(value, bool | np.bool_)


def _is_pair_of_ints(value: object) -> bool:
    return (
        isinstance(value, Sequence)
        and not isinstance(value, str)
        and len(value) == 2
        and all(_is_int(v) for v in value)
    )


def is_unlimited(length: float | str) -> bool:
    """Whether a range (``comm_range``) is ``inf``, that is unlimited.

    >>> is_unlimited(math.inf), is_unlimited(1e9), is_unlimited("20m")
    (True, False, False)
    """
    return isinstance(length, float) and math.isinf(length) and length > 0


def parse_length(value: float | str, option: str) -> tuple[float, bool]:
    """Parse a range: a number of cells, or ``"<x>m"`` for metres.

    Returns ``(amount, in_metres)``. Raises :class:`ScenarioError` for
    non-positive or malformed values.

    >>> parse_length("2.5m", "--sensor-range")
    (2.5, True)
    >>> parse_length(8, "--sensor-range")
    (8.0, False)
    """
    if isinstance(value, str):
        match = _LENGTH.match(value)
        if match is None:
            raise ScenarioError(f"{option} {value!r}: expected cells (8) or metres (2.5m)")
        amount, unit = float(match.group(1)), match.group(2)
        in_metres = unit == "m"
    elif _is_real(value):
        amount, in_metres = float(value), False
    else:
        raise ScenarioError(f"{option} {value!r}: expected cells (8) or metres (2.5m)")
    if not math.isfinite(amount) or amount <= 0:
        raise ScenarioError(f"{option} {value}: must be positive")
    return amount, in_metres


def parse_switch(text: str, option: str) -> bool:
    """Parse an on/off value: ``true``/``false``, ``yes``/``no``, ``on``/``off``, ``1``/``0``.

    >>> parse_switch("Yes", "--comm los")
    True
    """
    lowered = text.strip().lower()
    if lowered in {"1", "true", "yes", "on"}:
        return True
    if lowered in {"0", "false", "no", "off"}:
        return False
    raise ScenarioError(f"{option}={text}: expected true or false (also yes/no, on/off, 1/0)")


def parse_size(text: str) -> tuple[int, int]:
    """Parse ``"WxH"`` (or a single ``"N"`` for a square).

    >>> parse_size("200x100")
    (200, 100)
    """
    parts = text.lower().replace("×", "x").split("x")
    try:
        if len(parts) == 1:
            side = int(parts[0])
            width, height = side, side
        elif len(parts) == 2:
            width, height = int(parts[0]), int(parts[1])
        else:
            raise ValueError(text)
    except ValueError:
        raise ScenarioError(f"--size {text!r}: expected WIDTHxHEIGHT, e.g. 200x150") from None
    if width <= 0 or height <= 0:
        raise ScenarioError(f"--size {text}: both sides must be positive")
    return width, height


def parse_failure(text: str) -> tuple[int, int]:
    """Parse ``"ROBOT@TICK"``.

    >>> parse_failure("3@120")
    (3, 120)
    """
    robot, sep, tick = text.partition("@")
    try:
        if not sep:
            raise ValueError(text)
        return int(robot), int(tick)
    except ValueError:
        raise ScenarioError(
            f"--fail {text!r}: expected ROBOT@TICK or ROBOT@P%, e.g. 2@150 or any@50%"
        ) from None


def is_coverage_failure(text: str) -> bool:
    """Whether ``text`` is the mid-run form ``ROBOT@P%`` of ``--fail``."""
    return text.strip().endswith("%")


def parse_coverage_failure(text: str) -> tuple[int, float]:
    """Parse ``"ROBOT@P%"`` (``ROBOT`` an id or ``any``, which is ``-1``).

    >>> parse_coverage_failure("any@50%"), parse_coverage_failure("2@12.5%")
    ((-1, 0.5), (2, 0.125))
    """
    robot, sep, share = text.strip().partition("@")
    try:
        if not sep or not share.endswith("%"):
            raise ValueError(text)
        return (-1 if robot == "any" else int(robot)), float(share[:-1]) / 100.0
    except ValueError:
        raise ScenarioError(
            f"--fail {text!r}: expected ROBOT@P% (ROBOT an id or 'any'), e.g. any@50%"
        ) from None


def format_coverage_failure(robot: int, share: float) -> str:
    """The ``--fail`` text of a mid-run failure: ``any@50%``, ``2@12.5%``."""
    return f"{'any' if robot == -1 else robot}@{share * 100:g}%"


def parse_cells(text: str) -> list[Cell]:
    """Parse start cells ``"R,C;R,C"``.

    >>> parse_cells("3,4;5,6")
    [(3, 4), (5, 6)]
    """
    cells: list[Cell] = []
    for chunk in text.replace(" ", "").split(";"):
        if not chunk:
            continue
        try:
            row, col = (int(v) for v in chunk.split(","))
        except ValueError:
            raise ScenarioError(f"--start {text!r}: expected 'R,C;R,C;...'") from None
        cells.append((row, col))
    if not cells:
        raise ScenarioError(f"--start {text!r}: no cells given")
    return cells
