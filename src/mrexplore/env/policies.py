"""Policies that drive an :class:`~mrexplore.env.ExplorationEnv`.

* :class:`StrategyPolicy` runs any registered strategy through the env
  (``action_mode="decision"``): one strategy object per robot, exactly as
  :class:`~mrexplore.sim.Simulation` builds them, so the episode's trace is
  identical to ``mrexplore run`` / :func:`mrexplore.sim.simulate` with the same
  scenario and seed.
* :class:`RandomPolicy` picks a uniformly random valid action (``frontier`` or
  ``move`` mode), a baseline for learned policies.

A policy is called with the observations (and infos) of the live agents and
returns the actions dict for :meth:`ExplorationEnv.step`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from mrexplore.errors import ScenarioError
from mrexplore.strategies.base import Strategy
from mrexplore.strategies.registry import make_strategy

if TYPE_CHECKING:
    from mrexplore.env.parallel import DeferredDecision, ExplorationEnv


class StrategyPolicy:
    """A registered strategy choosing every robot's :class:`Decision` through the env.

    The actions it returns are the strategies' ``decide`` methods (deferred
    decisions): the env calls each one inside ``Simulation.step`` with the robot's
    :class:`RobotView` of that tick, after the tick's messages were delivered,
    exactly where ``mrexplore run`` calls the strategy. (Deciding from
    :meth:`ExplorationEnv.view` before ``step`` would miss those messages and
    change coordinating strategies such as ``burgard``.)

    Args:
        env: an env with ``action_mode="decision"``.
        strategy: registry id; default: the env scenario's ``strategy``.
        params: strategy parameters; default: the env scenario's ``params``.

    The strategy objects are rebuilt whenever the env starts a new episode.
    """

    def __init__(
        self,
        env: ExplorationEnv,
        strategy: str | None = None,
        params: Mapping[str, Any] | None = None,
    ) -> None:
        if env.action_mode != "decision":
            raise ScenarioError(
                f"StrategyPolicy needs action_mode='decision', the env has {env.action_mode!r}"
            )
        self.env = env
        self.strategy: str = strategy or env.scenario_kwargs.get("strategy", "nearest-frontier")
        self.params = dict(params if params is not None else env.scenario_kwargs.get("params", {}))
        self._episode = -1
        self.strategies: dict[str, Strategy] = {}

    def _ensure_episode(self) -> None:
        if self._episode == self.env.episode:
            return
        n_robots = self.env.n_robots
        self.strategies = {
            agent: make_strategy(self.strategy, robot_id, n_robots, dict(self.params))
            for robot_id, agent in enumerate(self.env.possible_agents)
        }
        self._episode = self.env.episode

    def __call__(
        self,
        observations: Mapping[str, Any] | None = None,
        infos: Mapping[str, Any] | None = None,
    ) -> dict[str, DeferredDecision]:
        """The actions of the env's live agents: each robot's strategy decides."""
        self._ensure_episode()
        return {agent: self.strategies[agent].decide for agent in self.env.agents}


class RandomPolicy:
    """Uniformly random valid actions from ``obs["action_mask"]``.

    With ``stay=False`` (default) the ``stay`` action is chosen only when it is
    the only valid one, so the robots keep exploring. ``seed`` seeds the
    policy's own generator.
    """

    def __init__(self, env: ExplorationEnv, seed: int | None = None, *, stay: bool = False) -> None:
        if env.action_mode not in ("frontier", "move"):
            raise ScenarioError("RandomPolicy needs action_mode 'frontier' or 'move'")
        self.env = env
        self.stay = stay
        self.rng = np.random.default_rng(seed)

    def __call__(
        self, observations: Mapping[str, Any], infos: Mapping[str, Any] | None = None
    ) -> dict[str, int]:
        actions: dict[str, int] = {}
        stay_action = self.env.stay_action
        for agent in self.env.agents:
            mask = np.asarray(observations[agent]["action_mask"]).astype(bool)
            if not self.stay and mask.sum() > 1:
                mask[stay_action] = False
            actions[agent] = int(self.rng.choice(np.flatnonzero(mask)))
        return actions
