"""The exploration environment as a PettingZoo ``ParallelEnv`` (extra ``rl``).

One :class:`~mrexplore.sim.Simulation` per episode: :meth:`ExplorationEnv.reset`
builds ``Scenario(**scenario, seed=episode_seed)`` and runs tick 0;
:meth:`ExplorationEnv.step` runs one tick with ``Simulation.step(decide=...)``,
whose ``decide`` turns each agent's action into the robot's
:class:`~mrexplore.strategies.base.Decision`. Everything else (moving, sensing,
communication, map sharing, failures, the end of the run, the run record) is the
simulator's own, so an env episode leaves the same ``result.json`` and
``trace.npz`` as ``mrexplore run``.

Observations are built only from what each robot knows (its belief, its inbox,
the teammates it is in contact with). ``state()`` (the global view for
centralised training) and the rewards are computed from the simulator's side,
like the metrics. The spaces, rewards and rules are documented in ``docs/env.md``.
"""

from __future__ import annotations

import dataclasses
import logging
import math
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt

from mrexplore.comm.bytes import BROADCAST, STATUS_BYTES, TARGET_BYTES, fixed_size
from mrexplore.comm.messages import Message
from mrexplore.env.observations import (
    MOVES,
    Candidate,
    CoarseGrid,
    candidate_features,
    coarse_map,
    egocentric_crop,
    frontier_candidates,
    max_path_length,
    move_mask,
    move_target,
)
from mrexplore.errors import MrexploreInputError, ScenarioError
from mrexplore.grid.occupancy import FREE
from mrexplore.planning import distance_field, extract_path
from mrexplore.seeding import make_streams
from mrexplore.sim.engine import Simulation
from mrexplore.sim.record import RunRecord
from mrexplore.sim.scenario import Cell, Scenario, parse_failure, parse_size
from mrexplore.sim.world import build_world
from mrexplore.strategies.base import Decision, RobotView, frontier_at
from mrexplore.strategies.registry import get_strategy

try:
    from gymnasium import spaces
    from pettingzoo.utils.env import ParallelEnv
except ImportError:  # pragma: no cover - only without the rl extra
    HAVE_RL = False
    ParallelEnv = object  # so that this module imports (doctests) without the extra
else:
    HAVE_RL = True

logger = logging.getLogger(__name__)

ACTION_MODES = ("frontier", "move", "decision")
REWARD_MODES = ("team", "individual")

#: Message type of the optional status broadcast (``status_messages=True``).
ENV_STATUS = "env_status"
#: Its size on the wire: header + a status item (robot, row, col, flags) + a
#: target announcement (robot, row, col) from :mod:`mrexplore.comm.bytes`.
ENV_STATUS_SIZE = fixed_size(STATUS_BYTES + TARGET_BYTES)

#: ``idle_ticks`` in ``move`` mode when not given: a robot that made its one-cell
#: step has no goal left, so the simulator's "every robot idle" stall rule would
#: end every ``move`` episode after ``idle_ticks`` ticks.
MOVE_IDLE_TICKS = 2**31 - 1

#: Columns of ``obs["teammates"]``.
TEAMMATE_COLUMNS = ("heard", "in_contact", "row", "col", "goal_row", "goal_col", "age")
#: Columns of ``obs["candidates"]``.
CANDIDATE_COLUMNS = ("valid", "d_row", "d_col", "distance", "size")
#: Channels of :meth:`ExplorationEnv.state`.
STATE_CHANNELS = ("occupied", "known", "robots", "failed")

_INT32_MAX = int(np.iinfo(np.int32).max)

#: Env options and their defaults; every other keyword is a :class:`Scenario` field.
ENV_OPTIONS: dict[str, Any] = {
    "action_mode": "frontier",
    "n_candidates": 8,
    "obs_radius": 16,
    "global_map_size": 16,
    "reward": "team",
    "step_cost": 0.001,
    "invalid_action_penalty": 0.0,
    "status_messages": False,
    "min_cluster_size": 1,
    "render_mode": None,
    "record_beliefs": None,
    "policy_name": None,
}

