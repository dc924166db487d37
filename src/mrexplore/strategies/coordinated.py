"""The shared part of the centralised strategies (``burgard``, ``simmons``, ``kme``).

Each sub-network's coordinator, its lowest live robot id, hands out goals; the
others ask for one when they need it and follow what they are assigned. What every
such method does the same way lives here:

* :class:`CoordinatedStrategy`: who coordinates, the goals the coordinator knows
  the robots hold (:attr:`~CoordinatedStrategy.held_goals`), reading an ``assign``
  from the inbox, sending one (an :class:`~mrexplore.comm.messages.CellItem`,
  ``HEADER_BYTES + TARGET_BYTES``), and following an assigned goal on the robot's own
  belief (:meth:`~CoordinatedStrategy.follow`, by
  :func:`~mrexplore.planning.team_fields.workspace_path`, :func:`~mrexplore.planning.path_to`
  in reused buffers).
* :class:`CoordinatedWithFallback`: the same with the two rules of
  :mod:`mrexplore.strategies.fallback` for lossy links and blocked targets (a robot
  left without an answer plans for a team of one; a target it was blocked on is
  given up), with their parameters (:class:`~mrexplore.strategies.fallback.FallbackRules`).

A method's own part (what the robots report, how the coordinator assigns) stays in
its module.
"""

from __future__ import annotations

from abc import abstractmethod
from typing import Any

from mrexplore.comm.messages import ASSIGN, CellItem, item_message
from mrexplore.planning.team_fields import workspace_path
from mrexplore.strategies.base import Cell, Decision, FrontierStrategy, RobotView, passable
from mrexplore.strategies.fallback import (
    BlockedTargets,
    CoordinatorWatch,
    FallbackRules,
    coordinator_timeout,
)


class CoordinatedStrategy(FrontierStrategy):
    """A frontier strategy whose goals come from the coordinator of the sub-network."""

    def __init__(self, robot_id: int, n_robots: int, **params: Any) -> None:
        super().__init__(robot_id, n_robots, **params)
        self.held_goals: dict[int, Cell] = {}
        """Coordinator: the goal each robot of the sub-network holds, as far as it knows."""
        self.requested_at = -1
        """Tick this robot last asked for a goal; -1 when no request is outstanding."""

    @staticmethod
    def coordinator(view: RobotView) -> int:
        """The robot that coordinates the sub-network: its lowest live id."""
        return min(view.subnetwork)

    def assignment(self, view: RobotView) -> Cell | None:
        """The goal this tick's inbox assigns to this robot (the last, if several)."""
        goal: Cell | None = None
        for message in view.inbox:
            payload = message.payload
            if message.type == ASSIGN and isinstance(payload, CellItem):
                if payload.robot == self.robot_id:
                    goal = payload.cell
        return goal

    def keep_members(self, members: frozenset[int]) -> None:
        """Forget the goals of robots that left the sub-network."""
        self.held_goals = {r: g for r, g in self.held_goals.items() if r in members}

    def allows(self, goal: Cell) -> bool:
        """Whether this robot may head for ``goal`` (every goal, unless a rule says not)."""
        return True

    def follow(self, view: RobotView, goal: Cell) -> Decision:
        """Adopt an assigned goal, planning the path on this robot's own belief; no
        change when it stands there already, may not go there or cannot reach it."""
        if goal == view.position or not self.allows(goal):
            return Decision()
        path = workspace_path(passable(view.belief), view.position, goal)
        if path is None:
            return Decision()
        self.last_plan_tick = view.tick
        return Decision(goal=goal, path=path)

    def hand_out(self, view: RobotView, decision: Decision, robot: int, goal: Cell) -> None:
        """Coordinator: give ``goal`` to ``robot``; its own goal it follows, another
        robot's it sends in an ``assign`` message, added to ``decision``."""
        if robot == self.robot_id:
            own = self.follow(view, goal)
            decision.goal, decision.path = own.goal, own.path
        else:
            assign = CellItem(robot, goal)
            decision.messages.append(item_message(ASSIGN, self.robot_id, robot, assign))


class CoordinatedWithFallback(CoordinatedStrategy, FallbackRules):
    """A coordinated strategy with the rules of :mod:`~mrexplore.strategies.fallback`.

    Its parameters include those of :class:`~mrexplore.strategies.fallback.FallbackRules`;
    subclasses implement :meth:`decide_coordinated` and :meth:`plan_alone`.
    """

    def __init__(self, robot_id: int, n_robots: int, **params: Any) -> None:
        super().__init__(robot_id, n_robots, **params)
        self.watch = CoordinatorWatch()
        self.blocked_targets = BlockedTargets(self.block_limit)

    def decide(self, view: RobotView) -> Decision:
        self.blocked_targets.observe(view)
        decision = self.decide_coordinated(view)
        self.blocked_targets.decided(view, decision)
        return decision

    @abstractmethod
    def decide_coordinated(self, view: RobotView) -> Decision:
        """The method's own decision; the blocked-targets rule is kept around it."""

    @abstractmethod
    def plan_alone(self, view: RobotView) -> Decision:
        """The method run by a team of one: this robot, its own belief, no other goals."""

    def allows(self, goal: Cell) -> bool:
        return self.blocked_targets.allows(goal)

    def fall_back(self, view: RobotView, request_ticks: int) -> Decision | None:
        """A robot that needs a goal: its own plan once it has waited the coordinator
        timeout (``coordinator_timeout``; 0 = 3 request periods of ``request_ticks``),
        or ``None`` while it still waits or found nothing."""
        self.watch.wait(view.tick)
        timeout = coordinator_timeout(self.coordinator_timeout, request_ticks)
        if not self.watch.expired(view.tick, timeout):
            return None
        own = self.plan_alone(view)
        self.watch.acted_alone(view.tick, own.goal is not None)
        if own.goal is None:
            return None
        self.requested_at = -1
        return own
