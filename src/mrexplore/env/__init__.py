"""mrexplore as a multi-agent RL environment (PettingZoo ``ParallelEnv``; extra ``rl``).

The same world, sensing, communication model, map sharing, failures and metrics
as ``mrexplore run``, with the robots as agents::

    from mrexplore.env import RandomPolicy, parallel_env

    env = parallel_env(map="office", size=(64, 64), robots=4, comm_range=16,
                       action_mode="frontier", max_ticks=500)
    observations, infos = env.reset(seed=1)
    policy = RandomPolicy(env, seed=1)
    while env.agents:
        observations, rewards, terminated, truncated, infos = env.step(policy(observations))
    env.save("runs/random")          # result.json + trace.npz, like `mrexplore run --out`

Action modes: ``frontier`` (choose one of K frontier clusters of the robot's own
map), ``move`` (8 directions or stay) and ``decision`` (a strategy's
:class:`~mrexplore.strategies.base.Decision`, used by :class:`StrategyPolicy` to
run any registered strategy through the env). Spaces, rewards and what each
agent knows: ``docs/env.md``.

Importing this package needs only numpy; building an env needs the ``rl`` extra
(``pip install 'mrexplore[rl]'``).
"""

from mrexplore.env.observations import (
    MOVE_NAMES,
    MOVES,
    Candidate,
    coarse_map,
    egocentric_crop,
    frontier_candidates,
    move_mask,
)
from mrexplore.env.parallel import (
    ACTION_MODES,
    CANDIDATE_COLUMNS,
    ENV_OPTIONS,
    ENV_STATUS,
    HAVE_RL,
    STATE_CHANNELS,
    TEAMMATE_COLUMNS,
    EnvStatus,
    ExplorationEnv,
    parallel_env,
)
from mrexplore.env.policies import RandomPolicy, StrategyPolicy

__all__ = [
    "ACTION_MODES",
    "CANDIDATE_COLUMNS",
    "ENV_OPTIONS",
    "ENV_STATUS",
    "HAVE_RL",
    "MOVES",
    "MOVE_NAMES",
    "STATE_CHANNELS",
    "TEAMMATE_COLUMNS",
    "Candidate",
    "EnvStatus",
    "ExplorationEnv",
    "RandomPolicy",
    "StrategyPolicy",
    "coarse_map",
    "egocentric_crop",
    "frontier_candidates",
    "move_mask",
    "parallel_env",
]
