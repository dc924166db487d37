"""The strategy protocol: given what one robot knows, choose a goal and messages.

A strategy object belongs to one robot. Each tick the simulator hands it a
:class:`RobotView` (the robot's own belief, inbox and state; never ground truth)
and gets back a :class:`Decision`. Per-robot state lives on the object; the
simulator builds one object per robot with :func:`make_strategy`.

Re-planning rules are explicit parameters shared by every frontier strategy
(see :data:`REPLAN_PARAMS`): a robot always plans when it has no goal, has
arrived or was blocked; optionally when its goal stopped being a frontier,
when its belief gained any new cell, or every ``replan_every`` ticks.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, ClassVar, TypeVar

import numpy as np
import numpy.typing as npt

from mrexplore import params as _params
from mrexplore.comm.messages import Message
from mrexplore.grid.occupancy import FREE, BeliefGrid
from mrexplore.params import Param  # declared in mrexplore.params; re-exported here
from mrexplore.planning import distance_field, extract_path, frontier_mask

Cell = tuple[int, int]
Path = npt.NDArray[np.int32]
T = TypeVar("T")


class ReplanRules:
    """The re-planning rules every frontier strategy declares (a parameter group).

    A robot always plans when it has no goal, has arrived or was blocked; these add
    the other occasions.
    """

    replan_every = Param(0, "ticks", "also re-plan every k ticks (0 = never)", low=0)
    replan_on_new_info = Param(False, "", "re-plan whenever the belief gained new cells")
    replan_on_target_explored = Param(
        True, "", "re-plan when the goal is no longer a frontier cell"
    )


def declared_params(cls: type) -> dict[str, Param[Any]]:
    """The parameters declared as class attributes of ``cls`` and its bases: its own
    first, in the order of its body, then each base's in method resolution order.

    >>> list(declared_params(ReplanRules))
    ['replan_every', 'replan_on_new_info', 'replan_on_target_explored']
    """
    found: dict[str, Param[Any]] = {}
    for klass in cls.__mro__:
        for name, value in vars(klass).items():
            if isinstance(value, Param) and name not in found:
                found[name] = value
    return found


REPLAN_PARAMS: dict[str, Param[Any]] = declared_params(ReplanRules)
"""The re-planning rules by name (:class:`ReplanRules`)."""


@dataclass(frozen=True)
class RobotView:
    """Everything a strategy may know about its robot at one tick.

    ``belief`` is the robot's own map, read-only. ``subnetwork`` holds the ids of
    the live robots it can currently reach (itself included) and ``links`` the
    direct links ``(a, b)``, ``a < b``, among them: every robot knows the topology
    of its own sub-network. ``comm_latency`` is the ticks a message takes per hop and
    ``comm_range`` the radio range in cells (``inf`` when unlimited): robots know their
    own radio's specification.
    ``rng`` is the robot's own random stream.
    """

    robot_id: int
    n_robots: int
    tick: int
    position: Cell
    belief: BeliefGrid
    goal: Cell | None
    path_remaining: int
    arrived: bool
    blocked: bool
    inbox: tuple[Message, ...]
    subnetwork: frozenset[int]
    sensor_range: float
    speed: float
    rng: np.random.Generator
    new_cells: int
    links: frozenset[tuple[int, int]] = frozenset()
    comm_latency: int = 1
    comm_range: float = math.inf


@dataclass
class Decision:
    """What a strategy wants this tick.

    * ``goal`` and ``path`` set: follow ``path`` (from the robot's cell to ``goal``).
    * ``idle=True``: drop the current goal and stay.
    * neither: keep doing what the robot is doing.
    """

    goal: Cell | None = None
    path: Path | None = None
    idle: bool = False
    messages: list[Message] = field(default_factory=list)

    @property
    def replans(self) -> bool:
        return self.goal is not None or self.idle


class Strategy(ABC):
    """Base class of every coordination strategy.

    Subclasses set ``id``, ``summary`` and ``citation``, declare their parameters as
    class attributes (:class:`Param`), and implement :meth:`decide`.
    """

    id: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    citation: ClassVar[str] = ""
    params: ClassVar[Mapping[str, Param[Any]]] = {}
    """Every parameter by name: the :class:`Param` class attributes of the class and
    its bases (:func:`declared_params`), set when the class is created. A class may
    instead give the mapping itself (``params = {...}``, the older form)."""
    default_sharing: ClassVar[str] = "full"
    """Map-sharing mechanism used when the scenario does not name one."""

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if "params" not in vars(cls):
            cls.params = declared_params(cls)

    def __init__(self, robot_id: int, n_robots: int, **params: Any) -> None:
        self.robot_id = robot_id
        self.n_robots = n_robots
        self.p: dict[str, Any] = resolve_params(type(self), params)

    @abstractmethod
    def decide(self, view: RobotView) -> Decision:
        """Choose what the robot does this tick."""


def resolve_params(cls: type[Strategy], given: Mapping[str, Any]) -> dict[str, Any]:
    """Defaults of ``cls.params`` overridden by ``given``, converted and range-checked."""
    return _params.resolve_params(cls.params, given, owner=f"strategy {cls.id!r}")


def passable(belief: BeliefGrid) -> npt.NDArray[np.bool_]:
    """Cells a robot may plan through: those it knows to be free."""
    return np.asarray(belief == FREE)


class FrontierStrategy(Strategy, ReplanRules):
    """A strategy that sends each robot to a frontier cell of its own belief.

    Handles the re-planning rules; subclasses implement :meth:`choose_goal`.
    """

    def __init__(self, robot_id: int, n_robots: int, **params: Any) -> None:
        super().__init__(robot_id, n_robots, **params)
        self.last_plan_tick = -1
        self.nearest_only = False
        """True if :meth:`choose_goal` only needs the nearest frontier cells' distances
        (the distance field then stops at the first frontier band)."""

    def needs_plan(self, view: RobotView) -> bool:
        """Whether the re-planning rules ask for a new goal at this tick."""
        if view.goal is None or view.arrived or view.blocked:
            return True
        every = self.replan_every
        if every > 0 and view.tick - self.last_plan_tick >= every:
            return True
        if self.replan_on_new_info and view.new_cells > 0:
            return True
        if self.replan_on_target_explored:
            row, col = view.goal
            return not bool(frontier_at(view.belief, row, col))
        return False

    def decide(self, view: RobotView) -> Decision:
        if not self.needs_plan(view):
            return Decision()
        self.last_plan_tick = view.tick
        frontier = frontier_mask(view.belief)
        if not frontier.any():
            return Decision(idle=True)
        targets = frontier
        if self.nearest_only:  # the nearest frontier is the first one settled
            targets = frontier.copy()
            targets[view.position] = False
        dist = distance_field(
            passable(view.belief),
            view.position,
            targets=targets,
            stop_after=1 if self.nearest_only else None,
        )
        goal = self.choose_goal(view, frontier, dist)
        if goal is None:
            return Decision(idle=True)
        return Decision(goal=goal, path=extract_path(dist, goal))

    def choose_goal(
        self, view: RobotView, frontier: npt.NDArray[np.bool_], dist: npt.NDArray[np.float64]
    ) -> Cell | None:
        """Pick a reachable frontier cell, or ``None`` if there is none."""
        raise NotImplementedError


def frontier_at(belief: BeliefGrid, row: int, col: int) -> bool:
    """Whether the cell is a frontier cell: known free with an unknown 4-neighbour."""
    if belief[row, col] != FREE:
        return False
    height, width = belief.shape
    for d_row, d_col in ((-1, 0), (1, 0), (0, -1), (0, 1)):
        r, c = row + d_row, col + d_col
        if 0 <= r < height and 0 <= c < width and belief[r, c] < FREE:
            return True
    return False


def reachable_frontier_cells(
    frontier: npt.NDArray[np.bool_], dist: npt.NDArray[np.float64]
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]:
    """Rows and cols (raster order) of frontier cells with a finite distance, excluding the
    robot's own cell.

    >>> reachable_frontier_cells(np.array([[True, True, True]]), np.array([[0.0, 1.0, np.inf]]))
    (array([0]), array([1]))
    """
    from mrexplore.planning.multi_fields import raster_cells

    index, rows, cols = raster_cells(frontier)  # few cells: index the field there only
    at = dist.reshape(-1)[index]
    keep = np.isfinite(at) & (at > 0)
    return rows[keep], cols[keep]
