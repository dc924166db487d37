"""Two rules for centralised strategies when coordination or motion breaks down.

The papers behind the centralised strategies assume that every message arrives
and that a robot can reach the target it is given. Under message loss, a narrow
bandwidth or failed robots standing in the way neither holds, and a literal
implementation freezes: a robot waits for an answer that never comes, or is sent
again and again to a cell it cannot enter. These rules are *our* additions; each
strategy that uses them states them on its doc page (``docs/strategies/<id>.md``)
beside the paper's text, with their parameters.

:class:`CoordinatorWatch` (parameter ``coordinator_timeout``)
    A robot that has needed a goal for ``coordinator_timeout`` ticks without
    getting one it can follow from its coordinator plans for itself, with the
    strategy's own method restricted to itself (the method run by a team of one).
    It goes on asking, and an answer from the coordinator, whenever it comes,
    replaces its own goal.

:class:`BlockedTargets` (parameter ``block_limit``)
    A target on which the robot was blocked ``block_limit`` times in a row (the
    simulator's wait, then its detour, failed each time) counts as unreachable
    for that robot until it next arrives at a target. When that leaves it with no
    target at all, it forgets these targets and tries them again.
"""

from __future__ import annotations

from typing import Any

from mrexplore.strategies.base import Cell, Decision, Param, RobotView, declared_params


class FallbackRules:
    """The parameters of the two rules (a parameter group), for every strategy that uses them."""

    coordinator_timeout = Param(
        0,
        "ticks",
        "plan alone after waiting this long for a goal; 0 = 3 x request_timeout",
        low=0,
        note=(
            "a robot that waited this long for a goal it can follow plans alone "
            "(ours, see below); 0 = 3 x `request_timeout`"
        ),
    )
    block_limit = Param(
        2,
        "",
        "give up a target after this many blocks in a row; 0 = never",
        low=0,
        note=(
            "a target the robot was blocked on this many times in a row counts as "
            "unreachable for it (ours, see below; 0 = never)"
        ),
    )


FALLBACK_PARAMS: dict[str, Param[Any]] = declared_params(FallbackRules)
"""The parameters of the two rules by name (:class:`FallbackRules`)."""

TIMEOUT_REQUESTS = 3
"""``coordinator_timeout = 0`` means this many request periods (``request_timeout``):
the first request and two re-sends went unanswered."""


def coordinator_timeout(given: int, request_timeout: int) -> int:
    """The wait, in ticks, before a robot plans on its own (``given``; 0 = auto).

    >>> coordinator_timeout(0, 5), coordinator_timeout(7, 5)
    (15, 7)
    """
    return given if given > 0 else TIMEOUT_REQUESTS * request_timeout


class CoordinatorWatch:
    """How long a robot has been waiting for a goal from its coordinator."""

    def __init__(self) -> None:
        self.since = -1
        """Tick the current wait began; -1 when the robot is not waiting."""
        self.fallbacks = 0
        """Goals the robot chose on its own because the coordinator was silent."""

    def wait(self, tick: int) -> None:
        """The robot needs a goal at ``tick`` (starts the clock unless it runs)."""
        if self.since < 0:
            self.since = tick

    def stop(self) -> None:
        """The robot has a goal again."""
        self.since = -1

    def expired(self, tick: int, timeout: int) -> bool:
        """Whether the current wait has lasted ``timeout`` ticks."""
        return self.since >= 0 and tick - self.since >= timeout

    def acted_alone(self, tick: int, found: bool) -> None:
        """Record a plan of the robot's own: a goal found ends the wait; none restarts
        the clock, so the next attempt comes ``timeout`` ticks later."""
        if found:
            self.fallbacks += 1
            self.since = -1
        else:
            self.since = tick


class BlockedTargets:
    """Targets a robot gave up on after being blocked on them ``limit`` times in a row.

    Call :meth:`observe` at the start of every decision and :meth:`decided` with
    the decision returned; :attr:`excluded` holds the targets to leave out.
    ``limit <= 0`` switches the rule off.
    """

    def __init__(self, limit: int) -> None:
        self.limit = limit
        self.excluded: set[Cell] = set()
        self.following: Cell | None = None
        """The target the robot was heading for after its last decision."""
        self.last_blocked: Cell | None = None
        self.in_a_row = 0
        self.given_up = 0
        """Targets given up so far (diagnostics and tests)."""

    def observe(self, view: RobotView) -> None:
        """Update from the view: an arrival clears the list, a block counts."""
        if self.limit <= 0:
            return
        if view.arrived:
            self.excluded.clear()
            self.last_blocked, self.in_a_row = None, 0
        if view.blocked and self.following is not None:
            target = self.following
            self.in_a_row = self.in_a_row + 1 if target == self.last_blocked else 1
            self.last_blocked = target
            if self.in_a_row >= self.limit and target not in self.excluded:
                self.excluded.add(target)
                self.given_up += 1
        self.following = view.goal

    def decided(self, view: RobotView, decision: Decision) -> None:
        """Remember which target the robot follows after ``decision``."""
        if decision.goal is not None:
            self.following = (int(decision.goal[0]), int(decision.goal[1]))
        elif decision.idle:
            self.following = None
        else:
            self.following = view.goal

    def allows(self, goal: Cell) -> bool:
        """Whether the robot may head for ``goal``."""
        return goal not in self.excluded

    def forget(self) -> bool:
        """Drop every excluded target (the robot has nothing else); whether any was."""
        had = bool(self.excluded)
        self.excluded.clear()
        self.last_blocked, self.in_a_row = None, 0
        return had