_SCENARIO_KEYS = frozenset(f.name for f in dataclasses.fields(Scenario))

DeferredDecision = Callable[[RobotView], Decision]
"""A ``decision``-mode action: called with the robot's view at decision time."""


@dataclasses.dataclass(frozen=True)
class EnvStatus:
    """Payload of an ``env_status`` message: where the sender is and where it goes."""

    robot: int
    position: Cell
    goal: Cell | None


def parallel_env(**kwargs: Any) -> ExplorationEnv:
    """A PettingZoo ``ParallelEnv`` over one exploration scenario.

    Keywords are the :class:`~mrexplore.sim.Scenario` fields (``run``'s long
    options with underscores: ``map``, ``size``, ``robots``, ``sensor_range``,
    ``comm_range``, ``max_ticks``, ``fail``, ...) plus the env options of
    :data:`ENV_OPTIONS` (``action_mode`` ``"frontier"`` | ``"move"`` |
    ``"decision"``, ...). ``seed`` seeds the env's own generator of episode seeds
    (see :meth:`ExplorationEnv.reset`). Needs the ``rl`` extra.

    Example (not a doctest, so that the module imports without the extra)::

        env = parallel_env(map="office", size=(32, 32), robots=2, action_mode="move")
        observations, infos = env.reset(seed=1)
        while env.agents:
            actions = {a: env.action_space(a).sample(observations[a]["action_mask"])
                       for a in env.agents}
            observations, rewards, terminated, truncated, infos = env.step(actions)
        env.save("runs/move-random")
    """
    return ExplorationEnv(**kwargs)


class ExplorationEnv(ParallelEnv):
    """Robots exploring one scenario, as PettingZoo agents ``robot_0`` ... ``robot_{N-1}``.

    ``possible_agents`` is fixed; ``agents`` holds the robots still running and
    shrinks when a robot fails (it is ``terminated``) or when the run ends
    (``terminated`` at the coverage threshold, ``truncated`` at ``max_ticks`` or
    when the simulator calls the run ``stalled``).
    """

    metadata: ClassVar[dict[str, Any]] = {
        "name": "mrexplore_v0",
        "render_modes": ["rgb_array"],
        "is_parallelizable": True,
    }

    def __init__(self, **kwargs: Any) -> None:
        if not HAVE_RL:
            raise ImportError(
                "mrexplore.env needs the 'rl' extra: pip install 'mrexplore[rl]' "
                "(pettingzoo and gymnasium)"
            )
        unknown = sorted(set(kwargs) - _SCENARIO_KEYS - set(ENV_OPTIONS))
        if unknown:
            raise ScenarioError(
                f"parallel_env: unknown setting {unknown[0]!r}; scenario keys are "
                f"{', '.join(sorted(_SCENARIO_KEYS))}; env options are {', '.join(ENV_OPTIONS)}"
            )
        options = {**ENV_OPTIONS, **{k: v for k, v in kwargs.items() if k in ENV_OPTIONS}}
        self.options = options
        self.action_mode: str = options["action_mode"]
        self.n_candidates = int(options["n_candidates"])
        self.obs_radius = int(options["obs_radius"])
        self.global_map_size = int(options["global_map_size"] or 0)
        self.reward_mode: str = options["reward"]
        self.step_cost = float(options["step_cost"])
        self.invalid_action_penalty = float(options["invalid_action_penalty"])
        self.status_messages = bool(options["status_messages"])
        self.min_cluster_size = int(options["min_cluster_size"])
        self.render_mode: str | None = options["render_mode"]
        self.record_beliefs: bool | None = options["record_beliefs"]
        self.policy_name: str | None = options["policy_name"]
        self._check_options()

        scenario_kwargs = _scenario_kwargs({k: v for k, v in kwargs.items() if k in _SCENARIO_KEYS})
        base_seed = scenario_kwargs.pop("seed", None)
        if self.action_mode == "move":
            scenario_kwargs.setdefault("idle_ticks", MOVE_IDLE_TICKS)
        self.scenario_kwargs: dict[str, Any] = scenario_kwargs
        probe = Scenario(**scenario_kwargs, seed=0 if base_seed is None else int(base_seed))
        probe.validate()
        if probe.start_delay:
            raise ScenarioError(
                f"start_delay {probe.start_delay}: not in the env (an agent that has not "
                "started would count as terminated, and an agent cannot join later)"
            )
        get_strategy(probe.strategy)  # fail now on an unknown id, not at reset()
        world = build_world(probe, make_streams(probe.seed, probe.robots).starts)
        self.shape: tuple[int, int] = world.grid.shape
        self.n_robots = probe.robots
        self._seed_rng = np.random.default_rng(base_seed)

        self.possible_agents: list[str] = [f"robot_{i}" for i in range(self.n_robots)]
        self.agents: list[str] = []
        self._index = {agent: i for i, agent in enumerate(self.possible_agents)}
        self._others = [
            np.array([j for j in range(self.n_robots) if j != i], dtype=np.intp)
            for i in range(self.n_robots)
        ]
        self.n_actions = {"frontier": self.n_candidates + 1, "move": len(MOVES)}.get(
            self.action_mode, 0
        )
        self.stay_action = self.n_candidates if self.action_mode == "frontier" else 0
        self._coarse = (
            CoarseGrid.for_shape(self.shape, self.global_map_size)
            if self.global_map_size > 0
            else None
        )
        self.observation_spaces = {a: self._build_observation_space() for a in self.possible_agents}
        self.action_spaces = {a: self._build_action_space() for a in self.possible_agents}
        height, width = self.shape
        self.state_space = spaces.Box(0, 1, (len(STATE_CHANNELS), height, width), np.uint8)

        self.simulation: Simulation | None = None
        self.episode = 0
        self.episode_seed: int | None = None
        self._pending: Mapping[str, Any] = {}
        self._invalid = np.zeros(self.n_robots, dtype=bool)
        self._ignored = np.zeros(self.n_robots, dtype=bool)
        self._needs_decision = np.zeros(self.n_robots, dtype=bool)
        self._candidates: list[list[Candidate]] = [[] for _ in range(self.n_robots)]
        self._in_contact = np.zeros((self.n_robots, self.n_robots), dtype=bool)
        self._heard_tick = np.full((self.n_robots, self.n_robots), -1, dtype=np.int64)
        self._heard_position = np.full((self.n_robots, self.n_robots, 2), -1, dtype=np.int32)
        self._heard_goal = np.full((self.n_robots, self.n_robots, 2), -1, dtype=np.int32)

    # ------------------------------------------------------------------ set-up
    def _check_options(self) -> None:
        if self.action_mode not in ACTION_MODES:
            raise ScenarioError(f"action_mode {self.action_mode!r}: choose one of {ACTION_MODES}")
        if self.reward_mode not in REWARD_MODES:
            raise ScenarioError(f"reward {self.reward_mode!r}: choose one of {REWARD_MODES}")
        if self.n_candidates < 1:
            raise ScenarioError(f"n_candidates {self.n_candidates}: must be >= 1")
        if self.obs_radius < 0 or self.global_map_size < 0 or self.min_cluster_size < 1:
            raise ScenarioError(
                "obs_radius and global_map_size must be >= 0, min_cluster_size >= 1 "
                f"(got {self.obs_radius}, {self.global_map_size}, {self.min_cluster_size})"
            )
        if self.render_mode not in (None, "rgb_array"):
            raise ScenarioError(f"render_mode {self.render_mode!r}: only 'rgb_array' or None")
        if self.status_messages and self.action_mode == "decision":
            raise ScenarioError(
                "status_messages: not in action_mode='decision', whose strategies send "
                "their own messages"
            )

    def _build_observation_space(self) -> spaces.Dict:
        height, width = self.shape
        side = 2 * self.obs_radius + 1
        n_others = self.n_robots - 1
        cell_high = np.array([height - 1, width - 1], dtype=np.int32)
        mate_low = np.full((n_others, len(TEAMMATE_COLUMNS)), -1, dtype=np.int32)
        mate_high = np.tile(
            np.array([1, 1, height - 1, width - 1, height - 1, width - 1, _INT32_MAX], np.int32),
            (n_others, 1),
        )
        parts: dict[str, spaces.Space[Any]] = {
            "map": spaces.Box(0, 3, (side, side), np.uint8),
            "position": spaces.Box(np.zeros(2, np.int32), cell_high, (2,), np.int32),
            "goal": spaces.Box(np.full(2, -1, np.int32), cell_high, (2,), np.int32),
            "teammates": spaces.Box(mate_low, mate_high, mate_low.shape, np.int32),
            "needs_decision": spaces.Box(0, 1, (1,), np.int8),
        }
        if self._coarse is not None:
            size = self.global_map_size
            parts["global_map"] = spaces.Box(0.0, 1.0, (2, size, size), np.float32)
        if self.action_mode == "frontier":
            k = self.n_candidates
            low = np.tile(np.array([0, -(height - 1), -(width - 1), 0, 0], np.float32), (k, 1))
            high = np.tile(
                np.array(
                    [1, height - 1, width - 1, max_path_length(self.shape), height * width],
                    np.float32,
                ),
                (k, 1),
            )
            parts["candidates"] = spaces.Box(low, high, low.shape, np.float32)
        if self.n_actions:
            parts["action_mask"] = spaces.Box(0, 1, (self.n_actions,), np.int8)
        return spaces.Dict(parts)

    def _build_action_space(self) -> spaces.Space[Any]:
        if self.action_mode == "decision":
            return DecisionSpace()
        return spaces.Discrete(self.n_actions)

    # ------------------------------------------------------------------ API
    def observation_space(self, agent: str) -> spaces.Space[Any]:
        """The observation space of ``agent`` (the same object every call)."""
        return self.observation_spaces[agent]

    def action_space(self, agent: str) -> spaces.Space[Any]:
        """The action space of ``agent`` (the same object every call)."""
        return self.action_spaces[agent]

    def reset(
        self, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, dict[str, Any]], dict[str, dict[str, Any]]]:
        """Start an episode; return the first observations and infos.

        ``seed`` is the episode's scenario seed (map for generators without
        ``map_seed``, start cells, communication, robots) and re-seeds the env's
        generator of episode seeds; without it the seed is drawn from that
        generator (seeded with the ``seed`` given to the env, or from the
        operating system when none was). ``options["scenario"]`` may override
        scenario keys for this episode (not ``robots`` nor anything that changes
        the map's shape); other option keys are ignored (logged).
        """
        if seed is not None:
            self._seed_rng = np.random.default_rng(seed)
            episode_seed = int(seed)
        else:
            episode_seed = int(self._seed_rng.integers(0, 2**31 - 1))
        scenario_kwargs = dict(self.scenario_kwargs)
        for key, value in (options or {}).items():
            if key == "scenario":
                overrides = _scenario_kwargs(dict(value))
                if "robots" in overrides or "seed" in overrides:
                    raise ScenarioError("reset options: 'robots' and 'seed' cannot change here")
                scenario_kwargs.update(overrides)
            else:
                logger.info("reset: option %r is not used by this environment", key)
        scenario = Scenario(**scenario_kwargs, seed=episode_seed)
        simulation = Simulation(scenario, record_beliefs=self.record_beliefs)
        if simulation.world.grid.shape != self.shape:
            raise ScenarioError(
                f"episode map is {simulation.world.grid.shape} cells, the spaces were built "
                f"for {self.shape}: fix the map's size (size=...) or use one map file"
            )
        simulation.start()
        self.simulation = simulation
        self.episode += 1
        self.episode_seed = episode_seed
        self._invalid[:] = False
        self._ignored[:] = False
        self._heard_tick.fill(-1)
        self._heard_position.fill(-1)
        self._heard_goal.fill(-1)
        self.agents = [] if simulation.status is not None else list(self.possible_agents)
        if not self.agents:
            logger.info("reset: the run ended at tick 0 (%s)", simulation.status)
        self._refresh()
        observations = {agent: self._observe(i) for i, agent in enumerate(self.possible_agents)}
        infos = {
            agent: self._info(i, observations[agent])
            for i, agent in enumerate(self.possible_agents)
        }
        return observations, infos

    def step(
        self, actions: Mapping[str, Any]
    ) -> tuple[
        dict[str, dict[str, Any]],
        dict[str, float],
        dict[str, bool],
        dict[str, bool],
        dict[str, dict[str, Any]],
    ]:
        """Run one tick with these actions (one per live agent; a missing one = no action).

        Actions of agents that are not live are ignored; so are ``frontier``-mode
        actions of agents whose ``needs_decision`` was false (``info`` says
        ``action_ignored``).
        """
        simulation = self._require_simulation()
        if not self.agents:
            raise RuntimeError("the episode is over: call reset() to start another")
        stray = sorted(set(actions) - set(self.possible_agents))
        if stray:
            raise MrexploreInputError(f"step: no agent {stray[0]!r}; agents are {self.agents}")
        live = list(self.agents)
        self._pending = actions
        self._invalid[:] = False
        self._ignored[:] = False
        known_before = simulation.known_explorable
        try:
            status = simulation.step(self._decide)
        finally:
            self._pending = {}
        gained = self._gains(simulation.known_explorable - known_before)
        self._refresh()

        rewards: dict[str, float] = {}
        terminated: dict[str, bool] = {}
        truncated: dict[str, bool] = {}
        for agent in live:
            robot_id = self._index[agent]
            alive = simulation.robots[robot_id].alive
            terminated[agent] = not alive or status == "complete"
            truncated[agent] = alive and status in ("max_ticks", "stalled")
            if alive:
                penalty = self.invalid_action_penalty if self._invalid[robot_id] else 0.0
                rewards[agent] = float(gained[robot_id]) - self.step_cost - penalty
            else:
                rewards[agent] = 0.0
        observations = {agent: self._observe(self._index[agent]) for agent in live}
        infos = {agent: self._info(self._index[agent], observations[agent]) for agent in live}
        self.agents = [a for a in live if not (terminated[a] or truncated[a])]
        return observations, rewards, terminated, truncated, infos

    def state(self) -> npt.NDArray[np.uint8]:
        """The global view: ``(4, H, W)`` uint8 channels ``occupied`` (ground truth),
        ``known`` (the team has sensed the cell), ``robots`` (a live robot stands
        there) and ``failed`` (a failed robot stands there)."""
        simulation = self._require_simulation()
        out = np.zeros(self.state_space.shape, dtype=np.uint8)
        out[0] = simulation.truth
        out[1] = simulation.first_known >= 0
        for robot in simulation.robots:
            out[2 if robot.alive else 3][robot.position] = 1
        return out

    def render(self) -> npt.NDArray[np.uint8] | None:
        """With ``render_mode="rgb_array"``: an ``H x W x 3`` picture (unknown grey,
        known free white, known walls black, unexplored walls dark grey, live robots
        in colour, failed robots red). ``None`` otherwise."""
        if self.render_mode != "rgb_array":
            return None
        simulation = self._require_simulation()
        known = simulation.first_known >= 0
        image = np.full((*self.shape, 3), 170, dtype=np.uint8)
        image[simulation.truth] = 90
        image[known & ~simulation.truth] = 255
        image[known & simulation.truth] = 0
        for robot in simulation.robots:
            image[robot.position] = (30, 110, 220) if robot.alive else (220, 40, 40)
        return image

    def close(self) -> None:
        """Release the episode's simulation."""
        self.simulation = None
        self.agents = []

    # ------------------------------------------------------------------ extras
    def view(self, agent: str) -> RobotView:
        """The :class:`RobotView` of ``agent``'s robot now (end of the last tick).

        The view a strategy gets at the next tick differs only by the messages
        delivered at its start; that is why ``decision``-mode actions may be
        callables, evaluated with the decision-time view (see :class:`StrategyPolicy`).
        """
        return self._require_simulation().view_of(self._index[agent])

    @property
    def tick(self) -> int:
        """The simulator's tick (0 after :meth:`reset`)."""
        return self._require_simulation().tick

    @property
    def coverage(self) -> float:
        """Share of the explorable cells the team knows."""
        simulation = self._require_simulation()
        return simulation.known_explorable / max(simulation.n_explorable, 1)

    def record(self, policy: str | None = None) -> RunRecord:
        """The run record of the episode so far (``Simulation.finish``).

        In ``decision`` mode it is the record of the strategy's run. In the RL
        modes, ``result.json``'s ``strategy`` names the policy (``policy``, the
        ``policy_name`` option, or ``env-<action_mode>``) and ``params`` holds the
        env options. An episode stopped before its end is recorded as ``max_ticks``.
        """
        record = self._require_simulation().finish()
        if self.action_mode == "decision":
            return record
        label = policy or self.policy_name or f"env-{self.action_mode}"
        env_params = {k: v for k, v in self.options.items() if k not in ("render_mode",)}
        return dataclasses.replace(
            record,
            scenario=dataclasses.replace(record.scenario, strategy=label),
            strategy_params=env_params,
        )

    def save(
        self, out_dir: str | Path, *, policy: str | None = None, **kwargs: Any
    ) -> dict[str, Path]:
        """Write the episode's ``result.json``, ``trace.npz`` (and ``final.png``, ...)
        with :func:`mrexplore.save_run`; keywords go to it (``png=False``, ``gif=True``)."""
        from mrexplore.rundir import save_run

        return save_run(self.record(policy), out_dir, **kwargs)

    # ------------------------------------------------------------------ internals
    def _require_simulation(self) -> Simulation:
        if self.simulation is None:
            raise RuntimeError("call reset() first")
        return self.simulation

    def _decide(self, robot_id: int, view: RobotView) -> Decision:
        """The ``decide`` hook of ``Simulation.step``: this agent's action as a Decision."""
        action = self._pending.get(self.possible_agents[robot_id])
        if self.action_mode == "decision":
            return _as_decision(action, view)
        if self.status_messages:
            self._hear(robot_id, view)
        if self.action_mode == "frontier":
            decision = self._frontier_decision(robot_id, view, action)
        else:
            decision = self._move_decision(robot_id, view, action)
        if self.status_messages:
            goal = decision.goal if decision.goal is not None or decision.idle else view.goal
            payload = EnvStatus(robot_id, view.position, goal)
            decision.messages.append(
                Message(ENV_STATUS, robot_id, BROADCAST, ENV_STATUS_SIZE, payload)
            )
        return decision

    def _discrete(self, robot_id: int, action: Any) -> int:
        try:
            value = int(action)
        except (TypeError, ValueError):
            value = -1
        if value != action or not 0 <= value < self.n_actions:
            raise MrexploreInputError(
                f"{self.possible_agents[robot_id]}: action {action!r} is not in "
                f"Discrete({self.n_actions})"
            )
        return value

    def _frontier_decision(self, robot_id: int, view: RobotView, action: Any) -> Decision:
        if not self._needs_decision[robot_id]:
            if action is not None:
                self._ignored[robot_id] = True
            return Decision()
        if action is None:
            return Decision(idle=True)
        choice = self._discrete(robot_id, action)
        if choice == self.stay_action:
            return Decision(idle=True)
        candidates = self._candidates[robot_id]
        if choice >= len(candidates):
            self._invalid[robot_id] = True
            return Decision(idle=True)
        target = candidates[choice].target
        # Plan on the belief the robot has now: the tick's deliveries may have added cells.
        targets = np.zeros(self.shape, dtype=bool)
        targets[target] = True
        dist = distance_field(view.belief == FREE, view.position, targets=targets)
        if not np.isfinite(dist[target]):  # only when a received map contradicted it
            return Decision(idle=True)
        return Decision(goal=target, path=extract_path(dist, target))

    def _move_decision(self, robot_id: int, view: RobotView, action: Any) -> Decision:
        move = 0 if action is None else self._discrete(robot_id, action)
        if move == 0:
            return Decision(idle=True)
        target = move_target(view.belief, view.position, move)
        if target is None:
            self._invalid[robot_id] = True
            return Decision(idle=True)
        path = np.array([view.position, target], dtype=np.int32)
        return Decision(goal=target, path=path)

    def _hear(self, robot_id: int, view: RobotView) -> None:
        """Status messages in the robot's inbox update what it knows of its teammates."""
        for message in view.inbox:
            payload = message.payload
            if message.type != ENV_STATUS or not isinstance(payload, EnvStatus):
                continue
            sender = payload.robot
            if message.tick_sent < self._heard_tick[robot_id, sender]:
                continue  # an older message overtaken by a newer one
            self._heard_tick[robot_id, sender] = message.tick_sent
            self._heard_position[robot_id, sender] = payload.position
            self._heard_goal[robot_id, sender] = payload.goal if payload.goal else (-1, -1)

    def _gains(self, team_gain: int) -> npt.NDArray[np.float64]:
        """Each robot's reward from new explorable cells this tick (before the step cost)."""
        simulation = self._require_simulation()
        n_explorable = max(simulation.n_explorable, 1)
        if self.reward_mode == "team" or team_gain == 0:
            return np.full(self.n_robots, team_gain / n_explorable)
        fresh = (simulation.first_known == simulation.tick) & simulation.world.explorable
        rows, cols = np.nonzero(fresh)
        sensed = np.stack([robot.sensed[rows, cols] for robot in simulation.robots])
        share = sensed / np.maximum(sensed.sum(axis=0), 1)  # cells seen together are split
        gains: npt.NDArray[np.float64] = share.sum(axis=1) / n_explorable
        return gains

    def _refresh(self) -> None:
        """After a tick: contacts, teammate knowledge, candidates and who must decide."""
        simulation = self._require_simulation()
        tick = simulation.tick
        robots = simulation.robots
        self._in_contact[:] = False
        for group in simulation.comm.subnetworks():
            members = np.fromiter(sorted(group), dtype=np.intp)
            self._in_contact[np.ix_(members, members)] = True
        np.fill_diagonal(self._in_contact, False)
        if not self.status_messages:
            # Teammates in the robot's sub-network are heard at once (a free beacon).
            positions = np.array([r.believed for r in robots], dtype=np.int32)
            goals = np.array([r.goal if r.goal else (-1, -1) for r in robots], dtype=np.int32)
            heard_i, heard_j = np.nonzero(self._in_contact)
            self._heard_tick[heard_i, heard_j] = tick
            self._heard_position[heard_i, heard_j] = positions[heard_j]
            self._heard_goal[heard_i, heard_j] = goals[heard_j]
        for robot in robots:
            if not robot.alive:
                self._needs_decision[robot.id] = False
                self._candidates[robot.id] = []
                continue
            if self.action_mode == "frontier":
                goal = robot.goal
                needs = goal is None or not frontier_at(robot.belief, goal[0], goal[1])
                self._needs_decision[robot.id] = needs
                # Listed only when the agent must choose: the costly part of the mode.
                self._candidates[robot.id] = (
                    frontier_candidates(
                        robot.belief,
                        robot.believed,
                        self.n_candidates,
                        min_cluster_size=self.min_cluster_size,
                    )
                    if needs
                    else []
                )
            else:
                self._needs_decision[robot.id] = True

    def _observe(self, robot_id: int) -> dict[str, Any]:
        simulation = self._require_simulation()
        robot = simulation.robots[robot_id]
        belief = robot.belief
        others = self._others[robot_id]
        heard_tick = self._heard_tick[robot_id, others]
        heard = heard_tick >= 0
        mates = np.empty((len(others), len(TEAMMATE_COLUMNS)), dtype=np.int32)
        mates[:, 0] = heard
        mates[:, 1] = self._in_contact[robot_id, others]
        mates[:, 2:4] = self._heard_position[robot_id, others]
        mates[:, 4:6] = self._heard_goal[robot_id, others]
        mates[:, 6] = np.where(heard, simulation.tick - heard_tick, -1)
        obs: dict[str, Any] = {
            "map": egocentric_crop(belief, robot.believed, self.obs_radius),
            "position": np.array(robot.believed, dtype=np.int32),
            "goal": np.array(robot.goal if robot.goal else (-1, -1), dtype=np.int32),
            "teammates": mates,
            "needs_decision": np.array([self._needs_decision[robot_id]], dtype=np.int8),
        }
        if self._coarse is not None:
            obs["global_map"] = coarse_map(belief, self._coarse)
        if self.action_mode == "frontier":
            candidates = self._candidates[robot_id]
            obs["candidates"] = candidate_features(candidates, robot.believed, self.n_candidates)
            mask = np.zeros(self.n_actions, dtype=np.int8)
            mask[: len(candidates)] = 1
            mask[self.stay_action] = 1
            obs["action_mask"] = mask
        elif self.action_mode == "move":
            if robot.alive:
                obs["action_mask"] = move_mask(belief, robot.believed)
            else:
                obs["action_mask"] = np.eye(1, self.n_actions, dtype=np.int8)[0]
        return obs

    def _info(self, robot_id: int, obs: Mapping[str, Any]) -> dict[str, Any]:
        simulation = self._require_simulation()
        robot = simulation.robots[robot_id]
        info: dict[str, Any] = {
            "tick": simulation.tick,
            "alive": robot.alive,
            "needs_decision": bool(self._needs_decision[robot_id]),
            "invalid_action": bool(self._invalid[robot_id]),
            "action_ignored": bool(self._ignored[robot_id]),
            "coverage": simulation.known_explorable / max(simulation.n_explorable, 1),
            "status": simulation.status,
        }
        if "action_mask" in obs:
            info["action_mask"] = obs["action_mask"]
        if self.action_mode == "frontier":
            info["candidate_targets"] = [c.target for c in self._candidates[robot_id]]
        return info


def _scenario_kwargs(given: dict[str, Any]) -> dict[str, Any]:
    """Scenario keywords as ``run`` would parse them (``size="64x64"``, ``fail=["1@20"]``)."""
    out = dict(given)
    if isinstance(out.get("size"), str):
        out["size"] = parse_size(out["size"])
    if "fail" in out:
        out["fail"] = [
            parse_failure(item) if isinstance(item, str) else (int(item[0]), int(item[1]))
            for item in out["fail"]
        ]
    if "comm_range" in out and out["comm_range"] is None:
        out["comm_range"] = math.inf
    return out


def _as_decision(action: Any, view: RobotView) -> Decision:
    """A ``decision``-mode action: a Decision, a callable of the view, or None (keep going)."""
    if action is None:
        return Decision()
    if isinstance(action, Decision):
        return action
    if callable(action):
        decision = action(view)
        if not isinstance(decision, Decision):
            raise MrexploreInputError(
                f"robot {view.robot_id}: the decision callable returned "
                f"{type(decision).__name__}, not a Decision"
            )
        return decision
    raise MrexploreInputError(
        f"robot {view.robot_id}: a decision-mode action is a Decision or a callable "
        f"(RobotView -> Decision), not {type(action).__name__}"
    )


if HAVE_RL:

    class DecisionSpace(spaces.Space[Any]):
        """Action space of ``action_mode="decision"``: a :class:`Decision` or a callable
        ``RobotView -> Decision``. Sampling gives ``Decision()`` (keep going)."""

        def __init__(self) -> None:
            super().__init__(shape=None, dtype=None)

        @property
        def is_np_flattenable(self) -> bool:
            return False

        def sample(self, mask: Any = None, probability: Any = None) -> Decision:
            return Decision()

        def contains(self, x: Any) -> bool:
            return isinstance(x, Decision) or callable(x)

        def __repr__(self) -> str:
            return "DecisionSpace()"

        def __eq__(self, other: object) -> bool:
            return isinstance(other, DecisionSpace)

        def __hash__(self) -> int:
            return hash(DecisionSpace)
